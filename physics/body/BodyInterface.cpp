#include "physics/body/BodyInterface.h"

#include <string>

namespace strata {

namespace {
Status NotFinite(const char* what) {
  return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " is not finite");
}
}  // namespace

template <class Function>
auto BodyInterface::Read(BodyID id, Function&& function) const
    -> Result<decltype(function(std::declval<const Body&>()))> {
  BodyLockRead lock(*parts_.bodies, id);
  if (!lock.Succeeded()) return lock.status().error();
  return function(lock.body());
}

template <class Function>
Status BodyInterface::Write(BodyID id, Function&& function) {
  BodyLockWrite lock(*parts_.bodies, id);
  if (!lock.Succeeded()) return lock.status();
  return function(lock.body());
}

void BodyInterface::WakeLocked(Body& body) {
  if (!body.in_world() || body.IsStatic()) return;
  body.SetSleepTimerInternal(0.0f);
  if (!body.sleeping()) return;
  body.SetSleepingInternal(false);
  // The rest of its island is woken at the start of the next step (we only hold this body's lock).
  parts_.wakes->Request(body.sleep_island());
}

Result<BodyID> BodyInterface::CreateBody(const BodyCreationSettings& settings) {
  if (settings.object_layer >= parts_.layers->ObjectLayerCount())
    return MakeError(ErrorCode::kInvalidArgument,
                     "object layer " + std::to_string(settings.object_layer) + " is not in the layer setup");
  return parts_.bodies->CreateBody(settings);
}

Result<BodyID> BodyInterface::CreateAndAddBody(const BodyCreationSettings& settings, Activation activation) {
  Result<BodyID> id = CreateBody(settings);
  if (!id) return id;
  if (Status added = AddBody(*id, activation); !added) {
    (void)parts_.bodies->DestroyBody(*id);
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
    BodyLockRead lock(*parts_.bodies, id);
    if (!lock.Succeeded()) return lock.status().error();
    if (lock.body().in_world())
      return MakeError(ErrorCode::kInvalidState,
                       "body " + std::to_string(id.index) + " is already in the world");
    batch.bounds.push_back(parts_.bounds->Of(lock.body(), 0.0f));
    layers.push_back(lock.body().object_layer());
  }
  Result<AddBatch> prepared = parts_.broad_phase->AddBodiesPrepare(ids, batch.bounds, layers);
  if (!prepared) return prepared.error();
  batch.broad_phase = std::move(*prepared);
  return batch;
}

void BodyInterface::UndoAdd(std::span<const BodyID> flagged, std::span<const BodyID> all) {
  for (const BodyID id : flagged) {
    BodyLockWrite lock(*parts_.bodies, id);
    parts_.move_order->Retire(id.index);  // moves made since it was added leave the broad phase alone
    lock.body().SetInWorldInternal(false);
    lock.body().SetSleepingInternal(false);
    parts_.snapshots->Withdraw(id);
  }
  parts_.bodies->CountRemovedFromWorld(flagged.size());
  (void)parts_.broad_phase->RemoveBodies(all);
}

Status BodyInterface::AddBodiesFinalize(BodyAddBatch& batch) {
  // The broad phase first: a step that starts meanwhile skips bodies it finds there but not yet in the world.
  if (Status linked = parts_.broad_phase->AddBodiesFinalize(batch.broad_phase); !linked) return linked;
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
  BodyLockWrite lock(*parts_.bodies, id);
  if (!lock.Succeeded()) return lock.status();
  Body& body = lock.body();
  if (body.in_world())
    return MakeError(ErrorCode::kInvalidState,
                     "body " + std::to_string(id.index) + " was added to the world meanwhile");
  body.SetInWorldInternal(true);
  body.SetSleepingInternal(batch.activation == Activation::kDontActivate && !body.IsStatic());
  body.SetSleepTimerInternal(0.0f);
  if (body.sleeping()) body.SetSleepIslandInternal(parts_.wakes->NewKeys(1));
  parts_.bodies->CountAddedToWorld(1);
  parts_.snapshots->Publish(body);
  // The body may have moved since it was prepared.
  const AABB bounds = parts_.bounds->Of(body, 0.0f);
  if (!(bounds.min == batch.bounds[i].min && bounds.max == batch.bounds[i].max))
    (void)parts_.broad_phase->UpdateBody(id, bounds);
  return Status::Ok();
}

Status BodyInterface::RemoveBody(BodyID id) {
  AABB vacated;
  {
    BodyLockWrite lock(*parts_.bodies, id);
    if (!lock.Succeeded()) return lock.status();
    Body& body = lock.body();
    if (!body.in_world())
      return MakeError(ErrorCode::kInvalidState, "body " + std::to_string(id.index) + " is not in the world");
    // Moves whose broad-phase update is still on its way must not reach the body once it is out.
    parts_.move_order->Retire(id.index);
    if (Status removed = parts_.broad_phase->RemoveBody(id); !removed) {
      // Still in the world: put back the bounds of its latest move, which the retirement may have dropped.
      (void)parts_.broad_phase->UpdateBody(id, parts_.bounds->Of(body, 0.0f));
      return removed;
    }
    vacated = body.world_bounds();
    body.SetInWorldInternal(false);
    body.SetSleepingInternal(false);
    parts_.bodies->CountRemovedFromWorld(1);
    parts_.snapshots->Withdraw(id);
  }
  return ActivateBodiesInBox(vacated);
}

Status BodyInterface::DestroyBody(BodyID id) {
  return parts_.bodies->DestroyBody(id);
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
    const StripedGatePass moving(parts_.bodies->move_gate());
    bool in_world = false;
    AABB bounds;
    std::uint64_t ticket = 0;
    parts_.broad_phase->PrefetchUpdate(id);
    const Status moved = Write(id, [&](Body& body) {
      vacated = body.world_bounds();
      in_world = body.in_world();
      if (position) body.SetPositionInternal(*position);
      if (rotation) body.SetRotationInternal(rotation->normalized());
      body.UpdateWorldBoundsInternal();
      if (in_world) {
        bounds = parts_.bounds->Of(body, 0.0f);
        ticket = parts_.move_order->Issue(id.index);
        parts_.snapshots->Publish(body);
      }
      WakeLocked(body);
      return Status::Ok();
    });
    if (!moved || !in_world) return moved;
    parts_.move_order->Apply(id.index, ticket, [&] { (void)parts_.broad_phase->UpdateBody(id, bounds); });
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
    body.SetLinearVelocityInternal(velocity);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::SetAngularVelocity(BodyID id, const Vec3& velocity) {
  if (!IsFinite(velocity)) return NotFinite("angular velocity");
  return Write(id, [&](Body& body) -> Status {
    if (body.IsStatic()) return MakeError(ErrorCode::kInvalidState, "a static body cannot have a velocity");
    body.SetAngularVelocityInternal(velocity);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddForce(BodyID id, const Vec3& force) {
  if (!IsFinite(force)) return NotFinite("force");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.AddForceInternal(force);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddForce(BodyID id, const Vec3& force, const Vec3& point) {
  if (!IsFinite(force)) return NotFinite("force");
  if (!IsFinite(point)) return NotFinite("point");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.AddForceInternal(force);
    body.AddTorqueInternal((point - body.CenterOfMass()).cross(force));
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddTorque(BodyID id, const Vec3& torque) {
  if (!IsFinite(torque)) return NotFinite("torque");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.AddTorqueInternal(torque);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddImpulse(BodyID id, const Vec3& impulse) {
  if (!IsFinite(impulse)) return NotFinite("impulse");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.SetLinearVelocityInternal(body.linear_velocity() + body.inverse_mass() * impulse);
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::AddImpulse(BodyID id, const Vec3& impulse, const Vec3& point) {
  if (!IsFinite(impulse)) return NotFinite("impulse");
  if (!IsFinite(point)) return NotFinite("point");
  return Write(id, [&](Body& body) {
    if (!body.IsDynamic()) return Status::Ok();
    body.SetLinearVelocityInternal(body.linear_velocity() + body.inverse_mass() * impulse);
    body.SetAngularVelocityInternal(
        body.angular_velocity() + body.InverseInertiaWorld() * (point - body.CenterOfMass()).cross(impulse));
    WakeLocked(body);
    return Status::Ok();
  });
}

Status BodyInterface::ActivateBodiesInBox(const AABB& box) {
  if (!box.IsValid())
    return MakeError(ErrorCode::kInvalidArgument, "activation box must be finite with min <= max");
  std::vector<BodyID> candidates;
  parts_.broad_phase->CollideAABB(box.Expanded(parts_.bounds->speculative_distance()), {}, candidates);
  for (const BodyID candidate : candidates) {
    // Most candidates are awake: peek at the flag without a lock, so only sleepers are locked (and checked
    // again under the lock). Game threads teleporting many objects then rarely meet on a body mutex.
    if (!parts_.bodies->BodyAt(candidate.index).sleeping()) continue;
    BodyLockWrite lock(*parts_.bodies, candidate);
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
