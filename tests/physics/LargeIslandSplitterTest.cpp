// The splitter's promise: no two constraints of one parallel split move the same body, every constraint is
// kept exactly once, a parallel split holds its constraints against the fixed body first and then by point
// count, most first, each kind in the island's order, and what no split can take goes last, in island order.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "physics/core/BlockArena.h"
#include "physics/solver/LargeIslandSplitter.h"

namespace strata::test {
namespace {

// Constraints between solver bodies [1, bodies]; body 0 is the fixed body, and some sides are kinematic
// (not moved), which never count as a conflict.
std::vector<ContactConstraint*> MakeConstraints(BlockArena& arena, std::uint32_t bodies, std::uint32_t count,
                                                std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::uint32_t> body(1, bodies);
  std::vector<ContactConstraint*> constraints;
  for (std::uint32_t i = 0; i < count; ++i) {
    auto* c = new (arena.Allocate(sizeof(ContactConstraint), alignof(ContactConstraint))) ContactConstraint{};
    c->body_a = body(random);
    c->body_b = random() % 5 == 0 ? 0u : body(random);
    if (c->body_b == c->body_a) c->body_b = c->body_a % bodies + 1;  // a constraint joins two bodies
    c->dynamic_a = true;
    c->dynamic_b = c->body_b != 0 && random() % 7 != 0;
    c->point_count = static_cast<std::uint8_t>(1 + random() % ContactManifold::kMaxPoints);
    constraints.push_back(c);
  }
  return constraints;
}

// A parallel split's order of kinds: against the fixed body first, then most points first.
std::pair<int, int> KindOrder(const ContactConstraint& c) {
  return {c.body_b == 0 ? 0 : 1, -static_cast<int>(c.point_count)};
}

void ExpectValidSplits(const std::vector<ContactConstraint*>& original,
                       const std::vector<ContactConstraint*>& split, const IslandSplits& splits) {
  // Every constraint exactly once.
  EXPECT_EQ(std::multiset<ContactConstraint*>(original.begin(), original.end()),
            std::multiset<ContactConstraint*>(split.begin(), split.end()));
  ASSERT_EQ(splits.begin[0], 0u);
  ASSERT_EQ(splits.begin[splits.split_count], split.size());
  std::map<ContactConstraint*, std::size_t> position;
  for (std::size_t i = 0; i < original.size(); ++i) position[original[i]] = i;
  for (std::uint32_t s = 0; s < splits.split_count; ++s) {
    const bool sequential = splits.last_is_sequential && s + 1 == splits.split_count;
    std::set<std::uint32_t> moved;
    for (std::uint32_t k = splits.begin[s]; k < splits.begin[s + 1]; ++k) {
      // Kinds in order within a parallel split, and island order within a kind (all of the sequential split).
      if (k > splits.begin[s]) {
        ContactConstraint* before = split[k - 1];
        ContactConstraint* now = split[k];
        if (sequential || KindOrder(*before) == KindOrder(*now)) {
          EXPECT_LT(position[before], position[now]);
        } else {
          EXPECT_LT(KindOrder(*before), KindOrder(*now)) << "split " << s << " at " << k;
        }
      }
      if (sequential) continue;
      const ContactConstraint& c = *split[k];
      if (c.dynamic_a) {
        EXPECT_TRUE(moved.insert(c.body_a).second) << "split " << s << " moves body " << c.body_a << " twice";
      }
      if (c.dynamic_b) {
        EXPECT_TRUE(moved.insert(c.body_b).second) << "split " << s << " moves body " << c.body_b << " twice";
      }
    }
    if (!sequential) {
      EXPECT_GE(splits.begin[s + 1] - splits.begin[s], LargeIslandSplitter::kMinSplitSize);
    }
  }
}

TEST(LargeIslandSplitter, ParallelSplitsNeverMoveABodyTwice) {
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    BlockArena arena;
    const std::vector<ContactConstraint*> original = MakeConstraints(arena, 400, 2000, seed);
    std::vector<ContactConstraint*> split = original;
    std::vector<std::uint32_t> masks(401, 0);
    std::vector<std::uint8_t> split_of;
    std::vector<ContactConstraint*> scratch;
    const IslandSplits splits = LargeIslandSplitter::Split(split, masks.data(), split_of, scratch);
    EXPECT_GT(splits.split_count, 2u);
    ExpectValidSplits(original, split, splits);
  }
}

TEST(LargeIslandSplitter, ABodyInEveryConstraintEndsInTheSequentialSplit) {
  // A hub touched by 100 constraints can be in at most 31 parallel splits; the rest are solved in order.
  BlockArena arena;
  std::vector<ContactConstraint*> original;
  for (std::uint32_t i = 0; i < 100; ++i) {
    auto* c = new (arena.Allocate(sizeof(ContactConstraint), alignof(ContactConstraint))) ContactConstraint{};
    c->body_a = 1;
    c->body_b = 2 + i;
    c->dynamic_a = c->dynamic_b = true;
    original.push_back(c);
  }
  std::vector<ContactConstraint*> split = original;
  std::vector<std::uint32_t> masks(200, 0);
  std::vector<std::uint8_t> split_of;
  std::vector<ContactConstraint*> scratch;
  const IslandSplits splits = LargeIslandSplitter::Split(split, masks.data(), split_of, scratch);
  // Every parallel split would hold one constraint (too few to be worth a hand-over): all go sequential, in
  // island order.
  EXPECT_EQ(splits.split_count, 1u);
  EXPECT_TRUE(splits.last_is_sequential);
  EXPECT_EQ(split, original);
}

TEST(LargeIslandSplitter, FixedAndKinematicSidesNeverConflict) {
  // Every constraint touches the fixed body and a kinematic body, plus a body of its own: one split.
  BlockArena arena;
  std::vector<ContactConstraint*> original;
  for (std::uint32_t i = 0; i < 64; ++i) {
    auto* c = new (arena.Allocate(sizeof(ContactConstraint), alignof(ContactConstraint))) ContactConstraint{};
    c->body_a = 10 + i;
    c->body_b = i % 2 ? 0u : 5u;
    c->dynamic_a = true;
    c->dynamic_b = false;
    original.push_back(c);
  }
  std::vector<ContactConstraint*> split = original;
  std::vector<std::uint32_t> masks(100, 0);
  std::vector<std::uint8_t> split_of;
  std::vector<ContactConstraint*> scratch;
  const IslandSplits splits = LargeIslandSplitter::Split(split, masks.data(), split_of, scratch);
  EXPECT_EQ(splits.split_count, 1u);
  EXPECT_FALSE(splits.last_is_sequential);
  // Those against the fixed body first (odd i), then those against the kinematic one, each in island order.
  std::vector<ContactConstraint*> expected;
  for (std::uint32_t i = 1; i < 64; i += 2) expected.push_back(original[i]);
  for (std::uint32_t i = 0; i < 64; i += 2) expected.push_back(original[i]);
  EXPECT_EQ(split, expected);
}

}  // namespace
}  // namespace strata::test
