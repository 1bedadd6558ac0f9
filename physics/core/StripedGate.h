// StripedGate: many threads pass at once, each touching only its own cache line, until one thread
// closes the gate; Close waits for those inside to leave and keeps new ones out until Open. For paths that
// run all the time (moving bodies) next to a rare exclusive one (rebuilding a tree). Thread-safe.
#pragma once

#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>

namespace strata {

/// A reader/writer gate with per-thread-stripe reader counts (a "big reader" lock).
class StripedGate {
 public:
  /// Passes the gate (waits only while it is closed). Pair with Leave on the same thread.
  void Enter() {
    const std::size_t index = ThreadStripe();
    // The first pass of a stripe marks it, so Close waits on the stripes in use rather than all 64 (in a
    // one-thread world that was most of a small tree's rebuild). seq_cst, as the count and the flag: a
    // closer that sees no mark cannot have missed an entrant (the mark comes before its count).
    const std::uint64_t bit = std::uint64_t{1} << index;
    if ((used_.load(std::memory_order_seq_cst) & bit) == 0) used_.fetch_or(bit, std::memory_order_seq_cst);
    Stripe& stripe = stripes_[index];
    for (;;) {
      stripe.inside.fetch_add(1, std::memory_order_seq_cst);
      if (!closed_.load(std::memory_order_seq_cst)) return;
      stripe.inside.fetch_sub(1, std::memory_order_release);
      closed_.wait(true, std::memory_order_acquire);
    }
  }
  void Leave() { stripes_[ThreadStripe()].inside.fetch_sub(1, std::memory_order_release); }

  /// Keeps new entrants out and waits for those inside to leave. One closer at a time. Returns how long it
  /// waited (zero, without reading the clock, when nobody was inside).
  std::chrono::nanoseconds Close() {
    close_mutex_.lock();
    closed_.store(true, std::memory_order_seq_cst);
    std::chrono::steady_clock::time_point waiting_since{};
    for (std::uint64_t used = used_.load(std::memory_order_seq_cst); used != 0; used &= used - 1) {
      const Stripe& stripe = stripes_[static_cast<std::size_t>(std::countr_zero(used))];
      while (stripe.inside.load(std::memory_order_acquire) != 0) {
        if (waiting_since == std::chrono::steady_clock::time_point{})
          waiting_since = std::chrono::steady_clock::now();
        std::this_thread::yield();
      }
    }
    if (waiting_since == std::chrono::steady_clock::time_point{}) return std::chrono::nanoseconds{0};
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() -
                                                                waiting_since);
  }
  void Open() {
    closed_.store(false, std::memory_order_release);
    closed_.notify_all();
    close_mutex_.unlock();
  }

 private:
  static constexpr std::size_t kStripes = 64;
  struct alignas(64) Stripe {
    std::atomic<std::int32_t> inside{0};
  };

  static std::size_t ThreadStripe() {
    static std::atomic<std::size_t> next{0};
    thread_local const std::size_t stripe = next.fetch_add(1, std::memory_order_relaxed) % kStripes;
    return stripe;
  }

  static_assert(kStripes <= 64, "one bit of used_ per stripe");
  std::array<Stripe, kStripes> stripes_;
  std::atomic<std::uint64_t> used_{0};  // stripes ever entered, one bit each
  std::atomic<bool> closed_{false};
  std::mutex close_mutex_;
};

/// Holds a StripedGate open for the current scope.
class StripedGatePass {
 public:
  explicit StripedGatePass(StripedGate& gate) : gate_(gate) { gate_.Enter(); }
  ~StripedGatePass() { gate_.Leave(); }
  StripedGatePass(const StripedGatePass&) = delete;
  StripedGatePass& operator=(const StripedGatePass&) = delete;

 private:
  StripedGate& gate_;
};

/// Keeps a StripedGate closed for the current scope.
class StripedGateClosure {
 public:
  explicit StripedGateClosure(StripedGate& gate) : gate_(gate) { gate_.Close(); }
  ~StripedGateClosure() { gate_.Open(); }
  StripedGateClosure(const StripedGateClosure&) = delete;
  StripedGateClosure& operator=(const StripedGateClosure&) = delete;

 private:
  StripedGate& gate_;
};

}  // namespace strata
