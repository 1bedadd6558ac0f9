// SpinningSharedMutex: a reader/writer mutex that retries briefly before sleeping. Body locks are held for
// well under a microsecond, while a sleep/wake round trip through the kernel costs several: a short spin
// turns most contended waits into a few hundred nanoseconds. Meets the standard SharedMutex requirements.
#pragma once

#include <shared_mutex>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace strata {

/// std::shared_mutex with a bounded spin in front of each blocking acquire.
class SpinningSharedMutex {
 public:
  void lock() {
    for (int attempt = 0; attempt < kSpins; ++attempt) {
      if (mutex_.try_lock()) return;
      Pause();
    }
    mutex_.lock();
  }
  bool try_lock() { return mutex_.try_lock(); }
  void unlock() { mutex_.unlock(); }

  void lock_shared() {
    for (int attempt = 0; attempt < kSpins; ++attempt) {
      if (mutex_.try_lock_shared()) return;
      Pause();
    }
    mutex_.lock_shared();
  }
  bool try_lock_shared() { return mutex_.try_lock_shared(); }
  void unlock_shared() { mutex_.unlock_shared(); }

 private:
  // About a microsecond of retrying on current x86 cores.
  static constexpr int kSpins = 64;

  static void Pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
  }

  std::shared_mutex mutex_;
};

}  // namespace strata
