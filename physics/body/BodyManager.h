// BodyManager: owns every body in a fixed-capacity slot array (chosen at creation) and a fixed set of
// read/write mutexes; body slot i is guarded by mutex i % mutex_count. Create/Destroy are thread-safe.
// Read a body through BodyLockRead, change it through BodyLockWrite. While a step runs, writers wait
// (BeginStep/EndStep); readers wait only while the step holds every lock (LockAll), at its start and end.
// Moves that finish their broad-phase part after releasing the body's lock pass move_gate(), which the step
// waits on.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <vector>

#include "physics/body/Body.h"
#include "physics/core/SpinningSharedMutex.h"
#include "physics/core/StripedGate.h"

namespace strata {

/// Fixed-capacity body storage with sharded locks.
class BodyManager {
 public:
  /// `capacity` bodies at most; `mutex_count` read/write mutexes shared by the bodies (default 32).
  BodyManager(std::uint32_t capacity, std::uint32_t mutex_count = 32);

  std::uint32_t capacity() const { return static_cast<std::uint32_t>(bodies_.size()); }
  std::uint32_t mutex_count() const { return static_cast<std::uint32_t>(mutexes_.size()); }
  /// Bodies created and not yet destroyed.
  std::uint32_t body_count() const;
  /// Bodies in the world (BodyInterface counts them as it adds and removes them).
  std::size_t in_world_count() const { return in_world_count_.load(std::memory_order_relaxed); }
  void CountAddedToWorld(std::size_t count) { in_world_count_.fetch_add(count, std::memory_order_relaxed); }
  void CountRemovedFromWorld(std::size_t count) {
    in_world_count_.fetch_sub(count, std::memory_order_relaxed);
  }

  /// Validates `settings` and creates a body outside the world. Fails on bad settings or a full manager.
  Result<BodyID> CreateBody(const BodyCreationSettings& settings);
  /// Frees the slot (the generation moves on, so old ids go stale). The body must not be in the world.
  Status DestroyBody(BodyID id);

  /// The mutex guarding `index`.
  SpinningSharedMutex& MutexFor(std::uint32_t index) const { return mutexes_[index % mutexes_.size()]; }

  /// Checks `id` against its slot; call with the body's lock held.
  Status CheckId(BodyID id) const;

  /// Direct slot access for code that already holds the lock (or all locks, as the step does).
  Body& BodyAt(std::uint32_t index) { return bodies_[index]; }
  const Body& BodyAt(std::uint32_t index) const { return bodies_[index]; }

  /// Takes every body lock that guards a slot handed out so far for writing (in index order, so it cannot
  /// deadlock with itself); one thread at a time (the step, or a settings change that excludes it).
  void LockAll();
  void UnlockAll();

  /// From BeginStep to EndStep every new BodyLockWrite (and DestroyBody) waits, so the step may read bodies
  /// without locks between its LockAll windows while readers carry on.
  void BeginStep();
  void EndStep();
  bool stepping() const { return stepping_.load(std::memory_order_acquire); }
  /// Passed (StripedGatePass) by a move from before it takes the body's lock until its broad-phase update,
  /// made after releasing the lock, is in. BeginStep closes it first: a step starts after every move in
  /// flight is complete, and moves that come during the step wait for its end, as other writers do.
  StripedGate& move_gate() { return move_gate_; }

  /// Every body index handed out so far is below this.
  std::uint32_t slot_limit() const { return slot_limit_.load(std::memory_order_acquire); }
  /// The slot limit when LockAll ran: the slots its locks guard, and so the ones the step may scan. A slot
  /// handed out later may be under a mutex LockAll did not take while its creator fills it in.
  std::uint32_t locked_slot_limit() const { return locked_slot_limit_; }

 private:
  friend class BodyLockWrite;

  std::vector<Body> bodies_;
  std::vector<std::uint32_t> generations_;
  std::vector<std::uint32_t> free_slots_;
  mutable std::mutex allocation_mutex_;  // guards free_slots_ and generations_
  mutable std::vector<SpinningSharedMutex> mutexes_;
  std::atomic<bool> stepping_{false};
  StripedGate move_gate_;
  std::atomic<std::uint32_t> waiting_writers_{0};  // writers blocked by the step that is ending
  std::atomic<std::uint32_t> slot_limit_{0};
  std::atomic<std::size_t> in_world_count_{0};
  std::uint32_t locked_count_ = 0;       // mutexes held by LockAll
  std::uint32_t locked_slot_limit_ = 0;  // slot_limit() when LockAll ran
};

/// Time this thread has spent blocked on body mutexes (ns) since it started. Only contended acquisitions are
/// timed (a failed try-lock starts the clock), so the uncontended path costs nothing extra.
std::uint64_t ThreadBodyLockWaitNanoseconds();

/// How often this thread has taken a body mutex since it started, and how many of those found it taken (and
/// waited): contended / acquisitions is the chance that another thread holds the same mutex, which with n
/// mutexes is about the share of time the other threads spend holding one, over n.
struct BodyLockCounts {
  std::uint64_t acquisitions = 0;
  std::uint64_t contended = 0;
};
BodyLockCounts ThreadBodyLockCounts();

/// RAII read access to one body; check Succeeded() (false for a stale or unknown id).
class BodyLockRead {
 public:
  BodyLockRead(const BodyManager& manager, BodyID id);
  bool Succeeded() const { return status_.ok(); }
  const Status& status() const { return status_; }
  const Body& body() const { return *body_; }

 private:
  std::shared_lock<SpinningSharedMutex> lock_;
  Status status_;
  const Body* body_ = nullptr;
};

/// RAII write access to one body; check Succeeded() (false for a stale or unknown id). Waits while a
/// step runs.
class BodyLockWrite {
 public:
  BodyLockWrite(BodyManager& manager, BodyID id);
  bool Succeeded() const { return status_.ok(); }
  const Status& status() const { return status_; }
  Body& body() const { return *body_; }

 private:
  std::unique_lock<SpinningSharedMutex> lock_;
  Status status_;
  Body* body_ = nullptr;
};

}  // namespace strata
