// IslandSolver: solves the step's islands in parallel. Small islands go whole to one job, one constraint at a
// time (ContactSolver: setup, warm start, velocity passes, store impulses, integrate, bounce shifts,
// position passes). Large ones are split (LargeIslandSplitter); a parallel split's constraints are solved
// a register of lanes at a time (ContactBundle), its sequential split one at a time, and every job helps with
// them one batch at a time: each stage of the island's solve (setup, one split of one pass, integration) is a
// round, a round's batches may run on any thread, and the thread finishing a round's last batch opens the
// next one. The result is the same for any thread count. BeginStep runs alone; PrepareIsland and SolveJob run
// from the step's jobs.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "physics/core/BlockArena.h"
#include "physics/solver/ContactBundle.h"
#include "physics/solver/ContactConstraint.h"
#include "physics/solver/ContactSolver.h"
#include "physics/solver/IslandBuilder.h"
#include "physics/solver/LargeIslandSplitter.h"

namespace strata {

/// Parallel island solve of one step.
class IslandSolver {
 public:
  /// What a step's solve needs; the arrays stay owned by the caller.
  struct Input {
    const IslandBuilder* islands;
    std::span<ContactConstraint* const> constraints;  ///< indexed as in IslandBuilder::Finalize
    SolverBody* bodies;                               ///< solver index = island body index + 1
    SolverPose* poses;
    std::uint32_t solver_body_count;
    float dt;
    const PhysicsSettings* settings;
  };

  /// Starts a step's solve with `job_count` jobs per stage.
  void BeginStep(const Input& input, std::uint32_t job_count);

  /// Orders island `island`'s constraints and splits it if it is large (one island per call, any job).
  void PrepareIsland(std::uint32_t island, std::uint32_t job);
  /// After every PrepareIsland: solves islands and split-island batches until none is left (one per job).
  void SolveJob(std::uint32_t job);

  /// Deepest penetration the last position pass saw (m, <= 0), once every SolveJob has returned.
  float deepest_penetration() const;
  std::uint32_t split_island_count() const { return large_count_; }
  /// Splits the largest split island used (0 if none), for profiles.
  std::uint32_t max_split_count() const;

 private:
  enum class RoundKind { kSetup, kWarmStart, kVelocity, kIntegrate, kBounce, kPosition };
  struct Round {
    RoundKind kind;
    std::uint32_t split;
    int iteration;
  };
  struct SplitIsland {
    std::uint32_t island = 0;
    IslandSplits splits;
    ContactBundle** bundles = nullptr;  // the parallel splits' bundles, split after split
    std::uint32_t bundle_begin[IslandSplits::kMaxSplits + 1] = {};
    std::uint32_t bundle_count = 0;
    ContactConstraint* const* sequential = nullptr;  // the sequential split's constraints
    SolverContact** sequential_contacts = nullptr;   // ...as set up in the setup round
    std::uint32_t sequential_count = 0;
    bool has_bounce = false;
    std::uint32_t round_count = 0;
    std::atomic<std::uint64_t> status{0};  // round << 32 | next unclaimed item
    std::atomic<std::uint32_t> processed{0};
  };
  struct alignas(64) JobState {
    BlockArena arena;  // set-up contacts and bundles, kept until the next step
    std::vector<std::uint8_t> split_of;
    std::vector<ContactConstraint*> scratch;
    float deepest = 0.0f;
  };

  void SolveSmallIsland(std::uint32_t island, JobState& job);
  bool TryRunBatch(SplitIsland& split, JobState& job);
  Round Describe(const SplitIsland& split, std::uint32_t round) const;
  std::uint32_t RoundItems(const SplitIsland& split, const Round& round) const;
  void RunBatch(SplitIsland& split, const Round& round, std::uint32_t begin, std::uint32_t end,
                JobState& job);
  bool IsSequential(const SplitIsland& split, std::uint32_t s) const {
    return split.splits.last_is_sequential && s + 1 == split.splits.split_count;
  }
  void Integrate(std::uint32_t island_body) const;
  std::span<ContactConstraint*> OrderedConstraints(std::uint32_t island);

  Input input_{};
  std::vector<ContactConstraint*> ordered_;  // every island's constraints, island after island
  std::vector<std::uint32_t> body_masks_;    // LargeIslandSplitter scratch, by solver body
  std::unique_ptr<SplitIsland[]> large_;
  std::uint32_t large_capacity_ = 0;
  std::uint32_t large_count_ = 0;
  std::vector<std::uint32_t> large_of_island_;  // island -> index in large_, or kNotLarge
  std::vector<std::uint32_t> small_islands_;
  std::atomic<std::uint32_t> next_small_{0};
  std::atomic<std::uint32_t> large_finished_{0};
  std::vector<JobState> jobs_;
};

}  // namespace strata
