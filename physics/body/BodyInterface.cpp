#include "physics/body/BodyInterface.h"

#include <string>

#include "physics/world/PhysicsSystem.h"

namespace strata {

namespace {
Status NotFinite(const char* what) {
  return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " is not finite");
}
}  // namespace

template <class Function>
auto BodyInterface::Read(BodyID id, Function&& function) const
    -> Result<decltype(function(std::declval<const Body&>()))> {
  BodyLockRead lock(system_.body_manager_, id);
  if (!lock.Succeeded()) return lock.status().error();
  return function(lock.body());
}

template <class Function>
Status BodyInterface::Write(BodyID id, Function&& function) {
  BodyLockWrite lock(system_.body_manager_, id);
  if (!lock.Succeeded()) return lock.status();
  return function(lock.body());
}

void BodyInterface::WakeLocked(Body& body) {
  if (!body.in_world_ || body.IsStatic()) return;
  body.sleep_timer_ = 0.0f;
  if (!body.sleeping_) return;
  body.sleeping_ = false;
  // The rest of its island is woken at the start of the next step (we only hold this body's lock).
  system_.RequestWake(body.sleep_island_);
}

Result<BodyID> BodyInterface::CreateBody(const BodyCreationSettings& settings) {
  if (settings.object_layer >= system_.layers_->ObjectLayerCount())
    return MakeError(ErrorCode::kInvalidArgument,
                     "object layer " + std::to_string(settings.object_layer) + " is not in the layer setup");
  return system_.body_manager_.CreateBody(settings);
}

Result<BodyID> BodyInterface::CreateAndAddBody(const BodyCreationSettings& settings, Activation activation) {
  Result<BodyID> id = CreateBody(settings);
  if (!id) return id;
  if (Status added = AddBody(*id, activation); !added) {
    (void)system_.body_manager_.DestroyBody(*id);
    return added.error();
  }
  return id;
}

Status BodyInterface::AddBody(BodyID id, Activation activation) {
  return AddBodies({&id, 1}, activation);
}

Status BodyInterface::AddBodies(std::span<const BodyID> ids, Activation activation) {
  Result<BodyAddBatch> batch = AddBodiesPrepare(ids, activation);
  if (!batch) return batch.error();
  return AddBodiesFinalize(*batch);
}

Result<BodyAddBatch> BodyInterface::AddBodiesPrepare(std::span<const BodyID> ids, Activation activation) {
  BodyAddBatch batch;
  batch.activation = activation;
  batch.ids.assign(ids.begin(), ids.end());
  std::vector<ObjectLayer> layers;
  for (const BodyID id : ids) {
    BodyLockRead lock(system_.body_manager_, id);
    if (!lock.Succeeded()) return lock.status().error();
    if (lock.body().in_world())
      return MakeError(ErrorCode::kInvalidState,
                       "body " + std::to_string(id.index) + " is already in the world");
    batch.bounds.push_back(system_.BroadPhaseBounds(lock.body(), 0.0f));
    layers.push_back(lock.body().object_layer());
  }
  Result<AddBatch> prepared = system_.broad_phase_->AddBodiesPrepare(ids, batch.bounds, layers);
  if (!prepared) return prepared.error();
  batch.broad_phase = std::move(*prepared);
  return batch;
}

void BodyInterface::UndoAdd(std::span<const BodyID> flagged, std::span<const BodyID> all) {
  for (const BodyID id : flagged) {
    BodyLockWrite lock(system_.body_manager_, id);
    system_.move_order_.Retire(id.index);  // moves made since it was added leave the broad phase alone
    lock.body().in_world_ = false;
    lock.body().sleeping_ = false;
    system_.body_snapshots_.Withdraw(id);
  }
  system_.in_world_count_.fetch_sub(flagged.size(), std::memory_order_relaxed);
  (void)system_.broad_phase_->RemoveBodies(all);
}

Status BodyInterface::AddBodiesFinalize(BodyAddBatch& batch) {
  // The broad phase first: a step that starts meanwhile skips bodies it finds there but not yet in the world.
  if (Status linked = system_.broad_phase_->AddBodiesFinalize(batch.broad_phase); !linked) return linked;
  for (std::size_t i = 0; i < batch.ids.size(); ++i) {
    if (Status flagged = MarkAdded(batch, i); !flagged) {
      UndoAdd(std::span<const BodyID>(batch.ids).first(i), batch.ids);
      return flagged;
    }
  }
  return Status::Ok();
}

Status BodyInterface::MarkAdded(const BodyAddBatch& batch, std::size_t i) {
  const BodyID id = batch.ids[i];
  BodyLockWrite lock(system_.body_manager_, id);
  if (!lock.Succeeded()) return lock.status();
  Body& body = lock.body();
  if (body.in_world())
    return MakeError(ErrorCode::kInvalidState,
                     "body " + std::to_string(id.index) + " was added to the world meanwhile");
  body.in_world_ = true;
  body.sleeping_ = batch.activation == Activation::kDontActivate && !body.IsStatic();
  body.sleep_timer_ = 0.0f;
  if (body.sleeping_) body.sleep_island_ = system_.next_island_key_.fetch_add(1, std::memory_order_relaxed);
  system_.in_world_count_.fetch_add(1, std::memory_order_relaxed);
  system_.body_snapshots_.Publish(body);
  // The body may have moved since it was prepared.
  const AABB bounds = system_.BroadPhaseBounds(body, 0.0f);
  if (!(bounds.min == batch.bounds[i].min && bounds.max == batch.bounds[i].max))
    (void)system_.broad_phase_->UpdateBody(id, bounds);
  return Status::Ok();
}

Status BodyInterface::RemoveBody(BodyID id) {
  AABB vacated;
  {
    BodyLockWrite lock(system_.body_manager_, id);
    if (!lock.Succeeded()) return lock.status();
    Body& body = lock.body();
    if (!body.in_world())
      return MakeError(ErrorCode::kInvalidState, "body " + std::to_string(id.index) + " is not in the world");
    // Moves whose broad-phase update is still on its way must not reach the body once it is out.
    system_.move_order_.Retire(id.index);
    if (Status removed = system_.broad_phase_->RemoveBody(id); !removed) {
      // Still in the world: put back the bounds of its latest move, which the retirement may have dropped.
      (void)system_.broad_phase_->UpdateBody(id, system_.BroadPhaseBounds(body, 0.0f));
      return removed;
    }
    vacated = body.world_bounds();
    body.in_world_ = false;
    body.sleeping_ = false;
    system_.in_world_count_.fetch_sub(1, std::memory_order_relaxed);
    system_.body_snapshots_.Withdraw(id);
  }
  return ActivateBodiesInBox(vacated);
}

Status BodyInterface::DestroyBody(BodyID id) {
  return system_.body_manager_.DestroyBody(id);
}

Status BodyInterface::RemoveAndDestroyBody(BodyID id) {
  Result<bool> in_world = IsInWorld(id);
  if (!in_world) return in_world.status();
  if (*in_world)
    if (Status removed = RemoveBody(id); !removed) return removed;
  return DestroyBody(id);
}

bool BodyInterface::IsValid(BodyID id) const {
  return Read(id, [](const Body&) { return true; }).ok();
}
Result<bool> BodyInterface::IsInWorld(BodyID id) const {
  return Read(id, [](const Body& b) { return b.in_world(); });
}
Result<bool> BodyInterface::IsActive(BodyID id) const {
  return Read(id, [](const Body& b) { return b.IsActive(); });
}
Result<Vec3> BodyInterface::GetPosition(BodyID id) const {
  return Read(id, [](const Body& b) { return b.position(); });
}
Result<Vec3d> BodyInterface::GetPrecisePosition(BodyID id) const {
  return Read(id, [](const Body& b) { return b.precise_position(); });
}
Result<Quat> BodyInterface::GetRotation(BodyID id) const {
  return Read(id, [](const Body& b) { return b.rotation(); });
}
Result<Vec3> BodyInterface::GetCenterOfMass(BodyID id) const {
  return Read(id, [](const Body& b) { return b.CenterOfMass(); });
}
Result<Vec3> BodyInterface::GetLinearVelocity(BodyID id) const {
  return Read(id, [](const Body& b) { return b.linear_velocity(); });
}
Result<Vec3> BodyInterface::GetAngularVelocity(BodyID id) const {
  return Read(id, [](const Body& b) { return b.angular_velocity(); });
}
Result<AABB> BodyInterface::GetWorldBounds(BodyID id) const {
  return Read(id, [](const Body& b) { return b.world_bounds(); });
}
Result<ShapeRef> BodyInterface::GetShape(BodyID id) const {
  return Read(id, [](const Body& b) { return b.shape(); });
}
Result<MotionType> BodyInterface::GetMotionType(BodyID id) const {
  return Read(id, [](const Body& b) { return b.motion_type(); });
}

Result<bool> BodyInterface::IsSensor(BodyID id) const {
  return Read(id, [](const Body& b) { return b.is_sensor(); });
}

Status BodyInterface::Teleport(BodyID id, const std::optional<Vec3>& position,
                               const std::optional<Quat>& rotation) {
  AABB vacated;
  {
    // The body's lock is held for the pose alone (what other threads wait on); the broad phase gets the new
    // bounds after it is released. The ticket keeps an earlier move of the same body, slower to get there,
    // from overwriting them, and the gate keeps a step from starting before they are in.
    const StripedGatePass moving(system_.body_manager_.move_gate());
    bool in_world = false;
    AABB bounds;
    std::uint64_t ticket = 0;
    system_.broad_phase_->PrefetchUpdate(id);
    const Status moved = Write(id, [&](Body& body) {
      vacated = body.world_bounds();
      in_world = body.in_world();
      if (position) {
        body.pose_.position = *position;
        body.position_remainder_.setZero();
      }
      if (rotation) body.pose_.rotation = rotation->normalized();
      body.UpdateWorldBounds();
      if (in_world) {
        bounds = system_.BroadPhaseBounds(body, 0.0f);
        ticket = system_.move_order_.Issue(id.index);
        system_.body_snapshots_.Publish(body);
      }
      WakeLocked(body);
      return Status::Ok();
    });
    if (!moved || !in_world) return moved;
    system_.move_order_.Apply(id.index, ticket, [&] { (void)system_.broad_phase_->UpdateBody(id, bounds); });
  }
  return ActivateBodiesInBox(vacated);
}

Status BodyInterface::SetPosition(BodyID id, const Vec3& position) {
  if (!IsFinite(position)) return NotFinite("position");
  return Teleport(id, position, std::nullopt);
}

Status BodyInterface::SetRotation(BodyID id, const Quat& rotation) {
  if (!IsFinite(rotation) || rotation.norm() < 1e-6f) return NotFinite("rotation");
  return Teleport(id, std::nullopt, rotation);
}

Status BodyInterface::SetPositionAndRotation(BodyID id, const Vec3& position, const Quat& rotation) {
  if (!IsFinite(position)) return NotFinite("position");
  if (!IsFinite(rotation) || rotation.norm() < 1e-6f) return NotFinite("rotation");
  return Teleport(id, position, rotation);
}

Status BodyInterface::SetLinearVelocity(BodyID id, const Vec3& velocity) {
  if (!IsFinite(velocity)) return NotFinite("linear velocity");
  return Write(id, [&](Body& body) -> Status {
    if (body.IsStatic()) return MakeError(ErrorCode::kInvalidState, "a static body cannot have a velocity");
    body.linear_velocity_ = velocity;
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::SetAngularVelocity(BodyID id, const Vec3& velocity) {
  if (!IsFinite(velocity)) return NotFinite("angular velocity");
  return Write(id, [&](Body& body) -> Status {
    if (body.IsStatic()) return MakeError(ErrorCode::kInvalidState, "a static body cannot have a velocity");
    body.angular_velocity_ = velocity;
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddForce(BodyID id, const Vec3& force) {
  if (!IsFinite(force)) return NotFinite("force");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.force_ += force;
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddForce(BodyID id, const Vec3& force, const Vec3& point) {
  if (!IsFinite(force)) return NotFinite("force");
  if (!IsFinite(point)) return NotFinite("point");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.force_ += force;
    body.torque_ += (point - body.CenterOfMass()).cross(force);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddTorque(BodyID id, const Vec3& torque) {
  if (!IsFinite(torque)) return NotFinite("torque");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.torque_ += torque;
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddImpulse(BodyID id, const Vec3& impulse) {
  if (!IsFinite(impulse)) return NotFinite("impulse");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.linear_velocity_ += body.inverse_mass_ * impulse;
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddImpulse(BodyID id, const Vec3& impulse, const Vec3& point) {
  if (!IsFinite(impulse)) return NotFinite("impulse");
  if (!IsFinite(point)) return NotFinite("point");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.linear_velocity_ += body.inverse_mass_ * impulse;
    body.angular_velocity_ += body.InverseInertiaWorld() * (point - body.CenterOfMass()).cross(impulse);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::ActivateBodiesInBox(const AABB& box) {
  if (!box.IsValid())
    return MakeError(ErrorCode::kInvalidArgument, "activation box must be finite with min <= max");
  std::vector<BodyID> candidates;
  system_.broad_phase_->CollideAABB(
      box.Expanded(system_.speculative_distance_.load(std::memory_order_relaxed)), {}, candidates);
  for (const BodyID candidate : candidates) {
    // Most candidates are awake: peek at the flag without a lock, so only sleepers are locked (and checked
    // again under the lock). Game threads teleporting many objects then rarely meet on a body mutex.
    if (!system_.body_manager_.BodyAt(candidate.index).sleeping()) continue;
    BodyLockWrite lock(system_.body_manager_, candidate);
    if (lock.Succeeded() && lock.body().sleeping()) WakeLocked(lock.body());
  }
  return Status::Ok();
}

Status BodyInterface::ActivateBody(BodyID id) {
  return Write(id, [&](Body& body) -> Status {
    if (!body.in_world()) return MakeError(ErrorCode::kInvalidState, "body is not in the world");
    WakeLocked(body);
    return Status::Ok();
  });
}

}  // namespace strata
