// WakeQueue: the sleeping islands to wake at the start of the next step, and the keys that name islands as
// they fall asleep. A BodyInterface call holds one body's lock and cannot wake the rest of that body's
// island, so it queues the island's key here; the step takes the queue while it holds every body lock.
// Thread-safe: Request and NewKeys from any thread, Take from the stepping thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

namespace strata {

class WakeQueue {
 public:
  /// Wakes island `key` at the next step.
  void Request(std::uint32_t key) {
    std::lock_guard lock(mutex_);
    pending_.push_back(key);
    pending_flag_.store(true, std::memory_order_release);
  }
  void Request(std::span<const std::uint32_t> keys) {
    if (keys.empty()) return;
    std::lock_guard lock(mutex_);
    pending_.insert(pending_.end(), keys.begin(), keys.end());
    pending_flag_.store(true, std::memory_order_release);
  }
  /// Swaps the queued keys into `keys` (cleared first). Most steps have none: the flag spares them the mutex,
  /// and a key queued after the exchange raises it again and is taken next step.
  void Take(std::vector<std::uint32_t>& keys) {
    keys.clear();
    if (!pending_flag_.exchange(false, std::memory_order_acq_rel)) return;
    std::lock_guard lock(mutex_);
    keys.swap(pending_);
  }
  /// `count` fresh island keys; the first is returned, the others follow it.
  std::uint32_t NewKeys(std::uint32_t count) { return next_key_.fetch_add(count, std::memory_order_relaxed); }

 private:
  std::mutex mutex_;
  std::atomic<bool> pending_flag_{false};  // pending_ may hold keys
  std::vector<std::uint32_t> pending_;
  std::atomic<std::uint32_t> next_key_{1};
};

}  // namespace strata
