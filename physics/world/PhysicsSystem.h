// PhysicsSystem: owns the bodies, the broad phase, the contact cache and the job system, and runs the
// step: forces -> broad phase -> narrow phase -> islands -> sequential impulses -> integration.
// Step() takes the world exclusively; BodyInterface calls and WorldQuery queries from any number of
// threads run concurrently with each other (sharded body locks) and wait while a step runs.
#pragma once

#include <memory>
#include <mutex>
#include <shared_mutex>
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
  std::shared_ptr<BroadPhase> broad_phase;   ///< null = BruteForceBroadPhase

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

  /// Ids of the bodies currently in the world, in the order they were added.
  std::vector<BodyID> BodiesInWorld() const;
  std::size_t body_count_in_world() const;

  BodyManager& body_manager() { return body_manager_; }
  const BodyManager& body_manager() const { return body_manager_; }
  const BroadPhase& broad_phase() const { return *broad_phase_; }

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
  void UpdateBroadPhaseBounds(float dt);
  void UpdateSleeping(float dt);

  // Membership and wake-ups, shared with BodyInterface.
  void AddToWorldList(std::uint32_t index);
  void RemoveFromWorldList(std::uint32_t index);
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

  // Step exclusivity: Step holds it uniquely, interface calls and queries share it.
  mutable std::shared_mutex step_mutex_;
  mutable std::mutex membership_mutex_;
  std::vector<std::uint32_t> world_list_;      // indices of bodies in the world
  std::vector<std::uint32_t> world_position_;  // index -> position in world_list_
  std::mutex wake_mutex_;
  std::vector<std::uint32_t> pending_wakes_;  // island keys to wake at the next step
  std::uint32_t next_island_key_ = 1;
  float last_dt_ = 1.0f / 60.0f;

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
