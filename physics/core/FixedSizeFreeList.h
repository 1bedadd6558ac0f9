// FixedSizeFreeList: a lock-free pool of at most `capacity` objects addressed by 32-bit index, allocated
// in blocks on first use so a small world pays for a small pool. Reserve, Allocate and Free may be called
// from any thread at once. Freed objects are poisoned in ASan builds, so a late reader is caught.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#endif

namespace strata {

/// Pool of T (default-constructible) with a Treiber-stack free list; indices stay valid until freed.
template <class T>
class FixedSizeFreeList {
 public:
  static constexpr std::uint32_t kInvalidIndex = 0xffffffffu;
  static constexpr std::uint32_t kBlockSize = 1024;

  explicit FixedSizeFreeList(std::uint32_t capacity)
      : capacity_(capacity),
        available_(capacity),
        blocks_((capacity + kBlockSize - 1) / kBlockSize),
        next_free_(capacity) {
    for (auto& block : blocks_) block.store(nullptr, std::memory_order_relaxed);
  }
  ~FixedSizeFreeList() {
    for (auto& block : blocks_) {
      T* objects = block.load(std::memory_order_relaxed);
      if (objects == nullptr) continue;
      Unpoison(objects, kBlockSize);
      delete[] objects;
    }
  }
  FixedSizeFreeList(const FixedSizeFreeList&) = delete;
  FixedSizeFreeList& operator=(const FixedSizeFreeList&) = delete;

  std::uint32_t capacity() const { return capacity_; }
  /// Objects neither allocated nor reserved.
  std::int64_t available() const { return available_.load(std::memory_order_relaxed); }
  /// Objects handed out and not yet freed.
  std::uint32_t in_use() const { return in_use_.load(std::memory_order_relaxed); }
  /// Bytes of the blocks allocated so far (the pool never shrinks).
  std::size_t reserved_bytes() const {
    return static_cast<std::size_t>(blocks_allocated_.load(std::memory_order_relaxed)) * kBlockSize *
           sizeof(T);
  }

  /// Promises `count` later Allocate calls will succeed; false (nothing reserved) when the pool is short.
  bool Reserve(std::uint32_t count) {
    std::int64_t available = available_.load(std::memory_order_relaxed);
    do {
      if (available < count) return false;
    } while (!available_.compare_exchange_weak(available, available - count, std::memory_order_relaxed));
    return true;
  }
  /// Gives back reservations that were not used.
  void Unreserve(std::uint32_t count) { available_.fetch_add(count, std::memory_order_relaxed); }

  /// Takes one object out of a reservation. Its contents are whatever the last user left.
  std::uint32_t Allocate() {
    std::uint32_t index = PopFree();
    if (index == kInvalidIndex) index = first_unused_.fetch_add(1, std::memory_order_relaxed);
    EnsureBlock(index / kBlockSize);
    Unpoison(&Get(index), 1);
    in_use_.fetch_add(1, std::memory_order_relaxed);
    return index;
  }

  /// Returns an object to the pool; nobody may read it afterwards.
  void Free(std::uint32_t index) {
    Poison(&Get(index), 1);
    in_use_.fetch_sub(1, std::memory_order_relaxed);
    PushFree(index);
    available_.fetch_add(1, std::memory_order_relaxed);
  }

  T& Get(std::uint32_t index) {
    return blocks_[index / kBlockSize].load(std::memory_order_acquire)[index % kBlockSize];
  }
  const T& Get(std::uint32_t index) const {
    return blocks_[index / kBlockSize].load(std::memory_order_acquire)[index % kBlockSize];
  }

 private:
  // Head of the free stack: index in the low 32 bits, a change counter in the high 32 against ABA.
  static std::uint64_t Pack(std::uint32_t index, std::uint32_t tag) {
    return static_cast<std::uint64_t>(tag) << 32 | index;
  }

  std::uint32_t PopFree() {
    std::uint64_t head = free_head_.load(std::memory_order_acquire);
    for (;;) {
      const auto index = static_cast<std::uint32_t>(head);
      if (index == kInvalidIndex) return kInvalidIndex;
      const std::uint32_t next = next_free_[index].load(std::memory_order_relaxed);
      if (free_head_.compare_exchange_weak(head, Pack(next, static_cast<std::uint32_t>(head >> 32) + 1),
                                           std::memory_order_acquire))
        return index;
    }
  }

  void PushFree(std::uint32_t index) {
    std::uint64_t head = free_head_.load(std::memory_order_relaxed);
    for (;;) {
      next_free_[index].store(static_cast<std::uint32_t>(head), std::memory_order_relaxed);
      if (free_head_.compare_exchange_weak(head, Pack(index, static_cast<std::uint32_t>(head >> 32) + 1),
                                           std::memory_order_release))
        return;
    }
  }

  void EnsureBlock(std::uint32_t block) {
    if (blocks_[block].load(std::memory_order_acquire) != nullptr) return;
    T* fresh = new T[kBlockSize];
    Poison(fresh, kBlockSize);
    T* expected = nullptr;
    if (blocks_[block].compare_exchange_strong(expected, fresh, std::memory_order_acq_rel)) {
      blocks_allocated_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    Unpoison(fresh, kBlockSize);
    delete[] fresh;  // another thread installed the block first
  }

  static void Poison([[maybe_unused]] T* objects, [[maybe_unused]] std::size_t count) {
#if defined(__SANITIZE_ADDRESS__)
    ASAN_POISON_MEMORY_REGION(objects, count * sizeof(T));
#endif
  }
  static void Unpoison([[maybe_unused]] T* objects, [[maybe_unused]] std::size_t count) {
#if defined(__SANITIZE_ADDRESS__)
    ASAN_UNPOISON_MEMORY_REGION(objects, count * sizeof(T));
#endif
  }

  const std::uint32_t capacity_;
  std::atomic<std::int64_t> available_;
  std::atomic<std::uint32_t> first_unused_{0};
  std::atomic<std::uint32_t> in_use_{0};
  std::atomic<std::uint32_t> blocks_allocated_{0};
  std::atomic<std::uint64_t> free_head_{Pack(kInvalidIndex, 0)};
  std::vector<std::atomic<T*>> blocks_;
  std::vector<std::atomic<std::uint32_t>> next_free_;
};

}  // namespace strata
