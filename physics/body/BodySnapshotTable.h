// BodySnapshotTable: copies of the bodies in the world that BodyInterface republishes on add, teleport and
// removal, so readers such as navmesh jobs see static geometry without a body lock. The step never touches
// it. Publish/Withdraw run under the body's write lock; Read and Enable from any thread.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "physics/body/Body.h"
#include "physics/core/SpinningSharedMutex.h"

namespace strata {

class BodyManager;

/// A body as of its last add or teleport. For a moving body only its identity, motion type and layer stay
/// true between teleports: the step moves it without republishing.
struct BodySnapshot {
  BodyID id;
  MotionType motion_type = MotionType::kStatic;
  ObjectLayer object_layer = 0;
  ShapeRef shape;
  Pose pose;
  AABB bounds;          ///< world bounds at `pose`
  bool sensor = false;  ///< a trigger volume: nothing stands on it or is stopped by it
};

/// Per-slot snapshots guarded by their own striped locks (never the body locks), held only to copy a slot.
class BodySnapshotTable {
 public:
  explicit BodySnapshotTable(std::uint32_t capacity) : capacity_(capacity) {}

  /// Turns publishing on (once; later calls only check a flag) and copies every body already in the world,
  /// each under its read lock. Call it before background readers start, from a foreground thread: the copy
  /// is the only time the table touches body locks. Const because it changes no body, only who can read.
  void Enable(const BodyManager& bodies) const;
  bool enabled() const { return enabled_.load(std::memory_order_acquire); }

  /// Records `body` (in the world); call with its write lock held. A no-op while the table is off.
  void Publish(const Body& body);
  /// Forgets the body in slot `id.index` (leaving the world); call with its write lock held.
  void Withdraw(BodyID id);

  /// The snapshot of `id`, or nothing when it is not in the world (or the id is stale, or the table is off).
  std::optional<BodySnapshot> Read(BodyID id) const;

 private:
  struct Slot {
    bool present = false;
    BodySnapshot snapshot;
  };
  static constexpr std::uint32_t kStripes = 64;

  void Store(std::uint32_t index, const Body* body) const;
  SpinningSharedMutex& StripeFor(std::uint32_t index) const { return stripes_[index % kStripes]; }

  const std::uint32_t capacity_;
  mutable std::atomic<bool> enabled_{false};
  mutable std::mutex enable_mutex_;
  mutable std::vector<Slot> slots_;  // capacity_ slots once enabled
  mutable std::unique_ptr<SpinningSharedMutex[]> stripes_;
};

}  // namespace strata
