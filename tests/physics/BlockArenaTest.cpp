// BlockArena and BlockPool: blocks are reused, not remade, and Recycle keeps exactly one standard block.
#include "physics/core/BlockArena.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <vector>

namespace strata::test {
namespace {

constexpr std::size_t kBlockBytes = 1024;

TEST(BlockArena, RecycleKeepsItsStandardBlockAndReusesItWithoutThePool) {
  BlockPool pool(kBlockBytes);
  BlockArena arena(pool);
  std::byte* const first = static_cast<std::byte*>(arena.Allocate(100));
  const std::size_t reserved = pool.bytes_reserved();
  arena.Recycle();
  EXPECT_EQ(arena.bytes_in_use(), 0u);
  // The kept block stays the arena's: another arena taking a block now gets a new one (after a Reset it
  // would get this one back).
  BlockArena other(pool);
  EXPECT_NE(static_cast<std::byte*>(other.Allocate(100)), first);
  EXPECT_EQ(pool.bytes_reserved(), 2 * reserved);
  for (int step = 0; step < 5; ++step) {
    // The same block, from its start, and no block made.
    EXPECT_EQ(static_cast<std::byte*>(arena.Allocate(100)), first);
    EXPECT_EQ(pool.bytes_reserved(), 2 * reserved);
    arena.Recycle();
  }
}

TEST(BlockArena, RecycleGivesBackEveryBlockButTheNewestStandardOne) {
  BlockPool pool(kBlockBytes);
  BlockArena arena(pool);
  // Three standard blocks in use, the newest last.
  for (int block = 0; block < 3; ++block) arena.Allocate(kBlockBytes);
  const std::size_t reserved = pool.bytes_reserved();
  arena.Recycle();
  // Two went back: a second arena takes both without a new block, the third needs one.
  BlockArena other(pool);
  other.Allocate(kBlockBytes);
  other.Allocate(kBlockBytes);
  EXPECT_EQ(pool.bytes_reserved(), reserved);
  other.Allocate(kBlockBytes);
  EXPECT_GT(pool.bytes_reserved(), reserved);
}

TEST(BlockArena, RecycleGivesBackAnOversizeBlockAndResetGivesBackAll) {
  BlockPool pool(kBlockBytes);
  BlockArena arena(pool);
  arena.Allocate(4 * kBlockBytes);  // a block of its own size, not kept
  const std::size_t reserved = pool.bytes_reserved();
  arena.Recycle();
  BlockArena other(pool);
  other.Allocate(4 * kBlockBytes);
  EXPECT_EQ(pool.bytes_reserved(), reserved);  // the oversize block came back and was reused
  other.Reset();
  arena.Allocate(4 * kBlockBytes);
  EXPECT_EQ(pool.bytes_reserved(), reserved);
}

TEST(BlockArena, BlocksStartAtEveryCacheLineOfAPageInTurn) {
  // The step writes this step's blocks while it reads last step's: blocks at one page offset would share
  // cache sets and alias in the store buffer. Each block takes the same memory whatever its offset.
  BlockPool pool(kBlockBytes);
  std::set<std::uintptr_t> offsets;
  std::vector<BlockPool::Block*> blocks;
  std::size_t per_block = 0;
  for (std::size_t k = 0; k < BlockPool::kColours; ++k) {
    blocks.push_back(pool.Take(kBlockBytes));
    if (k == 0) per_block = pool.bytes_reserved();
    offsets.insert(reinterpret_cast<std::uintptr_t>(blocks.back()->data()) % 4096);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blocks.back()->data()) % BlockPool::kAlignment, 0u);
    EXPECT_EQ(pool.bytes_reserved(), (k + 1) * per_block);
  }
  EXPECT_EQ(offsets.size(), BlockPool::kColours);
  for (BlockPool::Block* block : blocks) pool.Give(block);
}

}  // namespace
}  // namespace strata::test
