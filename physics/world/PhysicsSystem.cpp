#include "physics/world/PhysicsSystem.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cstdio>
#include <shared_mutex>
#include <string>

#include "physics/broadphase/QuadTreeBroadPhase.h"
#include "physics/core/ForEachChunk.h"
#include "physics/narrowphase/ShapeCast.h"

namespace strata {

namespace {
constexpr std::uint32_t kBodyChunk = 64;
constexpr std::uint32_t kIslandChunk = 16;
constexpr std::uint32_t kCastChunk = 8;
// A linear-cast body is swept when it moved more than this fraction of its smallest half extent (Jolt casts
// past 0.75 of its inner radius); slower bodies cannot skip anything their contacts did not see.
constexpr float kLinearCastThreshold = 0.75f;
// Casts stop this far before touching, so the next step's contacts start from a small gap.
constexpr float kCastTolerance = 1e-3f;

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

// Stage trampolines: the job graph calls plain functions with the system as context.
template <void (PhysicsSystem::*Stage)()>
void SerialStage(void* system, std::uint32_t, std::uint32_t) {
  (static_cast<PhysicsSystem*>(system)->*Stage)();
}
template <void (PhysicsSystem::*Stage)(std::uint32_t, std::uint32_t)>
void ParallelStage(void* system, std::uint32_t job, std::uint32_t width) {
  (static_cast<PhysicsSystem*>(system)->*Stage)(job, width);
}

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

Status PhysicsSystemConfig::Validate() const {
  if (max_bodies == 0 || max_bodies > (1u << 30))
    return MakeError(ErrorCode::kInvalidArgument, "max_bodies must be in [1, 2^30]");
  if (body_mutex_count == 0 || body_mutex_count > 4096)
    return MakeError(ErrorCode::kInvalidArgument, "body_mutex_count must be in [1, 4096]");
  if (thread_count < 0 || thread_count > kMaxThreads)
    return MakeError(ErrorCode::kInvalidArgument,
                     "thread_count must be in [0, " + std::to_string(kMaxThreads) + "] (0 = all cores)");
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
      constraints_(body_manager_),
      body_snapshots_(config.max_bodies),
      move_order_(config.max_bodies),
      broad_phase_(config.broad_phase ? config.broad_phase
                                      : std::make_shared<QuadTreeBroadPhase>(config.max_bodies, layers_)),
      bounds_(settings.speculative_distance),
      body_interface_(std::make_unique<BodyInterface>(
          BodyInterface::Parts{&body_manager_, broad_phase_.get(), &move_order_, &body_snapshots_,
                               layers_.get(), &wakes_, &bounds_})),
      query_(std::make_unique<WorldQuery>(body_manager_, *broad_phase_)),
      active_flags_(config.max_bodies, 0),
      solver_index_(config.max_bodies, 0),
      pair_cache_(config.max_bodies, step_blocks_),
      collisions_(step_blocks_),
      constraint_solver_(step_blocks_, {&contact_kind_, &joint_kind_}) {
  job_count_ = static_cast<std::uint32_t>(std::max(1, jobs_->ThreadCount()));
  constexpr std::size_t kBudgetPerBody = 16;
  max_body_pairs_ = config.max_body_pairs ? config.max_body_pairs : kBudgetPerBody * config.max_bodies;
  max_contact_constraints_ =
      config.max_contact_constraints ? config.max_contact_constraints : kBudgetPerBody * config.max_bodies;
  warning_ = config.warning;
  finish_counters_.resize(job_count_);
  cast_scratch_.resize(job_count_);
  BuildStepGraphs();
  reported_.resize(job_count_);
  for (JobGraph* graph : {&start_graph_, &middle_graph_, &end_graph_, &events_graph_})
    graph->set_timed(config.stage_timings);
}

PhysicsSystem::~PhysicsSystem() = default;

void PhysicsSystem::WarnAboutBudgets() {
  const auto warn = [&](bool& warned, const std::string& what, std::size_t budget, const char* setting) {
    if (warned) return;
    warned = true;
    const std::string message = "strata physics: warning: " + what + " past the budget of " +
                                std::to_string(budget) + " were dropped this step (" + setting +
                                "; later steps over it are counted in StepStats, not reported)";
    if (warning_) {
      warning_(message);
    } else {
      std::fprintf(stderr, "%s\n", message.c_str());
    }
  };
  if (stats_.pairs_dropped > 0 || stats_.bodies_skipped > 0)
    warn(warned_pairs_,
         std::to_string(stats_.pairs_dropped) + " body pairs" +
             (stats_.bodies_skipped
                  ? " (and the pairs of " + std::to_string(stats_.bodies_skipped) + " bodies, not looked for)"
                  : std::string()),
         max_body_pairs_, "PhysicsSystemConfig::max_body_pairs");
  if (stats_.constraints_dropped > 0)
    warn(warned_constraints_, std::to_string(stats_.constraints_dropped) + " contact constraints",
         max_contact_constraints_, "PhysicsSystemConfig::max_contact_constraints");
}

void PhysicsSystem::BuildStepGraphs() {
  const JobGraph::StageId prepare =
      start_graph_.Add("prepare", &SerialStage<&PhysicsSystem::PrepareStep>, this);
  const JobGraph::StageId forces =
      start_graph_.Add("apply forces", &ParallelStage<&PhysicsSystem::ApplyForces>, this, {prepare});
  start_graph_.SetWidth(forces, job_count_);

  // The rebuild publishes a new broad-phase generation while the collision jobs query the pinned old one.
  const JobGraph::StageId rebuild =
      middle_graph_.Add("broad-phase update", &SerialStage<&PhysicsSystem::UpdateBroadPhase>, this);
  const JobGraph::StageId collide =
      middle_graph_.Add("find collisions", &ParallelStage<&PhysicsSystem::FindCollisions>, this);
  middle_graph_.SetWidth(collide, job_count_);
  const JobGraph::StageId finalize = middle_graph_.Add(
      "finalize islands", &SerialStage<&PhysicsSystem::FinalizeIslands>, this, {rebuild, collide});
  prepare_islands_stage_ =
      middle_graph_.Add("prepare islands", &ParallelStage<&PhysicsSystem::PrepareIslands>, this, {finalize});
  middle_graph_.SetWidth(prepare_islands_stage_, job_count_);  // narrowed to the group count every step
  const JobGraph::StageId solve = middle_graph_.Add(
      "solve islands", &ParallelStage<&PhysicsSystem::SolveIslands>, this, {prepare_islands_stage_});
  middle_graph_.SetWidth(solve, job_count_);
  // One empty job when no body asks for linear casts (the width is set per step).
  linear_casts_stage_ =
      middle_graph_.Add("linear casts", &ParallelStage<&PhysicsSystem::LinearCasts>, this, {solve});

  const JobGraph::StageId finish =
      end_graph_.Add("finish islands", &ParallelStage<&PhysicsSystem::FinishIslands>, this);
  end_graph_.SetWidth(finish, job_count_);
  // Beside the write-back (it reads no pose): whether a body of a pair that touched is still in the world
  // is safe to read only while the step holds every body lock.
  end_graph_.Add("contact events", &SerialStage<&PhysicsSystem::ReportContacts>, this);

  // Sensors test the bodies where the step left them.
  sensors_stage_ = events_graph_.Add("sensors", &ParallelStage<&PhysicsSystem::TestSensors>, this);
}

Status PhysicsSystem::SetSettings(const PhysicsSettings& settings) {
  if (Status valid = settings.Validate(); !valid) return valid;
  std::lock_guard step(step_mutex_);
  StepScope no_writers(body_manager_);
  AllBodiesLock bodies(body_manager_);
  settings_ = settings;
  bounds_.set_speculative_distance(settings.speculative_distance);
  return Status::Ok();
}

void PhysicsSystem::CopyEvents(StepEvents& out) const {
  std::lock_guard lock(events_mutex_);
  out = events_;
}

void PhysicsSystem::SetContactValidator(ContactValidator validator) {
  std::lock_guard step(step_mutex_);
  validator_ = std::move(validator);
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

Status PhysicsSystem::Step(float dt) {
  if (!IsFinite(dt) || dt <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument,
                     "step dt must be a positive finite number, got " + std::to_string(dt));
  std::lock_guard step(step_mutex_);
  // Joint calls wait for the step's end; taken before any body lock (ConstraintManager::Add reads bodies
  // before it takes this mutex).
  std::lock_guard joints(constraints_.mutex());
  StepScope no_writers(body_manager_);
  // An untimed world reads no clock at all (see PhysicsSystemConfig::stage_timings).
  const bool timed = start_graph_.timed();
  const auto start = timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  stats_ = {};
  profile_.stage_count = 0;
  step_dt_ = dt;
  if (settings_.sleep_rule == SleepRule::kPointMovement)
    sleep_spheres_.resize(body_manager_.capacity());
  else
    std::vector<SleepSpheres>().swap(sleep_spheres_);
  auto run = [&](JobGraph& graph) {
    if (!graph.timed()) {
      graph.Run(*jobs_);
      return;
    }
    const double offset = MillisecondsSince(start);
    graph.Run(*jobs_);
    for (std::size_t s = 0; s < graph.stage_count() && profile_.stage_count < StepProfile::kMaxStages; ++s) {
      StageTiming timing = graph.timing(static_cast<JobGraph::StageId>(s));
      timing.start_ms += offset;
      timing.end_ms += offset;
      profile_.stages[profile_.stage_count++] = timing;
    }
  };
  {
    AllBodiesLock bodies(body_manager_);
    run(start_graph_);
  }
  // Between the two windows only this step changes anything, so bodies are read here without locks while
  // queries and other readers carry on. The broad phase swaps in a rebuilt generation; pinned readers keep
  // the old one.
  run(middle_graph_);
  {
    AllBodiesLock bodies(body_manager_);
    next_chunk_.store(0, std::memory_order_relaxed);
    run(end_graph_);
  }
  if (!sensors_.idle()) run(events_graph_);
  FinishStep();
  profile_.total_ms = timed ? MillisecondsSince(start) : 0.0;
  return Status::Ok();
}

void PhysicsSystem::PrepareStep() {
  // Bounds were swept over the last step's dt (or 1/60 s before the first step): a longer step sweeps them
  // again, so nothing it reaches is missed.
  const bool longer_step = bounds_.BeginStep(step_dt_);
  // Islands woken through the API since the last step (the API holds one body's lock, so it queued keys).
  wakes_.Take(wake_keys_);
  WakeConstrainedBodies();
  std::sort(wake_keys_.begin(), wake_keys_.end());
  for (const BodyID id : active_) {
    active_flags_[id.index] = 0;
    solver_index_[id.index] = 0;
  }
  active_.clear();
  linear_cast_bodies_.clear();
  sensor_bodies_.clear();
  next_events_.clear();
  // Index order: the same bodies give the same order, whatever order threads added them in. Only the slots
  // LockAll guarded: a later one is outside the world and may be filled in by its creator right now.
  const std::uint32_t limit = body_manager_.locked_slot_limit();
  for (std::uint32_t index = 0; index < limit; ++index) {
    Body& body = body_manager_.BodyAt(index);
    if (body.sleeping() && !wake_keys_.empty() &&
        std::binary_search(wake_keys_.begin(), wake_keys_.end(), body.sleep_island()))
      WakeUp(body);
    if (body.is_sensor() && body.in_world()) sensor_bodies_.push_back(body.id());
    if (!body.IsActive()) continue;
    if (body.IsDynamic() && body.motion_quality() == MotionQuality::kLinearCast && !body.is_sensor())
      linear_cast_bodies_.push_back(static_cast<std::uint32_t>(active_.size()));
    active_.push_back(body.id());
    active_flags_[index] = 1;
    solver_index_[index] = static_cast<std::uint32_t>(active_.size());
    if (longer_step) {
      const Status updated = broad_phase_->UpdateBody(body.id(), bounds_.Of(body, step_dt_));
      assert(updated.ok());
      (void)updated;
    }
  }
  wake_keys_.clear();
  const auto active_count = static_cast<std::uint32_t>(active_.size());
  stats_.active_bodies = active_count;
  constraint_solver_.ResetBodies(active_count);
  islands_.Reset(active_count);
  BindConstraints();
  // Enough blocks for any split of last step's work over the jobs: its bytes (the cache holds two steps'),
  // a margin for what blocks leave unused at their ends, and one partly filled block per arena.
  const std::size_t step_bytes =
      2 * pair_cache_.arena_bytes() + collisions_.arena_bytes() + constraint_solver_.arena_bytes();
  step_blocks_.EnsureBlocks(step_bytes * 5 / 4 / step_blocks_.block_bytes() + 4 * job_count_ + 1);
  pair_cache_.BeginStep(job_count_);
  CollisionFinder::Input input;
  input.bodies = &body_manager_;
  input.broad_phase = broad_phase_.get();
  input.layers = layers_.get();
  input.settings = &settings_;
  input.dt = step_dt_;
  input.active = active_;
  input.active_flags = active_flags_;
  input.solver_index = solver_index_;
  input.solver_bodies = constraint_solver_.bodies().data();
  input.velocity_steps = constraint_solver_.velocity_steps().data();
  input.solver_poses = constraint_solver_.poses().data();
  input.solver_rotations = constraint_solver_.start_rotations().data();
  input.cache = &pair_cache_;
  input.islands = &islands_;
  input.jointed_pairs = &jointed_pairs_;
  input.validator = validator_ ? &validator_ : nullptr;
  input.max_pairs = max_body_pairs_;
  input.max_constraints = max_contact_constraints_;
  collisions_.BeginStep(input, job_count_);
  SensorTracker::Input sensor_input;
  sensor_input.bodies = &body_manager_;
  sensor_input.broad_phase = broad_phase_.get();
  sensor_input.layers = layers_.get();
  sensor_input.active_flags = active_flags_;
  sensors_.BeginStep(sensor_input, sensor_bodies_, job_count_);
  const auto sensor_count = static_cast<std::uint32_t>(sensor_bodies_.size());
  events_graph_.SetWidth(sensors_stage_,
                         std::min(job_count_, (sensor_count + SensorTracker::kSensorsPerBatch - 1) /
                                                  SensorTracker::kSensorsPerBatch));
  next_chunk_.store(0, std::memory_order_relaxed);
}

void PhysicsSystem::WakeConstrainedBodies() {
  // A joint between an awake body and a sleeping one (added so, or the awake one was moved) wakes the
  // sleeping one's island; a joint's islands otherwise sleep and wake together.
  constraints_.ForEachActive([&](Constraint& joint) {
    const BodyID ids[2] = {joint.body_a(), joint.body_b()};
    const Body* sides[2] = {nullptr, nullptr};
    for (int k = 0; k < 2; ++k) {
      if (ids[k].IsInvalid()) continue;
      const Body& body = body_manager_.BodyAt(ids[k].index);
      if (ids[k].index < body_manager_.locked_slot_limit() && body.in_world() && body.id() == ids[k])
        sides[k] = &body;
    }
    for (int k = 0; k < 2; ++k) {
      const Body* sleeper = sides[k];
      const Body* other = sides[1 - k];
      if (sleeper != nullptr && other != nullptr && sleeper->sleeping() && sleeper->IsDynamic() &&
          other->IsActive())
        wake_keys_.push_back(sleeper->sleep_island());
    }
  });
}

void PhysicsSystem::BindConstraints() {
  step_joints_.clear();
  joint_island_body_.clear();
  jointed_pairs_.Clear();
  const float h = step_dt_ / static_cast<float>(settings_.substeps);
  constraints_.ForEachActive([&](Constraint& joint) {
    ConstraintSide sides[2];
    bool moves[2] = {false, false};
    const BodyID ids[2] = {joint.body_a(), joint.body_b()};
    for (int k = 0; k < 2; ++k) {
      if (ids[k].IsInvalid()) continue;  // the world: still, at the identity
      if (ids[k].index >= body_manager_.locked_slot_limit()) return;
      const Body& body = body_manager_.BodyAt(ids[k].index);
      // A joint whose body left the world (or was destroyed) waits until it is back.
      if (!body.in_world() || body.id() != ids[k]) return;
      moves[k] = body.IsActive() && body.IsDynamic();
      if (moves[k]) {
        sides[k].solver_index = solver_index_[ids[k].index];
        continue;
      }
      sides[k].start = {body.CenterOfMass(), body.rotation()};
      if (body.IsActive()) {  // kinematic: carries the joint along its velocity
        sides[k].linear_velocity = body.linear_velocity();
        sides[k].angular_velocity = body.angular_velocity();
      }
    }
    if (!moves[0] && !moves[1]) return;  // asleep, or between bodies that cannot move
    joint.BeginStep(sides[0], sides[1], h);
    joint.LinkIslands(islands_);
    step_joints_.push_back(&joint);
    if (!joint.collide_connected() && !ids[0].IsInvalid()) jointed_pairs_.Add(ids[0].index, ids[1].index);
    joint_island_body_.push_back((moves[0] ? sides[0].solver_index : sides[1].solver_index) - 1);
  });
  jointed_pairs_.Seal();
}

void PhysicsSystem::ApplyForces(std::uint32_t job, std::uint32_t width) {
  const float dt = step_dt_;
  const float h = dt / static_cast<float>(settings_.substeps);
  MotionClamps& clamps = finish_counters_[job].clamps;
  ForEachChunkItem(next_chunk_, static_cast<std::uint32_t>(active_.size()), kBodyChunk, width,
                   [&](std::uint32_t i) {
                     BeginStepMotion(body_manager_.BodyAt(active_[i].index), settings_, dt, h,
                                     constraint_solver_.bodies()[i + 1], constraint_solver_.poses()[i + 1],
                                     constraint_solver_.start_rotations()[i + 1],
                                     constraint_solver_.velocity_steps()[i + 1], clamps);
                   });
}

void PhysicsSystem::UpdateBroadPhase() {
  broad_phase_->Update();
}

void PhysicsSystem::FindCollisions(std::uint32_t job, std::uint32_t width) {
  collisions_.RunJob(job, width);
}

void PhysicsSystem::FinalizeIslands() {
  collisions_.Gather(contacts_, contact_island_body_);
  islands_.Finalize(contact_island_body_);
  // Kinematic bodies follow their velocity whatever they touch: moved now to their end-of-step pose (the
  // contacts that touch them follow them by their velocity).
  for (std::uint32_t i = 0; i < active_.size(); ++i) {
    if (body_manager_.BodyAt(active_[i].index).IsDynamic()) continue;
    MoveKinematic(constraint_solver_.bodies()[i + 1], constraint_solver_.poses()[i + 1], step_dt_);
  }
  contact_kind_.SetContacts(contacts_);
  joint_kind_.SetJoints(step_joints_, joint_island_body_);
  ConstraintSolver::Input input;
  input.islands = &islands_;
  input.dt = step_dt_;
  input.settings = &settings_;
  constraint_solver_.BeginStep(input, job_count_);
  const std::uint32_t island_count = islands_.island_count();
  middle_graph_.SetWidth(prepare_islands_stage_, std::min(job_count_, constraint_solver_.group_count()));
  const auto casts = static_cast<std::uint32_t>(linear_cast_bodies_.size());
  middle_graph_.SetWidth(linear_casts_stage_, std::min(job_count_, (casts + kCastChunk - 1) / kCastChunk));
  next_cast_.store(0, std::memory_order_relaxed);
  sleep_key_base_ = wakes_.NewKeys(island_count);
  next_chunk_.store(0, std::memory_order_relaxed);
}

void PhysicsSystem::PrepareIslands(std::uint32_t job, std::uint32_t width) {
  ForEachChunkItem(next_chunk_, constraint_solver_.group_count(), 1, width,
                   [&](std::uint32_t group) { constraint_solver_.PrepareGroup(group, job); });
}

void PhysicsSystem::SolveIslands(std::uint32_t job, std::uint32_t width) {
  constraint_solver_.SolveJob(job, width);
}

void PhysicsSystem::LinearCasts(std::uint32_t job, std::uint32_t width) {
  CastScratch& scratch = cast_scratch_[job];
  ForEachChunkItem(next_cast_, static_cast<std::uint32_t>(linear_cast_bodies_.size()), kCastChunk, width,
                   [&](std::uint32_t k) {
                     if (LinearCast(linear_cast_bodies_[k], scratch))
                       ++finish_counters_[job].linear_cast_hits;
                   });
}

bool PhysicsSystem::LinearCast(std::uint32_t active_index, CastScratch& scratch) {
  const Body& body = body_manager_.BodyAt(active_[active_index].index);
  SolverPose& pose = constraint_solver_.poses()[active_index + 1];
  SolverBody& solved = constraint_solver_.bodies()[active_index + 1];
  // The body has not been written back yet: its pose is still the one the step started from.
  const Vec3 displacement = ToVec3(pose.center_of_mass) - body.CenterOfMass();
  const ConvexShape& shape = static_cast<const ConvexShape&>(*body.shape());
  const float inner = shape.LocalBounds().HalfExtents().minCoeff();
  if (displacement.norm() <= kLinearCastThreshold * inner) return false;
  // The sweep keeps the end rotation and moves the centre of mass in a straight line.
  const Vec3 offset = pose.rotation * body.center_of_mass_local();
  const Pose start{body.CenterOfMass() - offset, pose.rotation};
  scratch.hits.clear();
  broad_phase_->CastAABB(shape.WorldBounds(start).Expanded(kCastTolerance), displacement, QueryFilter{},
                         scratch.hits);
  std::optional<ShapeCastHit> nearest;
  float nearest_restitution = 0.0f;
  for (const BroadPhaseRayHit& candidate : scratch.hits) {
    if (candidate.id == body.id()) continue;
    const Body& target = body_manager_.BodyAt(candidate.id.index);
    if (!target.in_world() || target.id() != candidate.id || target.is_sensor()) continue;
    if (!layers_->ShouldCollide(body.object_layer(), target.object_layer())) continue;
    const std::optional<ShapeCastHit> hit = CastConvexShape(shape, start, displacement, *target.shape(),
                                                            target.pose(), kCastTolerance, scratch.triangles);
    if (hit && (!nearest || hit->fraction < nearest->fraction)) {
      nearest = hit;
      nearest_restitution = target.restitution();
    }
  }
  if (!nearest) return false;
  // Stop at the first touch and take out the approach (a bounce if either body has restitution); friction
  // and the rest are the contacts' work next step.
  pose.center_of_mass = ToVec4(start.position + nearest->fraction * displacement + offset);
  solved.delta_position = ToVec4(nearest->fraction * displacement);
  const Vec4 normal = ToVec4(nearest->normal);
  const float approach = solved.linear_velocity.dot(normal);
  if (approach < 0.0f) {
    const float restitution = std::max(body.restitution(), nearest_restitution);
    solved.linear_velocity -= ((1.0f + restitution) * approach) * normal;
  }
  return true;
}

void PhysicsSystem::FinishIslands(std::uint32_t job, std::uint32_t width) {
  const float dt = step_dt_;
  FinishCounters& counters = finish_counters_[job];
  ForEachChunkItem(next_chunk_, islands_.island_count(), kIslandChunk, width, [&](std::uint32_t island) {
    const std::span<const std::uint32_t> members = islands_.bodies(island);
    bool awake = false;
    for (const std::uint32_t i : members) {
      const std::uint32_t index = active_[i].index;
      SleepSpheres* spheres = sleep_spheres_.empty() ? nullptr : &sleep_spheres_[index];
      awake |= !EndStepMotion(body_manager_.BodyAt(index), constraint_solver_.bodies()[i + 1],
                              constraint_solver_.poses()[i + 1], settings_, dt, counters.clamps, spheres);
    }
    for (const std::uint32_t i : members) {
      Body& body = body_manager_.BodyAt(active_[i].index);
      if (!awake) {
        PutToSleep(body, sleep_key_base_ + island);
        ++counters.bodies_put_to_sleep;
      }
      const Status updated = broad_phase_->UpdateBody(body.id(), bounds_.Of(body, dt));
      assert(updated.ok());
      (void)updated;
    }
  });
}

void PhysicsSystem::ReportContacts() {
  bool reported = false;
  for (std::uint32_t job = 0; job < collisions_.job_count(); ++job) {
    reported_[job] = collisions_.reported(job);
    reported = reported || !reported_[job].manifolds.empty();
  }
  if (!reported && contact_events_.idle()) return;
  contact_events_.Update(std::span(reported_).first(collisions_.job_count()), active_flags_, body_manager_,
                         next_events_);
}

void PhysicsSystem::TestSensors(std::uint32_t job, std::uint32_t width) {
  sensors_.RunJob(job, width);
}

void PhysicsSystem::FinishStep() {
  if (!sensors_.idle()) sensors_.EndStep(next_events_);
  // Published whole: a reader copying them never sees half of a step's events. A world without events takes
  // no lock.
  if (!next_events_.empty() || !events_.empty()) {
    std::lock_guard lock(events_mutex_);
    std::swap(events_, next_events_);
  }
  wake_keys_.clear();
  collisions_.CollectWakeKeys(wake_keys_);
  wakes_.Request(wake_keys_);
  const CollisionStats collision = collisions_.stats();
  stats_.pairs = collision.pairs;
  stats_.pairs_replayed = collision.pairs_replayed;
  stats_.pairs_slid = collision.pairs_slid;
  stats_.pairs_kept_apart = collision.pairs_kept_apart;
  stats_.pairs_dropped = collision.pairs_dropped;
  stats_.bodies_skipped = collision.bodies_skipped;
  stats_.constraints_dropped = collision.constraints_dropped;
  WarnAboutBudgets();
  stats_.manifolds = collision.manifolds;
  stats_.contact_points = collision.contact_points;
  stats_.island_links = collision.links;
  stats_.island_link_hops = collision.link_hops;
  stats_.islands = islands_.island_count();
  stats_.solve_groups = constraint_solver_.group_count();
  stats_.max_splits = contact_kind_.max_split_count();
  stats_.exact_islands = constraint_solver_.exact_island_count();
  stats_.max_penetration = -contact_kind_.deepest_penetration();
  stats_.constraints = step_joints_.size();
  for (Constraint* joint : step_joints_) {
    joint->EndStep();
    stats_.constraints_broken += joint->broken() ? 1 : 0;
  }
  for (FinishCounters& counters : finish_counters_) {
    stats_.bodies_put_to_sleep += counters.bodies_put_to_sleep;
    stats_.linear_velocity_clamps += counters.clamps.linear;
    stats_.angular_velocity_clamps += counters.clamps.angular;
    stats_.linear_cast_hits += counters.linear_cast_hits;
    counters = {};
  }
}

}  // namespace strata
