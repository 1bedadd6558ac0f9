// LargeIslandSplitter: spreads the constraints of one large island over splits (a greedy graph colouring,
// as in Jolt's LargeIslandSplitter after Chen et al., "High-Performance Physical Simulations on
// Next-Generation Architecture with Many Cores"): no two constraints of one parallel split move the same
// body, so a split's constraints can be solved by many threads at once in any order with the same result.
// Constraints that find no free split, and splits too small to be worth a hand-over between threads, go to
// one sequential split solved last by a single thread. Pure function of its input; any thread, one island
// each.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "physics/constraints/ContactConstraint.h"

namespace strata {

/// Where each split of an island starts in its (reordered) constraint list.
struct IslandSplits {
  static constexpr std::uint32_t kMaxSplits = 32;  ///< parallel splits + the sequential one
  std::uint32_t split_count = 0;                   ///< non-empty splits, the sequential one last if present
  std::uint32_t begin[kMaxSplits + 1] = {};        ///< split s is [begin[s], begin[s + 1])
  bool last_is_sequential = false;

  /// Makes this one sequential split of `count` constraints (none if `count` is 0). Readers look at begin[]
  /// only up to begin[split_count], so the rest is left as it was: clearing all of it each step (a string
  /// store) cost more than the rest of a small group's preparation.
  void SetSequential(std::uint32_t count) {
    split_count = count > 0 ? 1 : 0;
    begin[0] = 0;
    begin[1] = count;
    last_is_sequential = count > 0;
  }
};

/// Greedy colouring of a large island's constraints.
class LargeIslandSplitter {
 public:
  /// Islands with at least this many constraints are split.
  static constexpr std::uint32_t kMinConstraintsToSplit = 128;
  /// Parallel splits with fewer constraints than this join the sequential split.
  static constexpr std::uint32_t kMinSplitSize = 8;

  /// Reorders `constraints` split by split and says where each split starts. `body_masks` is scratch indexed
  /// by solver body and must be zero for every dynamic body the constraints name; they are left non-zero.
  static IslandSplits Split(std::span<ContactConstraint*> constraints, std::uint32_t* body_masks,
                            std::vector<std::uint8_t>& split_of, std::vector<ContactConstraint*>& scratch);
};

}  // namespace strata
