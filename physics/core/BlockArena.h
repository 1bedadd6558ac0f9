// BlockArena: a bump allocator over blocks it keeps between uses. Reset rewinds it without freeing, so a
// step that needs no more than an earlier one allocates nothing; addresses never move (blocks are never
// reallocated), so pointers into it stay valid until Reset. One owner thread at a time (each step job
// has its own arena); what it hands out may be read by any thread once the writer's stage has finished.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

namespace strata {

/// Bump allocator over retained blocks.
class BlockArena {
 public:
  explicit BlockArena(std::size_t block_bytes = 256 * 1024) : block_bytes_(block_bytes) {}
  BlockArena(BlockArena&&) noexcept = default;
  BlockArena& operator=(BlockArena&&) noexcept = default;

  /// `bytes` of uninitialised memory aligned to `alignment` (a power of two, at most 64).
  void* Allocate(std::size_t bytes, std::size_t alignment = alignof(std::max_align_t)) {
    std::size_t offset = (used_ + alignment - 1) & ~(alignment - 1);
    if (current_ >= blocks_.size() || offset + bytes > blocks_[current_].size) {
      NextBlock(bytes + alignment);
      offset = 0;
    }
    used_ = offset + bytes;
    bytes_in_use_ += bytes;
    return blocks_[current_].data.get() + offset;
  }

  /// Room for `count` objects of trivially destructible T (constructed by the caller).
  template <class T>
  T* AllocateArray(std::size_t count) {
    static_assert(std::is_trivially_destructible_v<T>, "Reset does not run destructors");
    return static_cast<T*>(Allocate(sizeof(T) * count, alignof(T)));
  }

  /// Forgets everything allocated; keeps the blocks for the next use.
  void Reset() {
    current_ = 0;
    used_ = 0;
    bytes_in_use_ = 0;
  }

  std::size_t bytes_in_use() const { return bytes_in_use_; }
  std::size_t bytes_reserved() const {
    std::size_t total = 0;
    for (const Block& block : blocks_) total += block.size;
    return total;
  }

 private:
  static constexpr std::size_t kBlockAlignment = 64;
  struct AlignedDelete {
    void operator()(std::byte* bytes) const { ::operator delete[](bytes, std::align_val_t(kBlockAlignment)); }
  };
  struct Block {
    std::unique_ptr<std::byte[], AlignedDelete> data;
    std::size_t size = 0;
  };

  void NextBlock(std::size_t at_least) {
    if (current_ < blocks_.size() && used_ > 0) ++current_;
    // Reuse the next kept block if it is big enough; a larger request gets a block of its own size.
    while (current_ < blocks_.size() && blocks_[current_].size < at_least) ++current_;
    if (current_ >= blocks_.size()) {
      const std::size_t size = at_least > block_bytes_ ? at_least : block_bytes_;
      auto* bytes = static_cast<std::byte*>(::operator new[](size, std::align_val_t(kBlockAlignment)));
      blocks_.push_back({std::unique_ptr<std::byte[], AlignedDelete>(bytes), size});
      current_ = blocks_.size() - 1;
    }
    used_ = 0;
  }

  std::size_t block_bytes_;
  std::vector<Block> blocks_;
  std::size_t current_ = 0;
  std::size_t used_ = 0;
  std::size_t bytes_in_use_ = 0;
};

}  // namespace strata
