#include "physics/body/BodySnapshotTable.h"

#include <shared_mutex>

#include "physics/body/BodyManager.h"

namespace strata {

void BodySnapshotTable::Enable(const BodyManager& bodies) const {
  if (enabled()) return;
  std::lock_guard once(enable_mutex_);
  if (enabled()) return;
  slots_.resize(capacity_);
  stripes_ = std::make_unique<SpinningSharedMutex[]>(kStripes);
  // From here on writers publish their own changes (they check the flag under the body's write lock), so the
  // copy below and a concurrent writer are ordered by that lock and the newer state is the one kept.
  enabled_.store(true, std::memory_order_release);
  const std::uint32_t limit = bodies.slot_limit();
  for (std::uint32_t index = 0; index < limit; ++index) {
    const std::shared_lock lock(bodies.MutexFor(index));
    const Body& body = bodies.BodyAt(index);
    if (body.in_world()) Store(index, &body);
  }
}

void BodySnapshotTable::Publish(const Body& body) {
  if (enabled()) Store(body.id().index, &body);
}

void BodySnapshotTable::Withdraw(BodyID id) {
  if (enabled()) Store(id.index, nullptr);
}

void BodySnapshotTable::Store(std::uint32_t index, const Body* body) const {
  // Built before taking the stripe, so the stripe is held for a copy only (and the old shape reference is
  // dropped after releasing it).
  Slot fresh;
  if (body != nullptr) {
    fresh.present = true;
    fresh.snapshot = {body->id(),   body->motion_type(),  body->object_layer(), body->shape(),
                      body->pose(), body->world_bounds(), body->is_sensor()};
  }
  {
    const std::lock_guard lock(StripeFor(index));
    std::swap(slots_[index], fresh);
  }
}

std::optional<BodySnapshot> BodySnapshotTable::Read(BodyID id) const {
  if (!enabled() || id.index >= capacity_) return std::nullopt;
  const std::shared_lock lock(StripeFor(id.index));
  const Slot& slot = slots_[id.index];
  if (!slot.present || slot.snapshot.id != id) return std::nullopt;
  return slot.snapshot;
}

}  // namespace strata
