// ForEachChunk: the jobs of a stage share a range through one cursor, each item to exactly one job; a stage
// run by one job takes every chunk in order and leaves the cursor alone.
#include "physics/core/ForEachChunk.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

namespace strata::test {
namespace {

TEST(ForEachChunk, OneJobTakesEveryChunkInOrderWithoutTheCursor) {
  for (const std::uint32_t count : {0u, 1u, 63u, 64u, 65u, 200u}) {
    std::atomic<std::uint32_t> next{7};  // a cursor the stage never reset: one job must not read it
    std::vector<std::pair<std::uint32_t, std::uint32_t>> chunks;
    ForEachChunk(next, count, 64, 1,
                 [&](std::uint32_t begin, std::uint32_t end) { chunks.emplace_back(begin, end); });
    EXPECT_EQ(next.load(), 7u) << count;
    ASSERT_EQ(chunks.size(), (count + 63) / 64) << count;
    for (std::size_t k = 0; k < chunks.size(); ++k) {
      const auto begin = static_cast<std::uint32_t>(64 * k);
      EXPECT_EQ(chunks[k].first, begin) << count;
      EXPECT_EQ(chunks[k].second, std::min(begin + 64, count)) << count;
    }
    std::vector<std::uint32_t> items;
    ForEachChunkItem(next, count, 16, 1, [&](std::uint32_t i) { items.push_back(i); });
    ASSERT_EQ(items.size(), count);
    for (std::uint32_t i = 0; i < count; ++i) EXPECT_EQ(items[i], i);
  }
}

TEST(ForEachChunk, ASingleJobOfAWiderStageClaimsEverything) {
  // The other jobs of a wide stage may find nothing left: the first one alone must still cover the range.
  std::atomic<std::uint32_t> next{0};
  std::vector<int> seen(100, 0);
  ForEachChunkItem(next, 100, 8, 4, [&](std::uint32_t i) { ++seen[i]; });
  for (int times : seen) EXPECT_EQ(times, 1);
  EXPECT_GE(next.load(), 100u);
}

TEST(ForEachChunkThreads, EveryItemGoesToExactlyOneJob) {
  constexpr std::uint32_t kJobs = 4, kCount = 10000, kChunk = 7;
  for (int repeat = 0; repeat < 20; ++repeat) {
    std::atomic<std::uint32_t> next{0};
    std::vector<std::atomic<int>> taken(kCount);
    std::vector<std::thread> jobs;
    for (std::uint32_t job = 0; job < kJobs; ++job)
      jobs.emplace_back([&] {
        ForEachChunkItem(next, kCount, kChunk, kJobs,
                         [&](std::uint32_t i) { taken[i].fetch_add(1, std::memory_order_relaxed); });
      });
    for (std::thread& job : jobs) job.join();
    for (std::uint32_t i = 0; i < kCount; ++i) ASSERT_EQ(taken[i].load(), 1) << "item " << i;
  }
}

}  // namespace
}  // namespace strata::test
