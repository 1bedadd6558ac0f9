// IslandSolver: solves the step's islands in parallel. Islands are solved in groups: a large island is a
// group of its own, and runs of consecutive small islands form groups of about the same size. A group's
// constraints are split (LargeIslandSplitter) so that no two in one parallel split move the same body: a
// parallel split is solved a register of lanes at a time (ContactBundle), the sequential split one
// constraint at a time (ContactSolver). The step is solved in substeps (Box2D v3's soft step): per substep
// gravity and forces (the first substep's before the solve), a warm start per split, biased velocity passes
// per split, integration, relax passes per split; after the last substep a restitution pass per split where
// something bounces. Each of these is a round; a round's batches may run on any job, and the job finishing a
// round's last batch opens the next one. Constraints
// of different small islands share no body, so grouping them changes no island's solve order, only fills
// the lanes. Joints (Constraint) of a group's islands are one more split, solved one joint at a time after
// the contact splits in every warm-start, velocity and relax round. The result is the same for any thread
// count.
// BeginStep runs alone; PrepareGroup and SolveJob run from the step's jobs.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "physics/constraints/Constraint.h"
#include "physics/constraints/DirectJointSolver.h"
#include "physics/core/BlockArena.h"
#include "physics/solver/ContactBundle.h"
#include "physics/solver/ContactConstraint.h"
#include "physics/solver/ContactSolver.h"
#include "physics/solver/DirectContactSolver.h"
#include "physics/solver/IslandBuilder.h"
#include "physics/solver/LargeIslandSplitter.h"

namespace strata {

/// Parallel island solve of one step.
class IslandSolver {
 public:
  /// A run of small islands closes once it has this many constraints.
  static constexpr std::uint32_t kGroupConstraints = LargeIslandSplitter::kMinConstraintsToSplit;
  /// Small islands are solved by a DirectContactSolver (with PhysicsSettings::direct_small_islands) when
  /// they have at least two bodies, at most this many contact points per body...
  static constexpr std::uint32_t kDirectMaxPointsPerBody = 8;
  /// ...and every body moves and turns slower than this (m/s, rad/s) when the step begins.
  static constexpr float kDirectRestSpeed = 1.0f;

  /// What a step's solve needs; the arrays stay owned by the caller.
  struct Input {
    const IslandBuilder* islands;
    std::span<ContactConstraint* const> constraints;  ///< indexed as in IslandBuilder::Finalize
    SolverBody* bodies;                               ///< solver index = island body index + 1
    SolverPose* poses;
    const SolverVelocityStep* velocity_steps;  ///< what gravity and forces add per substep, by solver body
    std::span<Constraint* const> joints;       ///< the step's joints, bound to their solver bodies
    std::span<const std::uint32_t> joint_island_body;  ///< per joint: a moving body's island body index
    std::uint32_t solver_body_count;
    float dt;
    const PhysicsSettings* settings;
  };

  /// Set-up contacts and bundles go into blocks from `pool`.
  explicit IslandSolver(BlockPool& pool) : pool_(pool) {}

  /// Starts a step's solve with `job_count` jobs per stage and forms the groups.
  void BeginStep(const Input& input, std::uint32_t job_count);

  std::uint32_t group_count() const { return group_count_; }
  /// Orders group `group`'s constraints and splits them (one group per call, any job).
  void PrepareGroup(std::uint32_t group, std::uint32_t job);
  /// After every PrepareGroup: solves batches of any group until every group is done (one call per job).
  void SolveJob(std::uint32_t job);

  /// Bytes this step's set-up contacts and bundles take in the pool's blocks.
  std::size_t arena_bytes() const;
  /// Deepest penetration the last pass saw (m, <= 0), once every SolveJob has returned.
  float deepest_penetration() const;
  /// Groups that hold more than one island.
  std::uint32_t merged_group_count() const;
  /// Islands solved by a DirectContactSolver this step.
  std::uint32_t direct_island_count() const;
  /// Splits of the most split group (0 if none), for profiles.
  std::uint32_t max_split_count() const;

 private:
  enum class RoundKind {
    kSetup,
    kAddForces,
    kWarmStart,
    kVelocity,
    kIntegrate,
    kRelax,
    kRestitution,
    kJointPositions
  };
  struct Round {
    RoundKind kind;
    std::uint32_t split = 0;
    int iteration = 0;
    int substep = 0;
  };
  struct Group {
    std::uint32_t first_island = 0;
    std::uint32_t end_island = 0;
    std::uint32_t first_constraint = 0;  // offset in ordered_
    IslandSplits splits;
    ContactBundle** bundles = nullptr;  // the parallel splits' bundles, split after split
    std::uint32_t bundle_begin[IslandSplits::kMaxSplits + 1] = {};
    std::uint32_t bundle_count = 0;
    Constraint* const* joints = nullptr;  // the joints' split (after the contact splits), in island order
    std::uint32_t joint_count = 0;
    DirectJointSolver* joint_solver = nullptr;       // the rigid rows of its islands that need an exact solve
    std::uint32_t round_splits = 0;                  // contact splits, plus one for the joints if any
    bool free = false;                               // no contacts and no joints: forces and integration only
    ContactConstraint* const* sequential = nullptr;  // the sequential split's constraints
    SolverContact** sequential_contacts = nullptr;   // ...as set up in the setup round
    std::uint32_t sequential_count = 0;
    bool direct = false;  // small islands only, each solved by its own DirectContactSolver
    DirectContactSolver** direct_solvers = nullptr;  // one per island, set up in the setup round
    bool has_restitution = false;
    // No parallel split and at most one body batch: every round is one item, so one job runs them all in
    // order at once instead of claiming them one by one.
    bool one_job = false;
    std::uint32_t round_count = 0;
    std::atomic<std::uint64_t> status{0};  // round << 32 | next unclaimed item
    std::atomic<std::uint32_t> processed{0};
  };
  struct alignas(64) JobState {
    BlockArena arena;  // set-up contacts and bundles, kept until the next step
    std::vector<std::uint8_t> split_of;
    std::vector<ContactConstraint*> scratch;
    std::vector<std::uint32_t> first_row_of_body;  // DirectJointSolver scratch, by solver index
    float deepest = 0.0f;
  };
  enum class BatchResult { kRan, kWaiting, kDone };

  BatchResult TryRunBatch(Group& group, JobState& job);
  BatchResult TryRunWholeGroup(Group& group, JobState& job);
  Round Describe(const Group& group, std::uint32_t round) const;
  std::uint32_t RoundItems(const Group& group, const Round& round) const;
  void RunBatch(Group& group, const Round& round, std::uint32_t begin, std::uint32_t end, JobState& job);
  bool IsJointSplit(const Group& group, std::uint32_t s) const {
    return group.joint_count > 0 && s == group.splits.split_count;
  }
  void RunJoints(const Group& group, const Round& round) const;
  // Whether a joint asks for its island's rigid rows to be solved exactly (see PhysicsSettings).
  bool NeedsDirectSolve(const Constraint& joint) const;
  bool IsSequential(const Group& group, std::uint32_t s) const {
    return group.splits.last_is_sequential && s + 1 == group.splits.split_count;
  }
  void AddGroup(std::uint32_t first_island, std::uint32_t end_island, bool direct);
  // A group of islands without constraints (bodies in free flight) needs no ordering, splits or set-up.
  void PrepareFreeGroup(Group& group);
  void RunFreeGroup(const Group& group) const;
  bool IsDirectIsland(std::uint32_t island) const;
  void SortJointsByIsland();
  void SetupDirectSolvers(Group& group, JobState& job);
  void Integrate(std::uint32_t island_body) const;  // positions and deltas of a dynamic body
  void AddForces(std::uint32_t island_body) const;  // a substep's share of gravity and forces
  // Whether a velocity or relax pass is the step's last (it measures penetration).
  bool IsLastSolvePass(const Round& round) const;

  BlockPool& pool_;
  Input input_{};
  SubstepContext context_{};  // elapsed set per round
  float substep_dt_ = 0.0f;
  std::vector<ContactConstraint*> ordered_;        // every island's constraints, island after island
  std::vector<std::uint32_t> body_masks_;          // LargeIslandSplitter scratch, by solver body
  std::vector<std::uint8_t> island_direct_;        // by island: solved by a DirectContactSolver
  std::vector<std::uint32_t> island_joint_begin_;  // by island, into joints_: its joints
  std::vector<Constraint*> joints_;                // every island's joints, island after island
  std::vector<std::uint8_t> joint_direct_;         // by joints_ entry: its rigid rows are solved exactly
  SoftSpring joint_spring_;                        // the joints' rigid rows while they push drift out
  std::unique_ptr<Group[]> groups_;
  std::uint32_t group_capacity_ = 0;
  std::uint32_t group_count_ = 0;
  std::atomic<std::uint32_t> groups_finished_{0};
  std::vector<JobState> jobs_;
};

}  // namespace strata
