// RelaxedAtomic: a copyable atomic for flags that one thread changes under a lock while others peek at them
// without one (a hint, re-checked under the lock before acting). Relaxed ordering; safe from any thread.
#pragma once

#include <atomic>

namespace strata {

/// std::atomic<T> with relaxed loads and stores, copyable so it can live in value types.
template <class T>
class RelaxedAtomic {
 public:
  RelaxedAtomic(T value = T()) : value_(value) {}  // NOLINT: implicit, as the plain T it replaces
  RelaxedAtomic(const RelaxedAtomic& other) : value_(other.load()) {}
  RelaxedAtomic& operator=(const RelaxedAtomic& other) {
    store(other.load());
    return *this;
  }
  RelaxedAtomic& operator=(T value) {
    store(value);
    return *this;
  }
  operator T() const { return load(); }  // NOLINT: implicit, as the plain T it replaces

  T load() const { return value_.load(std::memory_order_relaxed); }
  void store(T value) { value_.store(value, std::memory_order_relaxed); }

 private:
  std::atomic<T> value_;
};

}  // namespace strata
