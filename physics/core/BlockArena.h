// BlockArena and BlockPool: bump allocation over blocks that are kept between uses. Each step job bumps
// through its own arena (no shared allocator in the hot path); arenas take their blocks from one pool and
// give them back on Reset (Recycle keeps one), so a steady world allocates nothing however the jobs split
// the work, and memory follows the total the step needs, not each job's largest share. Addresses never move,
// so pointers into an arena stay valid until its Reset. An arena has one owner thread at a time; the pool is
// thread-safe (a mutex, taken once per block).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <type_traits>

namespace strata {

/// Blocks for BlockArenas, shared by any number of them.
class BlockPool {
 public:
  /// A block: its header sits at the start, the usable bytes follow.
  struct Block {
    Block* next = nullptr;
    std::size_t size = 0;         ///< usable bytes
    std::byte* memory = nullptr;  ///< what was allocated (the block sits at its colour offset in it)
    std::byte* data() { return reinterpret_cast<std::byte*>(this) + kHeaderBytes; }
  };
  static constexpr std::size_t kAlignment = 64;
  static constexpr std::size_t kHeaderBytes = kAlignment;  // keeps data() aligned
  /// Blocks start at different offsets within a page ("colours", kColourStride apart): each step writes its
  /// blocks while it reads the ones it wrote a step before (the body-pair cache's two halves), and blocks
  /// that all started at the same page offset put those reads on the writes' cache sets and made the loads
  /// wait on unrelated stores with the same low address bits (4K aliasing).
  static constexpr std::size_t kColourStride = 5 * kAlignment;
  static constexpr std::size_t kColours = 4096 / kAlignment;

  explicit BlockPool(std::size_t block_bytes = 256 * 1024) : block_bytes_(block_bytes) {}
  ~BlockPool();
  BlockPool(const BlockPool&) = delete;
  BlockPool& operator=(const BlockPool&) = delete;

  /// A block with at least `bytes` usable: a kept one when one is large enough, else a new one (of the
  /// standard size, or exactly this size when that is larger).
  Block* Take(std::size_t bytes);
  /// Gives back a chain of blocks linked through `next`.
  void Give(Block* chain);
  /// Makes standard blocks until the pool has made at least `blocks` in all (in use or kept).
  void EnsureBlocks(std::size_t blocks);
  std::size_t block_bytes() const { return block_bytes_; }
  /// Bytes of every block this pool has made, in use or kept.
  std::size_t bytes_reserved() const;

 private:
  Block* MakeBlock(std::size_t size);

  const std::size_t block_bytes_;
  mutable std::mutex mutex_;
  Block* free_ = nullptr;
  std::size_t bytes_reserved_ = 0;
  std::size_t next_colour_ = 0;
  // Changed under mutex_; read without it by EnsureBlocks, which a steady step calls to learn it has enough.
  std::atomic<std::size_t> standard_blocks_{0};
};

/// Bump allocator over pool blocks.
class BlockArena {
 public:
  /// An arena with a pool of its own.
  BlockArena() : own_pool_(std::make_unique<BlockPool>()), pool_(own_pool_.get()) {}
  /// An arena that shares `pool` (which must outlive it).
  explicit BlockArena(BlockPool& pool) : pool_(&pool) {}
  ~BlockArena() { Reset(); }
  BlockArena(BlockArena&& other) noexcept { *this = std::move(other); }
  BlockArena& operator=(BlockArena&& other) noexcept;
  BlockArena(const BlockArena&) = delete;
  BlockArena& operator=(const BlockArena&) = delete;

  /// Uses `pool` from now on (gives its blocks back to the old one first).
  void SetPool(BlockPool& pool);

  /// `bytes` of uninitialised memory aligned to `alignment` (a power of two, at most 64).
  void* Allocate(std::size_t bytes, std::size_t alignment = alignof(std::max_align_t)) {
    std::size_t offset = (used_ + alignment - 1) & ~(alignment - 1);
    if (current_ == nullptr || offset + bytes > current_->size) {
      BlockPool::Block* block = pool_->Take(bytes);
      block->next = current_;
      current_ = block;
      offset = 0;
    }
    used_ = offset + bytes;
    bytes_in_use_ += bytes;
    return current_->data() + offset;
  }

  /// Room for `count` objects of trivially destructible T (constructed by the caller).
  template <class T>
  T* AllocateArray(std::size_t count) {
    static_assert(std::is_trivially_destructible_v<T>, "Reset does not run destructors");
    return static_cast<T*>(Allocate(sizeof(T) * count, alignof(T)));
  }

  /// Forgets everything allocated and gives the blocks back to the pool.
  void Reset() {
    if (current_ != nullptr) pool_->Give(current_);
    current_ = nullptr;
    used_ = 0;
    bytes_in_use_ = 0;
  }

  /// Forgets everything allocated, as Reset, but keeps the newest block when it has the pool's standard size:
  /// an arena refilled every step then takes no block from the pool (and its mutex) while one is enough.
  void Recycle() {
    if (current_ != nullptr && current_->size == pool_->block_bytes()) {
      pool_->Give(current_->next);
      current_->next = nullptr;
    } else {
      if (current_ != nullptr) pool_->Give(current_);
      current_ = nullptr;
    }
    used_ = 0;
    bytes_in_use_ = 0;
  }

  std::size_t bytes_in_use() const { return bytes_in_use_; }

 private:
  std::unique_ptr<BlockPool> own_pool_;
  BlockPool* pool_ = nullptr;
  BlockPool::Block* current_ = nullptr;  // newest block; older ones follow through next
  std::size_t used_ = 0;
  std::size_t bytes_in_use_ = 0;
};

}  // namespace strata
