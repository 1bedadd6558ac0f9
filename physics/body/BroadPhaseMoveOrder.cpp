#include "physics/body/BroadPhaseMoveOrder.h"

#include <thread>

namespace strata {

BroadPhaseMoveOrder::BroadPhaseMoveOrder(std::uint32_t max_bodies)
    : slots_(std::make_unique<Slot[]>(max_bodies)) {}

std::uint64_t BroadPhaseMoveOrder::Issue(std::uint32_t index) {
  return ++slots_[index].issued;
}

bool BroadPhaseMoveOrder::Acquire(Slot& slot, std::uint64_t ticket) {
  std::uint64_t held = slot.applied.load(std::memory_order_acquire);
  for (int spins = 0;; ++spins) {
    if ((held & ~kBusy) >= ticket) return false;
    if ((held & kBusy) != 0) {
      // Another move of the same body is updating the broad phase (well under a microsecond).
      if (spins > 64) std::this_thread::yield();
      held = slot.applied.load(std::memory_order_acquire);
      continue;
    }
    if (slot.applied.compare_exchange_weak(held, held | kBusy, std::memory_order_acquire,
                                           std::memory_order_acquire))
      return true;
  }
}

void BroadPhaseMoveOrder::Retire(std::uint32_t index) {
  Slot& slot = slots_[index];
  // The body's write lock keeps `issued` still; taking the flag waits out an update that is running.
  if (Acquire(slot, slot.issued)) slot.applied.store(slot.issued, std::memory_order_release);
}

}  // namespace strata
