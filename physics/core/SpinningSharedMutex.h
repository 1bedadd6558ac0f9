// SpinningSharedMutex: a reader/writer mutex that retries briefly before sleeping. Body locks are held for
// well under a microsecond, while a sleep/wake round trip through the kernel costs several: a short spin
// turns most contended waits into a few hundred nanoseconds. Meets the standard SharedMutex requirements.
#pragma once

#include <atomic>
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace strata {

/// One atomic word (a writer bit and a reader count), one cache line each so that neighbouring body locks
/// taken by different threads do not share a line. Uncontended lock and unlock are one atomic operation
/// each (the step takes and releases every body lock twice a step); a waiter spins, then sleeps on the word.
/// Readers are not held back by a waiting writer, as with glibc's default rwlock.
class alignas(64) SpinningSharedMutex {
 public:
  void lock() { Acquire(&SpinningSharedMutex::try_lock); }
  bool try_lock() {
    std::uint32_t expected = 0;
    return state_.compare_exchange_strong(expected, kWriter, std::memory_order_acquire,
                                          std::memory_order_relaxed);
  }
  void unlock() {
    state_.store(0, std::memory_order_seq_cst);
    WakeSleepers();
  }

  void lock_shared() { Acquire(&SpinningSharedMutex::try_lock_shared); }
  bool try_lock_shared() {
    std::uint32_t state = state_.load(std::memory_order_relaxed);
    while ((state & kWriter) == 0) {
      if (state_.compare_exchange_weak(state, state + 1, std::memory_order_acquire,
                                       std::memory_order_relaxed))
        return true;
    }
    return false;
  }
  void unlock_shared() {
    // Only the last reader out can let a writer in, so only it looks for sleepers.
    if (state_.fetch_sub(1, std::memory_order_seq_cst) == 1) WakeSleepers();
  }

 private:
  static constexpr std::uint32_t kWriter = 1u << 31;
  // About a microsecond of retrying on current x86 cores.
  static constexpr int kSpins = 64;

  // Retries `try_acquire` with a pause between tries, sleeping on the word once the spin is spent.
  void Acquire(bool (SpinningSharedMutex::*try_acquire)()) {
    for (int attempt = 0; !(this->*try_acquire)(); ++attempt) {
      if (attempt >= kSpins)
        Sleep();
      else
        Pause();
    }
  }

  static void Pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
  }

  // Registers as a sleeper before looking at the word again: an unlock either sees the sleeper (and wakes
  // it) or happened before the look (and the wait returns at once, the word having changed).
  void Sleep() {
    sleepers_.fetch_add(1, std::memory_order_seq_cst);
    const std::uint32_t state = state_.load(std::memory_order_seq_cst);
    if (state != 0) state_.wait(state, std::memory_order_relaxed);
    sleepers_.fetch_sub(1, std::memory_order_relaxed);
  }
  void WakeSleepers() {
    if (sleepers_.load(std::memory_order_seq_cst) != 0) state_.notify_all();
  }

  std::atomic<std::uint32_t> state_{0};     // kWriter, or the number of readers
  std::atomic<std::uint32_t> sleepers_{0};  // threads blocked in Sleep()
};

}  // namespace strata
