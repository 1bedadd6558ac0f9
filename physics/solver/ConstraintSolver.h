// ConstraintSolver: solves the step's islands in parallel. It owns what every kind of constraint shares: the
// solver bodies' forces and integration, the groups of islands and the schedule of rounds; each kind of
// constraint (ConstraintKind: contacts, joints) lays out its constraints of a group in splits and runs
// them. A large island is a group of its own, runs of consecutive small islands form groups of about the
// same work. The step is solved in substeps (Box2D v3's soft step): per substep gravity and forces (the
// first substep's before the solve), a warm start per split, biased velocity passes per split,
// integration, relax passes per split; after the last substep restitution rounds (where a kind bounces) and
// position rounds (where a kind corrects positions). Each of these is a round; a round's batches may run on
// any job, and the job finishing a round's last batch opens the next one. Islands share no body, so
// grouping them changes no island's solve order. The result is the same for any thread count.
// Threading: BeginStep runs alone; PrepareGroup and SolveJob run from the step's jobs.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <vector>

#include "physics/constraints/ConstraintKind.h"
#include "physics/core/BlockArena.h"
#include "physics/solver/LargeIslandSplitter.h"

namespace strata {

/// Parallel island solve of one step.
class ConstraintSolver {
 public:
  /// A run of small islands closes once it has this much work (constraints of every kind).
  static constexpr std::uint32_t kGroupWork = LargeIslandSplitter::kMinConstraintsToSplit;
  static constexpr std::size_t kMaxKinds = 4;

  /// What a step's solve needs besides the solver bodies.
  struct Input {
    const IslandBuilder* islands;
    float dt;
    const PhysicsSettings* settings;
  };

  /// `kinds` in the order their splits run in every round (contacts before joints). Set-up data goes into
  /// blocks from `pool`.
  ConstraintSolver(BlockPool& pool, std::initializer_list<ConstraintKind*> kinds);

  /// The step's solver bodies, poses and per-substep velocity gains: [0] the fixed body (no velocity, no
  /// inverse mass, identity pose), then one per active body (solver index = island body index + 1). Reset
  /// as the step begins; the step's apply-forces stage fills them from the bodies, the collision stage reads
  /// them, the solve moves them, the write-back copies them to the bodies.
  void ResetBodies(std::uint32_t active_count);
  std::span<SolverBody> bodies() { return bodies_; }
  std::span<SolverPose> poses() { return poses_; }
  std::span<SolverVelocityStep> velocity_steps() { return velocity_steps_; }
  /// Each solver body's rotation at the step's start as a matrix (BeginStepMotion writes them; the narrow
  /// phase reads them for every pair the body is in). Slot 0 is the identity.
  std::span<Mat3> start_rotations() { return start_rotations_; }

  /// Starts a step's solve with `job_count` jobs per stage and forms the groups (the solver bodies filled).
  void BeginStep(const Input& input, std::uint32_t job_count);

  std::uint32_t group_count() const { return group_count_; }
  /// Lets every kind order and split its constraints of group `group` (one group per call, any job).
  void PrepareGroup(std::uint32_t group, std::uint32_t job);
  /// After every PrepareGroup: solves batches of any group until every group is done (one call per job, of
  /// `width` jobs). A single job solves each group whole, in order, claiming nothing.
  void SolveJob(std::uint32_t job, std::uint32_t width);

  /// Bytes this step's set-up constraints take in the pool's blocks.
  std::size_t arena_bytes() const;
  /// Groups that hold more than one island.
  std::uint32_t merged_group_count() const;
  /// Islands solved exactly this step.
  std::uint32_t exact_island_count() const;

 private:
  enum class RoundKind {
    kSetup,
    kAddForces,
    kWarmStart,
    kVelocity,
    kIntegrate,
    kRelax,
    kRestitution,
    kPositions
  };
  struct Round {
    RoundKind kind;
    std::uint32_t split = 0;  // over all kinds' splits
    int iteration = 0;
    int substep = 0;
  };
  struct Group {
    SolverGroup islands;
    std::uint32_t work = 0;
    std::array<std::uint32_t, kMaxKinds + 1> split_begin{};  // kind u's splits: [split_begin[u], [u + 1])
    std::array<std::uint32_t, kMaxKinds + 1> setup_begin{};  // kind u's setup items, likewise
    std::uint32_t split_count = 0;
    bool free = false;  // no constraints: forces and integration only
    bool bounces = false;
    bool positions = false;
    // One job runs every round in order at once instead of the jobs claiming them batch by batch: where
    // each round is one item anyway (no parallel split, at most one body batch), and where the group is a
    // small share of the step's work, so that the other jobs are better off with groups of their own than
    // meeting at this one's round barriers.
    bool one_job = false;
    std::uint32_t round_count = 0;
    std::atomic<std::uint64_t> status{0};  // round << 32 | next unclaimed item
    std::atomic<std::uint32_t> processed{0};
  };
  struct alignas(64) JobState {
    BlockArena arena;  // set-up constraints, kept until the next step
  };
  enum class BatchResult { kRan, kWaiting, kDone };

  void FormGroups();
  void AddGroup(std::uint32_t first_island, std::uint32_t end_island, bool exact);
  BatchResult TryRunBatch(Group& group, JobState& job, std::uint32_t job_index, std::uint32_t width);
  BatchResult TryRunWholeGroup(Group& group, JobState& job, std::uint32_t job_index);
  // Every round of a group one job runs whole, in order.
  void RunRoundsInOrder(Group& group, JobState& job, std::uint32_t job_index);
  Round Describe(const Group& group, std::uint32_t round) const;
  // The kind that owns solver-wide split `split` of `group`.
  std::uint32_t KindOf(const Group& group, std::uint32_t split) const;
  SolverPass PassFor(const Group& group, const Round& round, std::uint32_t kind) const;
  std::uint32_t RoundItems(const Group& group, const Round& round) const;
  void RunBatch(Group& group, const Round& round, std::uint32_t begin, std::uint32_t end, JobState& job,
                std::uint32_t job_index);
  void RunSetup(Group& group, std::uint32_t begin, std::uint32_t end, JobState& job);
  void RunFreeGroup(const Group& group);
  void Integrate(std::uint32_t island_body);  // positions and deltas of a dynamic body
  void AddForces(std::uint32_t island_body);  // a substep's share of gravity and forces
  // Whether a velocity or relax pass is the step's last (it measures penetration).
  bool IsLastSolvePass(const Round& round) const;

  BlockPool& pool_;
  std::array<ConstraintKind*, kMaxKinds> kinds_{};
  std::uint32_t kind_count_ = 0;
  Input input_{};
  std::vector<SolverBody> bodies_;
  std::vector<SolverPose> poses_;
  std::vector<SolverVelocityStep> velocity_steps_;
  std::vector<Mat3> start_rotations_;
  float substep_dt_ = 0.0f;
  std::vector<std::uint8_t> island_exact_;  // by island
  std::vector<std::uint32_t> island_work_;  // by island: every kind's constraints in it
  std::vector<std::uint8_t> island_kinds_;  // by island: how many kinds have constraints in it
  std::vector<SolverGroup> group_islands_;  // what the kinds are told of the groups
  std::unique_ptr<Group[]> groups_;
  std::uint32_t group_capacity_ = 0;
  std::uint32_t group_count_ = 0;
  std::uint64_t total_work_ = 0;  // every group's work
  std::atomic<std::uint32_t> groups_finished_{0};
  std::vector<JobState> jobs_;
};

}  // namespace strata
