#include "physics/body/BodyManager.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

namespace strata {

namespace {
std::string Describe(BodyID id) {
  return "body " + std::to_string(id.index) + "#" + std::to_string(id.generation);
}

thread_local std::uint64_t lock_wait_nanoseconds = 0;
thread_local BodyLockCounts lock_counts;

// Starts loading a body's cache lines before its lock is taken, so that the misses do not lengthen the
// time the lock is held (other threads wait on exactly that time).
void PrefetchForWrite(const Body& body) {
  const char* const bytes = reinterpret_cast<const char*>(&body);
  for (std::size_t offset = 0; offset < sizeof(Body); offset += 64) __builtin_prefetch(bytes + offset, 1);
}

// Locks `lock` (constructed deferred), timing the wait only when the mutex is taken.
template <class Lock>
void LockTimingWait(Lock& lock) {
  ++lock_counts.acquisitions;
  if (lock.try_lock()) return;
  ++lock_counts.contended;
  const auto start = std::chrono::steady_clock::now();
  lock.lock();
  lock_wait_nanoseconds += static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
}
}  // namespace

std::uint64_t ThreadBodyLockWaitNanoseconds() {
  return lock_wait_nanoseconds;
}

BodyLockCounts ThreadBodyLockCounts() {
  return lock_counts;
}

BodyManager::BodyManager(std::uint32_t capacity, std::uint32_t mutex_count)
    : bodies_(capacity), generations_(capacity, 1), mutexes_(mutex_count == 0 ? 1 : mutex_count) {
  free_slots_.reserve(capacity);
  // Hand out low indices first so small worlds stay compact.
  for (std::uint32_t i = capacity; i > 0; --i) free_slots_.push_back(i - 1);
}

std::uint32_t BodyManager::body_count() const {
  std::lock_guard lock(allocation_mutex_);
  return capacity() - static_cast<std::uint32_t>(free_slots_.size());
}

Result<BodyID> BodyManager::CreateBody(const BodyCreationSettings& settings) {
  if (Status valid = settings.Validate(); !valid) return valid.error();
  BodyID id;
  {
    std::lock_guard lock(allocation_mutex_);
    if (free_slots_.empty())
      return MakeError(ErrorCode::kCapacityExceeded,
                       "body manager is full (capacity " + std::to_string(capacity()) + ")");
    id.index = free_slots_.back();
    free_slots_.pop_back();
    id.generation = generations_[id.index];
    if (id.index >= slot_limit_.load(std::memory_order_relaxed))
      slot_limit_.store(id.index + 1, std::memory_order_release);
  }
  std::unique_lock lock(MutexFor(id.index));
  bodies_[id.index].ResetInternal(settings, id);
  return id;
}

Status BodyManager::CheckId(BodyID id) const {
  if (id.IsInvalid() || id.index >= capacity())
    return MakeError(ErrorCode::kStaleBodyId, Describe(id) + " does not exist");
  if (bodies_[id.index].id() != id)
    return MakeError(ErrorCode::kStaleBodyId, Describe(id) + " is stale (destroyed or never created)");
  return Status::Ok();
}

Status BodyManager::DestroyBody(BodyID id) {
  {
    BodyLockWrite lock(*this, id);
    if (!lock.Succeeded()) return lock.status();
    if (lock.body().in_world())
      return MakeError(ErrorCode::kInvalidState, Describe(id) + " is still in the world; remove it first");
    lock.body() = Body();
  }
  std::lock_guard lock(allocation_mutex_);
  // Skip generation 0 on wrap so a zeroed id never matches a live body.
  generations_[id.index] = generations_[id.index] + 1 == 0 ? 1 : generations_[id.index] + 1;
  free_slots_.push_back(id.index);
  return Status::Ok();
}

void BodyManager::LockAll() {
  // Only the mutexes of slots handed out so far guard anything: a small world takes as many as it has
  // bodies. A slot handed out after this point is outside the world until a writer adds it, and writers
  // wait for the step, so nothing the step touches is left unlocked.
  locked_slot_limit_ = slot_limit();
  locked_count_ = std::min(mutex_count(), std::max(locked_slot_limit_, 1u));
  // Timed like any other contended acquisition, so tools can see a step waiting for readers.
  for (std::uint32_t i = 0; i < locked_count_; ++i) {
    std::unique_lock lock(mutexes_[i], std::defer_lock);
    LockTimingWait(lock);
    lock.release();
  }
}

void BodyManager::UnlockAll() {
  for (std::uint32_t i = 0; i < locked_count_; ++i) mutexes_[i].unlock();
}

void BodyManager::BeginStep() {
  // Writers that waited through the previous step go first, so a thread stepping back to back cannot
  // starve them; writers arriving now are not counted and cannot hold the step up for long.
  while (waiting_writers_.load(std::memory_order_acquire) > 0) std::this_thread::yield();
  // The move gate closes before the flag goes up: a move inside it takes its body's lock after this and must
  // not find the flag up (it would wait for the end of a step that waits for it). Waiting for moves in flight
  // counts as lock wait: LockAll waited for them when they updated the broad phase under their body's lock.
  lock_wait_nanoseconds += static_cast<std::uint64_t>(move_gate_.Close().count());
  stepping_.store(true, std::memory_order_seq_cst);
}

void BodyManager::EndStep() {
  stepping_.store(false, std::memory_order_release);
  stepping_.notify_all();
  move_gate_.Open();
}

BodyLockRead::BodyLockRead(const BodyManager& manager, BodyID id)
    : lock_(manager.MutexFor(id.index < manager.capacity() ? id.index : 0), std::defer_lock) {
  LockTimingWait(lock_);
  status_ = manager.CheckId(id);
  if (status_.ok()) body_ = &manager.BodyAt(id.index);
}

BodyLockWrite::BodyLockWrite(BodyManager& manager, BodyID id)
    : lock_(manager.MutexFor(id.index < manager.capacity() ? id.index : 0), std::defer_lock) {
  if (id.index < manager.capacity()) PrefetchForWrite(manager.BodyAt(id.index));
  LockTimingWait(lock_);
  // A writer that got the lock while a step runs backs off until the step ends: the step reads bodies
  // unlocked between its own LockAll windows. Taking the lock first orders this check after the step's
  // LockAll/UnlockAll, so no writer slips in once BeginStep has been called.
  bool waited = false;
  while (manager.stepping()) {
    if (!waited) manager.waiting_writers_.fetch_add(1, std::memory_order_acq_rel);
    waited = true;
    lock_.unlock();
    manager.stepping_.wait(true, std::memory_order_acquire);
    LockTimingWait(lock_);
  }
  if (waited) manager.waiting_writers_.fetch_sub(1, std::memory_order_acq_rel);
  status_ = manager.CheckId(id);
  if (status_.ok()) body_ = &manager.BodyAt(id.index);
}

}  // namespace strata
