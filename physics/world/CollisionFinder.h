// CollisionFinder: the step's "find collisions" stage. Each job claims small batches of active bodies and,
// for each, asks the broad phase for its pairs and runs the narrow phase on them straight away (no global
// pair list or sort): a pair that barely moved relative to last step replays its cached manifolds, a face
// contact that only slid carries its corners along, any other runs the shape test. Every manifold becomes a
// ContactConstraint in the job's own arena and a body-pair cache entry, and links the two bodies' islands.
// Pairs with a sensor are skipped (sensors never collide); a contact of a body created with validate_contacts
// is first put to the world's validator, and one of a body created with report_contacts is also reported
// (ReportedManifold) for the step's contact events.
// Runs only inside the step's unlocked window, where nothing else writes bodies; BeginStep and Gather run
// alone, RunJob from any number of jobs.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "physics/body/BodyManager.h"
#include "physics/broadphase/BroadPhase.h"
#include "physics/constraints/ContactConstraint.h"
#include "physics/core/BlockArena.h"
#include "physics/core/IndexPairSet.h"
#include "physics/narrowphase/BodyPairCache.h"
#include "physics/narrowphase/CollideShapes.h"
#include "physics/solver/IslandBuilder.h"
#include "physics/world/ContactEventTracker.h"
#include "physics/world/ContactValidator.h"

namespace strata {

/// Figures of one step's collision stage.
struct CollisionStats {
  std::size_t pairs = 0;             ///< body pairs whose bounds overlap
  std::size_t pairs_replayed = 0;    ///< of those, how many reused last step's manifolds
  std::size_t pairs_slid = 0;        ///< how many carried last step's face contact along a slide
  std::size_t pairs_kept_apart = 0;  ///< how many last step's separating axis still held apart
  std::size_t manifolds = 0;
  std::size_t contact_points = 0;
  std::size_t constraints = 0;  ///< manifolds with a body the solver moves
  std::uint64_t link_hops = 0;  ///< union-find links followed by IslandBuilder::Link
  std::size_t links = 0;
  std::size_t pairs_dropped = 0;        ///< past Input::max_pairs
  std::size_t bodies_skipped = 0;       ///< active bodies whose pairs were not looked for (budget spent)
  std::size_t constraints_dropped = 0;  ///< past Input::max_constraints
};

/// Broad phase + narrow phase + contact constraints, in parallel jobs.
class CollisionFinder {
 public:
  /// What one step's collision stage reads and writes (owned by the caller).
  struct Input {
    const BodyManager* bodies;
    const BroadPhase* broad_phase;
    const LayerSetup* layers;
    const PhysicsSettings* settings;
    float dt;
    std::span<const BodyID> active;               ///< active bodies in index order
    std::span<const std::uint8_t> active_flags;   ///< by body index
    std::span<const std::uint32_t> solver_index;  ///< by body index: active index + 1, or 0
    const SolverBody* solver_bodies;
    const SolverVelocityStep* velocity_steps;  ///< by solver index: what each substep adds
    const SolverPose* solver_poses;
    const Mat3* solver_rotations;  ///< solver_poses' rotations as matrices
    BodyPairCache* cache;
    IslandBuilder* islands;
    /// Body pairs (indices) joined by a joint that do not collide.
    const IndexPairSet* jointed_pairs = nullptr;
    /// Asked about contacts of bodies created with validate_contacts; null: none is set.
    const ContactValidator* validator = nullptr;
    /// The step's budgets: broad-phase pairs taken and constraints built; the rest are dropped and counted.
    std::size_t max_pairs = SIZE_MAX;
    std::size_t max_constraints = SIZE_MAX;
  };

  /// Constraints go into blocks from `pool`.
  explicit CollisionFinder(BlockPool& pool) : pool_(pool) {}

  /// Starts a step with `job_count` jobs (job indices [0, job_count)). Reserves every job's buffers for the
  /// whole of last step's work, so how the jobs split the next one never makes them grow.
  void BeginStep(const Input& input, std::uint32_t job_count);
  /// Claims batches of active bodies until none is left; one of `width` jobs (see ForEachChunk).
  void RunJob(std::uint32_t job, std::uint32_t width);
  /// After every job: the constraints in the order of the active body that found them (the same order for
  /// any thread count), each with its island body (active index of a body the solver moves).
  void Gather(std::vector<ContactConstraint*>& constraints, std::vector<std::uint32_t>& island_body) const;
  /// Island keys of sleeping bodies an active body touched this step, appended to `out`.
  void CollectWakeKeys(std::vector<std::uint32_t>& out) const;
  CollisionStats stats() const;
  /// The manifolds job `job` reported this step (pairs with a body created with report_contacts), in the
  /// order it found them.
  JobReports reported(std::uint32_t job) const { return {jobs_[job].reported, jobs_[job].reported_geometry}; }
  std::uint32_t job_count() const { return job_count_; }
  /// Bytes this step's constraints take in the pool's blocks.
  std::size_t arena_bytes() const;

 private:
  struct BodyContacts {
    std::uint32_t job;
    std::uint32_t begin;
    std::uint32_t end;
  };
  struct alignas(64) Job {
    BlockArena arena;
    std::vector<ContactConstraint*> constraints;
    std::vector<std::uint32_t> island_body;
    std::vector<BodyPair> pairs;
    std::vector<ContactManifold> manifolds;
    CollisionScratch scratch;
    std::vector<std::uint32_t> wake_keys;
    std::vector<ReportedManifold> reported;
    std::vector<ReportedGeometry> reported_geometry;
    std::size_t constraint_allowance = 0;  // constraints claimed from the step's budget, not yet built
    CollisionStats stats;
  };
  // A posed side of a pair as the narrow phase and the constraint builder need it.
  struct Side {
    const Body* body;
    std::uint32_t solver_index;
    bool dynamic;
    Vec3 center_of_mass;
    Quat rotation;
    Mat3 rotation_matrix;
  };

  // Takes pairs from the step's budget: the first `wanted` of those the job holds, or as many as are left.
  void ClaimPairs(Job& job);
  // Takes one constraint from the step's budget (claimed in small lots per job); false when it is spent.
  bool ClaimConstraint(Job& job);
  // Whether two convex shapes are still apart beyond `max_separation` along the separating axis of last
  // step's entry for their pair: then no contact test could find a contact.
  bool KeptApart(const CachedBodyPair& previous, const Side& a, const Side& b, float max_separation) const;
  void CollidePair(BodyPair pair, BodyPairCache::PreviousPairs& previous_pairs, std::uint32_t job_index);
  /// Makes last step's manifolds this step's, moved with the bodies.
  void ReplayManifolds(const CachedBodyPair& previous, const Side& a, const Side& b, CachedBodyPair& entry,
                       std::uint32_t job_index);
  /// Carries last step's face manifold along with the corners' body if the pair kept its turn and the
  /// corners are still on the face (ContactFace); false, adding nothing, where the shapes need a test.
  bool SlideManifold(BodyPair pair, const CachedBodyPair& previous, const Side& a, const Side& b,
                     const Vec3& delta_position, const Quat& delta_rotation, float max_separation,
                     std::uint32_t job_index);
  /// Takes a freshly computed manifold, warm-started from last step's manifold of the same sub-shape.
  void AddComputedManifold(const ContactManifold& manifold, const Side& a, const Side& b,
                           CachedBodyPair& entry, const CachedManifold* previous, std::uint32_t job_index);
  /// Asks the validator (bodies with validate_contacts), wakes the sleepers it touches, then builds the
  /// constraint, links the islands and reports the manifold (bodies with report_contacts).
  void AddConstraint(const Vec3& normal, std::span<const ContactArms> arms, const Side& a, const Side& b,
                     CachedManifold& cached, std::uint32_t job_index);
  /// Whether the validator lets the manifold be solved.
  bool Validate(const Vec3& normal, std::span<const ContactArms> arms, const Side& a, const Side& b) const;
  /// Adds the manifold's record to the job's reports; its impulses are those the solver sums in `cached`
  /// (none without a `constraint`).
  void Report(const Vec3& normal, std::span<const ContactArms> arms, const Side& a, const Side& b,
              const ContactConstraint* constraint, const CachedManifold& cached, Job& job) const;
  /// Whether the pair's manifolds are reported (a body created with report_contacts).
  static bool Reports(const Side& a, const Side& b);
  Side MakeSide(const Body& body) const;
  ContactSide ContactInputSide(const Side& side) const;

  BlockPool& pool_;
  Input input_{};
  std::uint32_t job_count_ = 0;
  float replay_max_distance_squared_ = 0.0f;
  float replay_min_half_angle_cosine_ = 1.0f;
  float replay_max_angle_ = 0.0f;  // degrees, what the cosine above was computed from
  bool slides_ = false;
  bool keeps_apart_ = false;  // pairs pass over on last step's separating axis
  bool replays_ = false;
  std::atomic<std::uint32_t> next_body_{0};
  alignas(64) std::atomic<std::size_t> pairs_claimed_{0};
  alignas(64) std::atomic<std::size_t> constraints_claimed_{0};
  std::vector<Job> jobs_;
  std::vector<BodyContacts> body_contacts_;  // by active index
};

}  // namespace strata
