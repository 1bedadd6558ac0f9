#include "physics/solver/LargeIslandSplitter.h"

#include <bit>

namespace strata {

IslandSplits LargeIslandSplitter::Split(std::span<ContactConstraint*> constraints, std::uint32_t* body_masks,
                                        std::vector<std::uint8_t>& split_of,
                                        std::vector<ContactConstraint*>& scratch) {
  constexpr std::uint32_t kSequential = IslandSplits::kMaxSplits - 1;
  split_of.resize(constraints.size());
  std::uint32_t counts[IslandSplits::kMaxSplits] = {};
  // Each body remembers, as one bit per split, which splits already move it; a constraint takes the first
  // split free for both of its dynamic bodies (the fixed body and kinematic ones are never written).
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const ContactConstraint& c = *constraints[k];
    const std::uint32_t used =
        (c.dynamic_a ? body_masks[c.body_a] : 0u) | (c.dynamic_b ? body_masks[c.body_b] : 0u);
    std::uint32_t split = static_cast<std::uint32_t>(std::countr_one(used));
    if (split >= kSequential) {
      split = kSequential;
    } else {
      if (c.dynamic_a) body_masks[c.body_a] |= 1u << split;
      if (c.dynamic_b) body_masks[c.body_b] |= 1u << split;
    }
    split_of[k] = static_cast<std::uint8_t>(split);
    ++counts[split];
  }
  // Moving a small split's constraints to the sequential split keeps every parallel split conflict-free.
  for (std::uint32_t s = 0; s < kSequential; ++s) {
    if (counts[s] == 0 || counts[s] >= kMinSplitSize) continue;
    counts[kSequential] += counts[s];
    counts[s] = 0;
  }
  std::uint32_t target[IslandSplits::kMaxSplits];
  IslandSplits splits;
  std::uint32_t offset = 0;
  for (std::uint32_t s = 0; s < IslandSplits::kMaxSplits; ++s) {
    target[s] = offset;
    if (counts[s] == 0) continue;
    splits.begin[splits.split_count++] = offset;
    offset += counts[s];
  }
  splits.begin[splits.split_count] = offset;
  splits.last_is_sequential = counts[kSequential] > 0;

  // Stable scatter: within a split the island's order is kept, so the result is the same on every run.
  scratch.resize(constraints.size());
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    std::uint32_t split = split_of[k];
    if (counts[split] == 0) split = kSequential;  // a merged small split
    scratch[target[split]++] = constraints[k];
  }
  std::copy(scratch.begin(), scratch.end(), constraints.begin());
  return splits;
}

}  // namespace strata
