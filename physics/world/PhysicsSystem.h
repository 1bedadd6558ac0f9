// PhysicsSystem: owns the bodies, the broad phase, the body-pair cache and the job system, and runs the
// step as a graph of parallel stages: forces -> (broad-phase rebuild | find collisions: broad phase, narrow
// phase, contact constraints, island links) -> islands -> split large islands -> solve islands (sequential
// impulses, integration, position passes) -> write back and sleep. One Step at a time. BodyInterface calls
// and WorldQuery queries from any number of threads run at once (sharded body locks, lock-free broad phase);
// while a step runs, queries and reads go on (they pause only for its short LockAll windows at the start and
// end) and body writes wait for the step to end. After the bodies have moved the step reports contact and
// sensor events (StepEvents), read between steps on the stepping thread or copied from any thread.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "physics/PhysicsSettings.h"
#include "physics/body/BodyInterface.h"
#include "physics/body/BodyManager.h"
#include "physics/body/BodyMotion.h"
#include "physics/body/BodySnapshotTable.h"
#include "physics/body/BroadPhaseMoveOrder.h"
#include "physics/body/SpeculativeBounds.h"
#include "physics/body/WakeQueue.h"
#include "physics/broadphase/BroadPhase.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/constraints/ContactConstraintKind.h"
#include "physics/constraints/JointConstraintKind.h"
#include "physics/core/IndexPairSet.h"
#include "physics/core/JobGraph.h"
#include "physics/core/JobSystem.h"
#include "physics/narrowphase/BodyPairCache.h"
#include "physics/solver/ConstraintSolver.h"
#include "physics/solver/IslandBuilder.h"
#include "physics/world/CollisionFinder.h"
#include "physics/world/ContactEventTracker.h"
#include "physics/world/ContactValidator.h"
#include "physics/world/SensorTracker.h"
#include "physics/world/StepEvents.h"
#include "physics/world/WorldQuery.h"

namespace strata {

/// Sizes and plug-ins fixed when the world is created.
struct PhysicsSystemConfig {
  std::uint32_t max_bodies = 65536;          ///< capacity of the body slot array
  std::uint32_t body_mutex_count = 32;       ///< read/write mutexes shared by the bodies
  int thread_count = 0;                      ///< threads of the default job system (0 = all cores)
  std::shared_ptr<const LayerSetup> layers;  ///< null = DefaultLayerSetup
  std::shared_ptr<JobSystem> job_system;     ///< null = oneTBB default (std::thread pool without oneTBB)
  std::shared_ptr<BroadPhase> broad_phase;   ///< null = QuadTreeBroadPhase
  /// Time the step and every stage's jobs for last_step_profile(). Off, no clock is read: two reads per job
  /// were about 16% of a one-body step.
  bool stage_timings = true;
  /// Step memory budgets, as Jolt's: body pairs the broad phase may hand the narrow phase in one step, and
  /// contact constraints (manifolds the solver takes). Past either, the step drops the rest (StepStats counts
  /// them), warns once and goes on: 10,000 bodies spawned at one point would otherwise want 50 million pairs.
  /// 0: 16 per body slot (max_bodies), which no scene of ours comes near. Which pairs are dropped depends on
  /// the threads' timing: a step over budget is not deterministic.
  std::size_t max_body_pairs = 0;
  std::size_t max_contact_constraints = 0;
  /// Where the world's warnings go (a budget exceeded, once per world and kind); null: standard error.
  std::function<void(const std::string&)> warning;

  static constexpr int kMaxThreads = 256;  ///< thread_count's limit

  Status Validate() const;
};

/// What the last step did, for tools and tests.
struct StepStats {
  std::size_t active_bodies = 0;
  std::size_t pairs = 0;             ///< body pairs whose bounds overlap (at least one dynamic body)
  std::size_t pairs_replayed = 0;    ///< pairs that reused last step's manifolds (body-pair cache)
  std::size_t pairs_slid = 0;        ///< pairs that carried last step's face contact along a slide
  std::size_t pairs_kept_apart = 0;  ///< pairs that last step's separating axis still held apart
  std::size_t manifolds = 0;
  std::size_t contact_points = 0;
  std::size_t islands = 0;
  std::size_t solve_groups =
      0;                       ///< groups the islands were solved in (a large island, or small ones together)
  std::size_t max_splits = 0;  ///< splits of the most split group
  std::size_t exact_islands = 0;  ///< islands solved exactly (ExactContactSolver)
  std::size_t bodies_put_to_sleep = 0;
  std::size_t island_links = 0;             ///< IslandBuilder::Link calls
  std::uint64_t island_link_hops = 0;       ///< links they followed
  float max_penetration = 0.0f;             ///< deepest overlap at the end of the solve (m)
  std::size_t linear_velocity_clamps = 0;   ///< bodies slowed to their max_linear_velocity
  std::size_t angular_velocity_clamps = 0;  ///< bodies slowed to their max_angular_velocity
  std::size_t linear_cast_hits = 0;         ///< linear-cast bodies stopped at a first impact
  std::size_t constraints = 0;              ///< joints solved (at least one of their bodies awake)
  std::size_t constraints_broken = 0;       ///< joints that broke this step
  std::size_t pairs_dropped = 0;            ///< body pairs past PhysicsSystemConfig::max_body_pairs
  std::size_t bodies_skipped = 0;       ///< active bodies whose pairs were not looked for (pair budget spent)
  std::size_t constraints_dropped = 0;  ///< contact constraints past max_contact_constraints
};

/// Where the last step's time went: the stages in order, with their start, end and summed job time.
struct StepProfile {
  static constexpr std::size_t kMaxStages = 16;
  StageTiming stages[kMaxStages];
  std::size_t stage_count = 0;
  double total_ms = 0.0;  ///< the whole step; 0 when the world was created without stage_timings
};

/// A physics world.
class PhysicsSystem {
 public:
  /// Fails on a bad config or settings.
  static Result<std::unique_ptr<PhysicsSystem>> Create(const PhysicsSystemConfig& config,
                                                       const PhysicsSettings& settings = {});
  ~PhysicsSystem();
  PhysicsSystem(const PhysicsSystem&) = delete;
  PhysicsSystem& operator=(const PhysicsSystem&) = delete;

  /// Thread-safe body creation, membership and state access.
  BodyInterface& bodies() { return *body_interface_; }
  /// Thread-safe joints (calls made during a step wait for its end).
  ConstraintManager& constraints() { return constraints_; }
  const ConstraintManager& constraints() const { return constraints_; }
  /// Thread-safe ray, box and shape queries.
  const WorldQuery& query() const { return *query_; }

  /// Advances the world by `dt` seconds. Fails (world unchanged) for a non-positive or non-finite dt.
  Status Step(float dt);

  const PhysicsSettings& settings() const { return settings_; }
  /// Replaces the settings between steps; fails (settings unchanged) if they do not validate.
  Status SetSettings(const PhysicsSettings& settings);
  /// The last step's contact and sensor events, valid until the next Step: read them on the thread that
  /// steps, between steps. Other threads use CopyEvents.
  const StepEvents& events() const { return events_; }
  /// Copies the last finished step's events into `out` (reusing its capacity); from any thread at any time,
  /// also while a step runs (it publishes its events as it ends).
  void CopyEvents(StepEvents& out) const;
  /// The callback asked, from the narrow-phase jobs, about every contact of a body created with
  /// validate_contacts (see ContactValidator for what it may do); empty: none, contacts are solved. Waits for
  /// a running step.
  void SetContactValidator(ContactValidator validator);

  const StepStats& last_step_stats() const { return stats_; }
  const StepProfile& last_step_profile() const { return profile_; }
  const LayerSetup& layers() const { return *layers_; }
  JobSystem& job_system() { return *jobs_; }

  /// Ids of the bodies currently in the world, in index order.
  std::vector<BodyID> BodiesInWorld() const;
  std::size_t body_count_in_world() const { return body_manager_.in_world_count(); }

  BodyManager& body_manager() { return body_manager_; }
  const BodyManager& body_manager() const { return body_manager_; }
  const BroadPhase& broad_phase() const { return *broad_phase_; }
  BroadPhase& broad_phase() { return *broad_phase_; }
  /// Lock-free copies of the bodies in the world for background readers (off until one enables it).
  const BodySnapshotTable& body_snapshots() const { return body_snapshots_; }

 private:
  PhysicsSystem(const PhysicsSystemConfig& config, const PhysicsSettings& settings);
  void BuildStepGraphs();
  /// Reports the first step over each budget (PhysicsSystemConfig::max_body_pairs, max_contact_constraints).
  void WarnAboutBudgets();

  // Stages of Step, in order. Each runs as jobs of the step's graphs (see BuildStepGraphs); a parallel
  // stage's job knows how many jobs (`width`) run it.
  void PrepareStep();            // serial: wake islands, collect active bodies
  void WakeConstrainedBodies();  // part of PrepareStep: a joint wakes its sleeping side
  void BindConstraints();        // part of PrepareStep: the step's joints and their islands
  void ApplyForces(std::uint32_t job, std::uint32_t width);     // parallel over active bodies
  void UpdateBroadPhase();                                      // one job, beside FindCollisions
  void FindCollisions(std::uint32_t job, std::uint32_t width);  // parallel over active bodies
  void FinalizeIslands();                                       // serial, O(bodies + constraints)
  void PrepareIslands(std::uint32_t job, std::uint32_t width);  // parallel over islands
  void SolveIslands(std::uint32_t job, std::uint32_t width);    // parallel over islands and split batches
  void LinearCasts(std::uint32_t job,
                   std::uint32_t width);  // parallel over fast linear-cast bodies (one empty job if none)
  void FinishIslands(std::uint32_t job,
                     std::uint32_t width);  // parallel over islands: write back, bounds, sleep
  void ReportContacts();  // one job beside FinishIslands: contact events (returns at once without any)
  void TestSensors(std::uint32_t job, std::uint32_t width);  // parallel over sensors, after the end window
  void FinishStep();                                         // serial: wake-ups, figures, events

  PhysicsSettings settings_;
  std::shared_ptr<const LayerSetup> layers_;
  std::shared_ptr<JobSystem> jobs_;
  BodyManager body_manager_;
  ConstraintManager constraints_;  // its mutex is held by Step from start to end
  BodySnapshotTable body_snapshots_;
  BroadPhaseMoveOrder move_order_;  // orders the broad-phase updates moves make after their lock
  std::shared_ptr<BroadPhase> broad_phase_;
  WakeQueue wakes_;           // islands BodyInterface woke, taken by the next step
  SpeculativeBounds bounds_;  // the broad phase's bounds of a body, shared with BodyInterface
  std::unique_ptr<BodyInterface> body_interface_;
  std::unique_ptr<WorldQuery> query_;

  std::mutex step_mutex_;  // one Step (or SetSettings) at a time

  // The step's stages and its per-step data, sized once and reused so a steady step allocates nothing.
  JobGraph start_graph_;   // runs while the step holds every body lock
  JobGraph middle_graph_;  // runs unlocked
  JobGraph end_graph_;     // runs while the step holds every body lock
  JobGraph events_graph_;  // runs unlocked after end_graph_, only in a world with sensors
  JobGraph::StageId sensors_stage_ = 0;
  JobGraph::StageId prepare_islands_stage_ = 0;
  std::uint32_t job_count_ = 1;
  // Step budgets (PhysicsSystemConfig) and whether each was reported.
  std::size_t max_body_pairs_ = 0;
  std::size_t max_contact_constraints_ = 0;
  std::function<void(const std::string&)> warning_;
  bool warned_pairs_ = false;
  bool warned_constraints_ = false;
  float step_dt_ = 0.0f;
  std::atomic<std::uint32_t> next_chunk_{0};  // work claimed by the current parallel stage
  std::vector<std::uint32_t> wake_keys_;
  std::vector<BodyID> active_;
  std::vector<std::uint8_t> active_flags_;   // by body index
  std::vector<SleepSpheres> sleep_spheres_;  // by body index, only while SleepRule::kPointMovement is in use
  std::vector<std::uint32_t> solver_index_;  // by body index: active index + 1, 0 = not active
  std::vector<ContactConstraint*> contacts_;
  std::vector<Constraint*> step_joints_;          // the joints this step solves, in slot order
  std::vector<std::uint32_t> joint_island_body_;  // per step joint: a moving body's active index
  IndexPairSet jointed_pairs_;                    // body index pairs a joint keeps from colliding
  std::vector<std::uint32_t> contact_island_body_;
  std::uint32_t sleep_key_base_ = 0;  // island i falling asleep this step gets key base + i
  struct alignas(64) FinishCounters {
    std::size_t bodies_put_to_sleep = 0;
    MotionClamps clamps;
    std::size_t linear_cast_hits = 0;
  };
  struct CastScratch {
    std::vector<BroadPhaseRayHit> hits;
    std::vector<Triangle> triangles;
  };
  // Sweeps one linear-cast body over its motion this step; true if it was stopped at a hit.
  bool LinearCast(std::uint32_t active_index, CastScratch& scratch);
  std::vector<FinishCounters> finish_counters_;
  std::vector<CastScratch> cast_scratch_;          // per job
  std::vector<std::uint32_t> linear_cast_bodies_;  // active indices of awake linear-cast bodies
  std::atomic<std::uint32_t> next_cast_{0};
  JobGraph::StageId linear_casts_stage_ = 0;
  BlockPool step_blocks_;  // every step arena's blocks (declared before its users, so it outlives them)
  BodyPairCache pair_cache_;
  CollisionFinder collisions_;
  IslandBuilder islands_;
  // The kinds of constraint the solver drives, in the order their splits run (declared before the solver).
  ContactConstraintKind contact_kind_;
  JointConstraintKind joint_kind_;
  ConstraintSolver constraint_solver_;
  // Events: built by the step into next_events_ and swapped into events_ (under events_mutex_) as it ends.
  ContactValidator validator_;  // changed only under step_mutex_
  ContactEventTracker contact_events_;
  std::vector<JobReports> reported_;  // per job, for contact_events_
  SensorTracker sensors_;
  std::vector<BodyID> sensor_bodies_;  // the sensors in the world this step, by index
  StepEvents next_events_;
  StepEvents events_;
  mutable std::mutex events_mutex_;
  StepStats stats_;
  StepProfile profile_;
};

}  // namespace strata
