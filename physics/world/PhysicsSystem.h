// PhysicsSystem: owns the bodies, the broad phase, the contact cache and the job system, and runs the
// step: forces -> broad phase -> narrow phase -> islands -> sequential impulses -> integration.
// One Step at a time. BodyInterface calls and WorldQuery queries from any number of threads run at once
// (sharded body locks, lock-free broad phase). While a step runs, queries and reads go on (they pause
// only for its short LockAll windows at the start and end); body writes wait for the step to end.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "physics/body/BodyManager.h"
#include "physics/broadphase/BroadPhase.h"
#include "physics/core/JobSystem.h"
#include "physics/narrowphase/ContactCache.h"
#include "physics/solver/ContactSolver.h"
#include "physics/solver/IslandBuilder.h"
#include "physics/world/PhysicsSettings.h"

namespace strata {

class BodyInterface;
class WorldQuery;

/// Sizes and plug-ins fixed when the world is created.
struct PhysicsSystemConfig {
  std::uint32_t max_bodies = 65536;          ///< capacity of the body slot array
  std::uint32_t body_mutex_count = 32;       ///< read/write mutexes shared by the bodies
  int thread_count = 0;                      ///< threads of the default job system (0 = all cores)
  std::shared_ptr<const LayerSetup> layers;  ///< null = DefaultLayerSetup
  std::shared_ptr<JobSystem> job_system;     ///< null = oneTBB default (serial without oneTBB)
  std::shared_ptr<BroadPhase> broad_phase;   ///< null = QuadTreeBroadPhase

  Status Validate() const;
};

/// What the last step did, for tools and tests.
struct StepStats {
  std::size_t active_bodies = 0;
  std::size_t pairs = 0;
  std::size_t manifolds = 0;
  std::size_t contact_points = 0;
  std::size_t islands = 0;
  std::size_t bodies_put_to_sleep = 0;
  float max_penetration = 0.0f;  ///< after position correction (m)
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
  /// Thread-safe ray, box and shape queries.
  const WorldQuery& query() const { return *query_; }

  /// Advances the world by `dt` seconds. Fails (world unchanged) for a non-positive or non-finite dt.
  Status Step(float dt);

  const PhysicsSettings& settings() const { return settings_; }
  /// Replaces the settings between steps; fails (settings unchanged) if they do not validate.
  Status SetSettings(const PhysicsSettings& settings);
  const StepStats& last_step_stats() const { return stats_; }
  const LayerSetup& layers() const { return *layers_; }
  JobSystem& job_system() { return *jobs_; }

  /// Ids of the bodies currently in the world, in index order.
  std::vector<BodyID> BodiesInWorld() const;
  std::size_t body_count_in_world() const { return in_world_count_.load(std::memory_order_relaxed); }

  BodyManager& body_manager() { return body_manager_; }
  const BodyManager& body_manager() const { return body_manager_; }
  const BroadPhase& broad_phase() const { return *broad_phase_; }
  BroadPhase& broad_phase() { return *broad_phase_; }

 private:
  friend class BodyInterface;
  friend class WorldQuery;

  PhysicsSystem(const PhysicsSystemConfig& config, const PhysicsSettings& settings);

  // Stages of Step, in order.
  void WakePendingIslands();
  void CollectActiveBodies();
  void ApplyForces(float dt);
  void FindPairs(float dt);
  void RunNarrowPhase();
  void WakeTouchedSleepers();
  void Solve(float dt);
  void WriteBackSolvedBodies();
  void UpdateBroadPhaseBounds(float dt);
  void UpdateSleeping(float dt);

  // Wake-ups, shared with BodyInterface.
  void RequestWake(std::uint32_t island_key);
  AABB BroadPhaseBounds(const Body& body, float dt) const;
  float MotionBound(const Body& body, float dt) const;

  PhysicsSettings settings_;
  std::shared_ptr<const LayerSetup> layers_;
  std::shared_ptr<JobSystem> jobs_;
  BodyManager body_manager_;
  std::shared_ptr<BroadPhase> broad_phase_;
  std::unique_ptr<BodyInterface> body_interface_;
  std::unique_ptr<WorldQuery> query_;

  std::mutex step_mutex_;  // one Step (or SetSettings) at a time
  std::atomic<std::size_t> in_world_count_{0};
  std::mutex wake_mutex_;
  std::vector<std::uint32_t> pending_wakes_;  // island keys to wake at the next step
  std::atomic<std::uint32_t> next_island_key_{1};
  // Read by BodyInterface outside the step; written only under every body lock.
  std::atomic<float> last_dt_{1.0f / 60.0f};
  std::atomic<float> speculative_distance_;

  // Per-step scratch, kept to avoid reallocation.
  std::vector<BodyID> active_;
  std::vector<std::uint8_t> active_flags_;
  std::vector<BodyPair> pairs_;
  std::vector<float> pair_max_separation_;
  std::vector<ContactManifold> manifolds_;
  std::vector<SolverBody> solver_bodies_;
  std::vector<std::uint32_t> solver_index_;       // body index -> solver index (kNoSolverIndex if none)
  std::vector<std::uint32_t> solver_body_index_;  // solver index -> body index
  ContactCache contact_cache_;
  ContactSolver contact_solver_;
  IslandBuilder islands_;
  StepStats stats_;
};

}  // namespace strata
