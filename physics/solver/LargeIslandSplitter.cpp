#include "physics/solver/LargeIslandSplitter.h"

#include <algorithm>
#include <bit>

#include "physics/narrowphase/ContactManifold.h"

namespace strata {

namespace {

// Within a parallel split the constraints share no body that moves, so their order does not change the
// result; the solver packs consecutive ones into SIMD bundles. Ordered by kind, a bundle's lanes are alike:
// against the fixed body first (those bundles skip B's side), and by point count, most first (a bundle
// solves as many points in every lane as its fullest lane has).
constexpr std::uint32_t kKinds = 2 * ContactManifold::kMaxPoints;

std::uint32_t KindOf(const ContactConstraint& c) {
  const std::uint32_t points = std::clamp<std::uint32_t>(c.point_count, 1, ContactManifold::kMaxPoints);
  return (c.body_b == 0 ? 0 : ContactManifold::kMaxPoints) + (ContactManifold::kMaxPoints - points);
}

}  // namespace

IslandSplits LargeIslandSplitter::Split(std::span<ContactConstraint*> constraints, std::uint32_t* body_masks,
                                        std::vector<std::uint8_t>& split_of,
                                        std::vector<ContactConstraint*>& scratch) {
  constexpr std::uint32_t kSequential = IslandSplits::kMaxSplits - 1;
  split_of.resize(constraints.size());
  std::uint32_t counts[IslandSplits::kMaxSplits] = {};
  std::uint32_t kind_counts[IslandSplits::kMaxSplits][kKinds] = {};
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
    ++kind_counts[split][KindOf(c)];
  }
  // Moving a small split's constraints to the sequential split keeps every parallel split conflict-free.
  for (std::uint32_t s = 0; s < kSequential; ++s) {
    if (counts[s] == 0 || counts[s] >= kMinSplitSize) continue;
    counts[kSequential] += counts[s];
    counts[s] = 0;
  }
  // Where each split's constraints of each kind go. The sequential split keeps the island's order (one kind
  // for all): it is solved one constraint after another.
  std::uint32_t target[IslandSplits::kMaxSplits][kKinds];
  IslandSplits splits;
  std::uint32_t offset = 0;
  for (std::uint32_t s = 0; s < IslandSplits::kMaxSplits; ++s) {
    std::uint32_t kind_offset = offset;
    for (std::uint32_t kind = 0; kind < kKinds; ++kind) {
      target[s][kind] = s == kSequential ? offset : kind_offset;
      kind_offset += kind_counts[s][kind];
    }
    if (counts[s] == 0) continue;
    splits.begin[splits.split_count++] = offset;
    offset += counts[s];
  }
  splits.begin[splits.split_count] = offset;
  splits.last_is_sequential = counts[kSequential] > 0;

  // Stable scatter: within a split's kind the island's order is kept, so the layout is the same on every run.
  scratch.resize(constraints.size());
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    std::uint32_t split = split_of[k];
    if (counts[split] == 0) split = kSequential;  // a merged small split
    const std::uint32_t kind = split == kSequential ? 0 : KindOf(*constraints[k]);
    scratch[target[split][kind]++] = constraints[k];
  }
  std::copy(scratch.begin(), scratch.end(), constraints.begin());
  return splits;
}

}  // namespace strata
