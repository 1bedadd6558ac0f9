// BoundedQueue: a fixed-capacity lock-free multi-producer multi-consumer FIFO (a sequence number per cell,
// after Dmitry Vyukov's bounded MPMC queue). Any thread may push and pop at once; a full queue refuses
// the push instead of allocating, so the caller decides what to do (the thread pool runs the job inline).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>

namespace strata {

/// Lock-free FIFO of at most `capacity` (a power of two) trivially copyable items.
template <class T>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity) : mask_(capacity - 1), cells_(new Cell[capacity]) {
    for (std::size_t i = 0; i < capacity; ++i) cells_[i].sequence.store(i, std::memory_order_relaxed);
  }

  /// False when the queue is full.
  bool TryPush(const T& item) {
    std::size_t position = push_position_.load(std::memory_order_relaxed);
    while (true) {
      Cell& cell = cells_[position & mask_];
      const std::size_t sequence = cell.sequence.load(std::memory_order_acquire);
      const auto lag = static_cast<std::ptrdiff_t>(sequence) - static_cast<std::ptrdiff_t>(position);
      if (lag == 0) {
        if (push_position_.compare_exchange_weak(position, position + 1, std::memory_order_relaxed)) {
          cell.item = item;
          cell.sequence.store(position + 1, std::memory_order_release);
          return true;
        }
      } else if (lag < 0) {
        return false;  // the cell still holds an item from one lap ago
      } else {
        position = push_position_.load(std::memory_order_relaxed);
      }
    }
  }

  /// False when the queue is empty.
  bool TryPop(T& item) {
    std::size_t position = pop_position_.load(std::memory_order_relaxed);
    while (true) {
      Cell& cell = cells_[position & mask_];
      const std::size_t sequence = cell.sequence.load(std::memory_order_acquire);
      const auto lag = static_cast<std::ptrdiff_t>(sequence) - static_cast<std::ptrdiff_t>(position + 1);
      if (lag == 0) {
        if (pop_position_.compare_exchange_weak(position, position + 1, std::memory_order_relaxed)) {
          item = cell.item;
          cell.sequence.store(position + mask_ + 1, std::memory_order_release);
          return true;
        }
      } else if (lag < 0) {
        return false;
      } else {
        position = pop_position_.load(std::memory_order_relaxed);
      }
    }
  }

  /// A hint: true when a pop would probably find nothing.
  bool LooksEmpty() const {
    return pop_position_.load(std::memory_order_acquire) >= push_position_.load(std::memory_order_acquire);
  }

 private:
  struct Cell {
    std::atomic<std::size_t> sequence;
    T item;
  };
  static constexpr std::size_t kCacheLine = 64;

  const std::size_t mask_;
  std::unique_ptr<Cell[]> cells_;
  alignas(kCacheLine) std::atomic<std::size_t> push_position_{0};
  alignas(kCacheLine) std::atomic<std::size_t> pop_position_{0};
};

}  // namespace strata
