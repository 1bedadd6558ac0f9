// Atomics: atomic minimum and maximum (compare-exchange loops), used by the island builder's path
// compression, the broad phase's bound widening and the job graph's timings. Safe from any thread.
#pragma once

#include <atomic>

namespace strata {

/// Lowers `value` to `candidate` if that is smaller; returns the value seen before (or the new one).
template <class T>
T AtomicMin(std::atomic<T>& value, T candidate, std::memory_order order = std::memory_order_relaxed) {
  T current = value.load(std::memory_order_relaxed);
  while (candidate < current &&
         !value.compare_exchange_weak(current, candidate, order, std::memory_order_relaxed)) {
  }
  return current;
}

/// Raises `value` to `candidate` if that is larger; returns the value seen before (or the new one).
template <class T>
T AtomicMax(std::atomic<T>& value, T candidate, std::memory_order order = std::memory_order_relaxed) {
  T current = value.load(std::memory_order_relaxed);
  while (candidate > current &&
         !value.compare_exchange_weak(current, candidate, order, std::memory_order_relaxed)) {
  }
  return current;
}

}  // namespace strata
