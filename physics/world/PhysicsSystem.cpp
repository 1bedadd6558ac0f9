#include "physics/world/PhysicsSystem.h"

#include <algorithm>
#include <cassert>
#include <shared_mutex>
#include <string>

#include "physics/body/BodyInterface.h"
#include "physics/broadphase/QuadTreeBroadPhase.h"
#include "physics/narrowphase/CollideShapes.h"
#include "physics/world/WorldQuery.h"

namespace strata {

namespace {
constexpr std::uint32_t kNoSolverIndex = 0xffffffffu;
constexpr std::size_t kPairGrain = 64;

// Releases the step's hold on every body lock however the step leaves.
class AllBodiesLock {
 public:
  explicit AllBodiesLock(BodyManager& manager) : manager_(manager) { manager_.LockAll(); }
  ~AllBodiesLock() { manager_.UnlockAll(); }
  AllBodiesLock(const AllBodiesLock&) = delete;
  AllBodiesLock& operator=(const AllBodiesLock&) = delete;

 private:
  BodyManager& manager_;
};

// Makes body writers wait from construction to destruction (see BodyManager::BeginStep).
class StepScope {
 public:
  explicit StepScope(BodyManager& manager) : manager_(manager) { manager_.BeginStep(); }
  ~StepScope() { manager_.EndStep(); }
  StepScope(const StepScope&) = delete;
  StepScope& operator=(const StepScope&) = delete;

 private:
  BodyManager& manager_;
};

// Runs `function(begin, end, out)` over chunks of [0, count) in parallel and concatenates the chunk
// outputs in index order, so the result does not depend on how the job system split the range.
template <class T, class Function>
void ParallelCollect(JobSystem& jobs, std::size_t count, std::size_t grain, std::vector<T>& out,
                     Function&& function) {
  struct Chunk {
    std::size_t begin;
    std::vector<T> items;
  };
  std::mutex chunks_mutex;
  std::vector<Chunk> chunks;
  jobs.ParallelFor(count, grain, [&](std::size_t begin, std::size_t end) {
    Chunk chunk{begin, {}};
    function(begin, end, chunk.items);
    std::lock_guard lock(chunks_mutex);
    chunks.push_back(std::move(chunk));
  });
  std::sort(chunks.begin(), chunks.end(), [](const Chunk& a, const Chunk& b) { return a.begin < b.begin; });
  for (Chunk& chunk : chunks) out.insert(out.end(), chunk.items.begin(), chunk.items.end());
}
}  // namespace

Status PhysicsSystemConfig::Validate() const {
  if (max_bodies == 0 || max_bodies > (1u << 30))
    return MakeError(ErrorCode::kInvalidArgument, "max_bodies must be in [1, 2^30]");
  if (body_mutex_count == 0 || body_mutex_count > 4096)
    return MakeError(ErrorCode::kInvalidArgument, "body_mutex_count must be in [1, 4096]");
  if (thread_count < 0) return MakeError(ErrorCode::kInvalidArgument, "thread_count must be >= 0");
  if (!broad_phase && layers && layers->BroadPhaseLayerCount() > QuadTreeBroadPhase::kMaxBroadPhaseLayers)
    return MakeError(ErrorCode::kInvalidArgument,
                     "the quad-tree broad phase supports at most " +
                         std::to_string(QuadTreeBroadPhase::kMaxBroadPhaseLayers) + " broad-phase layers");
  if (layers && layers->BroadPhaseLayerCount() == 0)
    return MakeError(ErrorCode::kInvalidArgument, "the layer setup needs at least one broad-phase layer");
  return Status::Ok();
}

Result<std::unique_ptr<PhysicsSystem>> PhysicsSystem::Create(const PhysicsSystemConfig& config,
                                                             const PhysicsSettings& settings) {
  if (Status valid = config.Validate(); !valid) return valid.error();
  if (Status valid = settings.Validate(); !valid) return valid.error();
  return std::unique_ptr<PhysicsSystem>(new PhysicsSystem(config, settings));
}

PhysicsSystem::PhysicsSystem(const PhysicsSystemConfig& config, const PhysicsSettings& settings)
    : settings_(settings),
      layers_(config.layers ? config.layers : std::make_shared<DefaultLayerSetup>()),
      jobs_(config.job_system ? config.job_system
                              : std::shared_ptr<JobSystem>(MakeDefaultJobSystem(config.thread_count))),
      body_manager_(config.max_bodies, config.body_mutex_count),
      broad_phase_(config.broad_phase ? config.broad_phase
                                      : std::make_shared<QuadTreeBroadPhase>(config.max_bodies, layers_)),
      body_interface_(std::make_unique<BodyInterface>(*this)),
      query_(std::make_unique<WorldQuery>(*this)),
      speculative_distance_(settings.speculative_distance),
      active_flags_(config.max_bodies, 0),
      solver_index_(config.max_bodies, kNoSolverIndex) {}

PhysicsSystem::~PhysicsSystem() = default;

Status PhysicsSystem::SetSettings(const PhysicsSettings& settings) {
  if (Status valid = settings.Validate(); !valid) return valid;
  std::lock_guard step(step_mutex_);
  StepScope no_writers(body_manager_);
  AllBodiesLock bodies(body_manager_);
  settings_ = settings;
  speculative_distance_.store(settings.speculative_distance, std::memory_order_relaxed);
  return Status::Ok();
}

std::vector<BodyID> PhysicsSystem::BodiesInWorld() const {
  std::vector<BodyID> ids;
  const std::uint32_t limit = body_manager_.slot_limit();
  for (std::uint32_t index = 0; index < limit; ++index) {
    std::shared_lock lock(body_manager_.MutexFor(index));
    const Body& body = body_manager_.BodyAt(index);
    if (body.in_world()) ids.push_back(body.id());
  }
  return ids;
}

void PhysicsSystem::RequestWake(std::uint32_t island_key) {
  std::lock_guard lock(wake_mutex_);
  pending_wakes_.push_back(island_key);
}

float PhysicsSystem::MotionBound(const Body& body, float dt) const {
  if (!body.IsActive()) return 0.0f;
  const float radius = body.shape()->LocalBounds().HalfExtents().norm() + body.center_of_mass_local().norm();
  return (body.linear_velocity().norm() + body.angular_velocity().norm() * radius) * dt;
}

AABB PhysicsSystem::BroadPhaseBounds(const Body& body, float dt) const {
  AABB bounds = body.world_bounds().Expanded(settings_.speculative_distance);
  if (!body.IsActive()) return bounds;
  // Sweep over the coming step so speculative contacts are found before bodies touch.
  const float step = dt > 0.0f ? dt : last_dt_.load(std::memory_order_relaxed);
  const Vec3 travel = body.linear_velocity() * step;
  const float turn = body.angular_velocity().norm() * step * body.shape()->LocalBounds().HalfExtents().norm();
  AABB swept = bounds;
  swept.min += travel;
  swept.max += travel;
  bounds.Encapsulate(swept);
  return bounds.Expanded(turn);
}

Status PhysicsSystem::Step(float dt) {
  if (!IsFinite(dt) || dt <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument,
                     "step dt must be a positive finite number, got " + std::to_string(dt));
  std::lock_guard step(step_mutex_);
  StepScope no_writers(body_manager_);
  stats_ = {};
  {
    AllBodiesLock bodies(body_manager_);
    last_dt_.store(dt, std::memory_order_relaxed);
    WakePendingIslands();
    CollectActiveBodies();
    ApplyForces(dt);
  }
  // Between the two windows only this step changes anything, so bodies are read here without locks while
  // queries and other readers carry on. The broad phase swaps in a rebuilt generation; pinned readers keep
  // the old one.
  broad_phase_->Update();
  FindPairs(dt);
  RunNarrowPhase();
  WakeTouchedSleepers();
  Solve(dt);
  {
    AllBodiesLock bodies(body_manager_);
    WriteBackSolvedBodies();
    UpdateBroadPhaseBounds(dt);
    UpdateSleeping(dt);
  }
  return Status::Ok();
}

void PhysicsSystem::WakePendingIslands() {
  std::vector<std::uint32_t> keys;
  {
    std::lock_guard lock(wake_mutex_);
    keys.swap(pending_wakes_);
  }
  if (keys.empty()) return;
  std::sort(keys.begin(), keys.end());
  const std::uint32_t limit = body_manager_.slot_limit();
  for (std::uint32_t index = 0; index < limit; ++index) {
    Body& body = body_manager_.BodyAt(index);
    if (body.sleeping_ && std::binary_search(keys.begin(), keys.end(), body.sleep_island_)) {
      body.sleeping_ = false;
      body.sleep_timer_ = 0.0f;
    }
  }
}

void PhysicsSystem::CollectActiveBodies() {
  for (const BodyID id : active_) active_flags_[id.index] = 0;
  active_.clear();
  // Index order: the same bodies give the same order, whatever order threads added them in.
  const std::uint32_t limit = body_manager_.slot_limit();
  for (std::uint32_t index = 0; index < limit; ++index) {
    const Body& body = body_manager_.BodyAt(index);
    if (!body.IsActive()) continue;
    active_.push_back(body.id());
    active_flags_[index] = 1;
  }
  stats_.active_bodies = active_.size();
}

void PhysicsSystem::ApplyForces(float dt) {
  for (const BodyID id : active_) {
    Body& body = body_manager_.BodyAt(id.index);
    if (!body.IsDynamic()) continue;
    body.linear_velocity_ +=
        dt * (settings_.gravity * body.gravity_factor_ + body.inverse_mass_ * body.force_);
    body.angular_velocity_ += dt * (body.InverseInertiaWorld() * body.torque_);
    body.force_.setZero();
    body.torque_.setZero();
    body.linear_velocity_ *= std::max(0.0f, 1.0f - body.linear_damping_ * dt);
    body.angular_velocity_ *= std::max(0.0f, 1.0f - body.angular_damping_ * dt);
    if (body.linear_velocity_.norm() > body.max_linear_velocity_)
      body.linear_velocity_ *= body.max_linear_velocity_ / body.linear_velocity_.norm();
    if (body.angular_velocity_.norm() > body.max_angular_velocity_)
      body.angular_velocity_ *= body.max_angular_velocity_ / body.angular_velocity_.norm();
  }
}

void PhysicsSystem::FindPairs(float dt) {
  pairs_.clear();
  ParallelCollect(*jobs_, active_.size(), kPairGrain, pairs_,
                  [&](std::size_t begin, std::size_t end, auto& out) {
                    broad_phase_->FindPairs(std::span<const BodyID>(active_).subspan(begin, end - begin),
                                            active_flags_, *layers_, out);
                  });
  // Keep only pairs with a dynamic body (kinematic vs static or kinematic makes no contact), with the
  // convex shape first so the narrow phase always sees mesh as B.
  std::vector<BodyPair> kept;
  kept.reserve(pairs_.size());
  for (BodyPair pair : pairs_) {
    const Body& a = body_manager_.BodyAt(pair.a.index);
    const Body& b = body_manager_.BodyAt(pair.b.index);
    // The broad phase may briefly hold a body another thread is adding or removing.
    if (!b.in_world() || b.id() != pair.b) continue;
    if (!a.IsDynamic() && !b.IsDynamic()) continue;
    if (!a.shape()->IsConvex()) std::swap(pair.a, pair.b);
    kept.push_back(pair);
  }
  std::sort(kept.begin(), kept.end());
  pairs_.swap(kept);
  pair_max_separation_.resize(pairs_.size());
  for (std::size_t i = 0; i < pairs_.size(); ++i)
    pair_max_separation_[i] = settings_.speculative_distance +
                              MotionBound(body_manager_.BodyAt(pairs_[i].a.index), dt) +
                              MotionBound(body_manager_.BodyAt(pairs_[i].b.index), dt);
  stats_.pairs = pairs_.size();
}

void PhysicsSystem::RunNarrowPhase() {
  manifolds_.clear();
  ParallelCollect(
      *jobs_, pairs_.size(), kPairGrain, manifolds_, [&](std::size_t begin, std::size_t end, auto& out) {
        for (std::size_t i = begin; i < end; ++i) {
          const Body& a = body_manager_.BodyAt(pairs_[i].a.index);
          const Body& b = body_manager_.BodyAt(pairs_[i].b.index);
          ContactManifold prototype;
          prototype.body_a = a.id();
          prototype.body_b = b.id();
          CollideShapes(*a.shape(), a.pose(), *b.shape(), b.pose(), pair_max_separation_[i], prototype, out);
        }
      });
  stats_.manifolds = manifolds_.size();
  for (const ContactManifold& manifold : manifolds_) stats_.contact_points += manifold.count;
}

void PhysicsSystem::WakeTouchedSleepers() {
  std::vector<std::uint32_t> keys;
  for (const ContactManifold& manifold : manifolds_) {
    const Body& a = body_manager_.BodyAt(manifold.body_a.index);
    const Body& b = body_manager_.BodyAt(manifold.body_b.index);
    if (manifold.MinSeparation() > settings_.speculative_distance) continue;
    // A sleeping body stays put (infinite mass) this step and wakes, with its island, for the next one.
    if (a.sleeping_ && b.IsActive()) keys.push_back(a.sleep_island_);
    if (b.sleeping_ && a.IsActive()) keys.push_back(b.sleep_island_);
  }
  if (keys.empty()) return;
  std::lock_guard lock(wake_mutex_);
  pending_wakes_.insert(pending_wakes_.end(), keys.begin(), keys.end());
}

void PhysicsSystem::Solve(float dt) {
  // Solver bodies: the active ones first (they are integrated), then static/asleep ones that contacts touch.
  for (const std::uint32_t index : solver_body_index_) solver_index_[index] = kNoSolverIndex;
  solver_bodies_.clear();
  solver_body_index_.clear();
  auto add_solver_body = [&](const Body& body) {
    const std::uint32_t index = body.id().index;
    if (solver_index_[index] != kNoSolverIndex) return solver_index_[index];
    SolverBody solver;
    solver.center_of_mass = body.CenterOfMass();
    solver.rotation = body.rotation();
    if (body.IsActive()) {
      solver.linear_velocity = body.linear_velocity();
      solver.angular_velocity = body.angular_velocity();
      if (body.IsDynamic()) {
        solver.inverse_mass = body.inverse_mass();
        solver.inverse_inertia = body.InverseInertiaWorld();
        solver.gravity_factor = body.gravity_factor();
      }
    }
    solver_index_[index] = static_cast<std::uint32_t>(solver_bodies_.size());
    solver_bodies_.push_back(solver);
    solver_body_index_.push_back(index);
    return solver_index_[index];
  };
  for (const BodyID id : active_) add_solver_body(body_manager_.BodyAt(id.index));
  std::vector<std::uint32_t> body_a(manifolds_.size()), body_b(manifolds_.size());
  std::vector<ContactMaterial> materials(manifolds_.size());
  for (std::size_t m = 0; m < manifolds_.size(); ++m) {
    const Body& a = body_manager_.BodyAt(manifolds_[m].body_a.index);
    const Body& b = body_manager_.BodyAt(manifolds_[m].body_b.index);
    body_a[m] = add_solver_body(a);
    body_b[m] = add_solver_body(b);
    materials[m] = {std::sqrt(a.friction() * b.friction()), std::max(a.restitution(), b.restitution())};
  }

  contact_cache_.BeginStep();
  contact_solver_.Setup(manifolds_, body_a, body_b, materials, solver_bodies_, contact_cache_, dt, settings_);
  contact_solver_.WarmStart(solver_bodies_);
  for (int i = 0; i < settings_.velocity_iterations; ++i) contact_solver_.SolveVelocities(solver_bodies_, i);
  contact_solver_.StoreImpulses(contact_cache_);

  // Symplectic Euler: positions move with the velocities the solver just produced.
  for (std::size_t i = 0; i < active_.size(); ++i) {
    SolverBody& body = solver_bodies_[i];
    body.center_of_mass += body.linear_velocity * dt;
    const Vec3 turn = body.angular_velocity * dt;
    const Quat delta(0.0f, 0.5f * turn.x(), 0.5f * turn.y(), 0.5f * turn.z());
    body.rotation.coeffs() += (delta * body.rotation).coeffs();
    body.rotation.normalize();
  }
  contact_solver_.ApplyBounceCorrection(solver_bodies_);
  float penetration = 0.0f;
  for (int i = 0; i < settings_.position_iterations; ++i)
    penetration = contact_solver_.SolvePositions(solver_bodies_, settings_);
  stats_.max_penetration = -penetration;
}

void PhysicsSystem::WriteBackSolvedBodies() {
  for (std::size_t i = 0; i < active_.size(); ++i) {
    Body& body = body_manager_.BodyAt(active_[i].index);
    const SolverBody& solved = solver_bodies_[i];
    body.linear_velocity_ = solved.linear_velocity;
    body.angular_velocity_ = solved.angular_velocity;
    body.pose_.rotation = solved.rotation;
    body.pose_.position = solved.center_of_mass - solved.rotation * body.center_of_mass_local_;
    body.UpdateWorldBounds();
  }
}

void PhysicsSystem::UpdateBroadPhaseBounds(float dt) {
  for (const BodyID id : active_) {
    const Status updated = broad_phase_->UpdateBody(id, BroadPhaseBounds(body_manager_.BodyAt(id.index), dt));
    assert(updated.ok());
    (void)updated;
  }
}

void PhysicsSystem::UpdateSleeping(float dt) {
  // Islands over the dynamic active bodies (solver indices [0, active count)).
  const auto active_count = static_cast<std::uint32_t>(active_.size());
  islands_.Reset(active_count);
  for (const ContactManifold& manifold : manifolds_) {
    const std::uint32_t a = solver_index_[manifold.body_a.index];
    const std::uint32_t b = solver_index_[manifold.body_b.index];
    if (a < active_count && b < active_count && body_manager_.BodyAt(manifold.body_a.index).IsDynamic() &&
        body_manager_.BodyAt(manifold.body_b.index).IsDynamic())
      islands_.Link(a, b);
  }
  std::vector<std::uint8_t> island_awake(active_count, 0);
  for (std::uint32_t i = 0; i < active_count; ++i) {
    Body& body = body_manager_.BodyAt(active_[i].index);
    const bool resting = body.linear_velocity_.norm() < settings_.sleep_linear_velocity &&
                         body.angular_velocity_.norm() < settings_.sleep_angular_velocity;
    body.sleep_timer_ = resting ? body.sleep_timer_ + dt : 0.0f;
    const bool may_sleep =
        settings_.allow_sleeping && body.allow_sleeping_ && body.sleep_timer_ >= settings_.time_before_sleep;
    if (!may_sleep) island_awake[islands_.Find(i)] = 1;
  }
  std::vector<std::uint32_t> island_key(active_count, 0);
  for (std::uint32_t i = 0; i < active_count; ++i) {
    const std::uint32_t root = islands_.Find(i);
    if (root == i) ++stats_.islands;
    if (island_awake[root]) continue;
    if (island_key[root] == 0) island_key[root] = next_island_key_++;
    Body& body = body_manager_.BodyAt(active_[i].index);
    body.sleeping_ = true;
    body.sleep_island_ = island_key[root];
    body.linear_velocity_.setZero();
    body.angular_velocity_.setZero();
    (void)broad_phase_->UpdateBody(body.id(), BroadPhaseBounds(body, dt));
    ++stats_.bodies_put_to_sleep;
  }
}

}  // namespace strata
