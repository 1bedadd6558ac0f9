// IndexPairSet against a std::set oracle: every pair added is found in either order, no other pair is.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>

#include "physics/core/IndexPairSet.h"

namespace strata {
namespace {

TEST(IndexPairSet, FindsEveryPairAddedInEitherOrderAndNoOther) {
  std::mt19937 random(7);
  // Indices from a small range (many near misses sharing one index) and from the whole range.
  for (const std::uint32_t range : {40u, 0xfffffffeu}) {
    std::uniform_int_distribution<std::uint32_t> index(0, range);
    IndexPairSet set;
    std::set<std::pair<std::uint32_t, std::uint32_t>> oracle;
    for (int i = 0; i < 300; ++i) {
      const std::uint32_t a = index(random), b = index(random);
      set.Add(a, b);
      oracle.insert({std::min(a, b), std::max(a, b)});
    }
    set.Seal();
    for (const auto& [low, high] : oracle) {
      EXPECT_TRUE(set.Contains(low, high)) << low << " " << high;
      EXPECT_TRUE(set.Contains(high, low)) << low << " " << high;
    }
    int misses = 0;
    for (int i = 0; i < 5000; ++i) {
      const std::uint32_t a = index(random), b = index(random);
      const bool expected = oracle.count({std::min(a, b), std::max(a, b)}) > 0;
      EXPECT_EQ(set.Contains(a, b), expected) << a << " " << b;
      misses += expected ? 0 : 1;
    }
    EXPECT_GT(misses, 1000);  // the lookups asked about absent pairs too
  }
}

TEST(IndexPairSet, IsEmptyUntilSealedAndAfterClear) {
  IndexPairSet set;
  EXPECT_FALSE(set.Contains(0, 0));
  set.Add(3, 9);
  set.Add(9, 3);  // the same pair
  EXPECT_FALSE(set.Contains(3, 9));
  set.Seal();
  EXPECT_TRUE(set.Contains(9, 3));
  EXPECT_FALSE(set.Contains(3, 3));
  set.Clear();
  EXPECT_TRUE(set.empty());
  set.Seal();
  EXPECT_FALSE(set.Contains(3, 9));
}

}  // namespace
}  // namespace strata
