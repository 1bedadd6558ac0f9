// BroadPhaseMoveOrder: lets a move hold its body's lock only for the pose write and give the broad phase
// the new bounds after releasing it, while the broad phase still ends with the bounds of the body's latest
// move. Each move takes a ticket under the body's write lock (so tickets follow the lock order); applying
// bounds with an older ticket than what a body's slot already holds does nothing. Issue and Retire under
// the body's write lock; Apply from any thread, once per ticket.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

namespace strata {

/// Per body slot: the last ticket issued and the last one applied to the broad phase.
class BroadPhaseMoveOrder {
 public:
  explicit BroadPhaseMoveOrder(std::uint32_t max_bodies);

  /// A ticket for a move of the body in `index`, later than every earlier one. Call under its write lock.
  std::uint64_t Issue(std::uint32_t index);

  /// Runs `update` (the broad-phase update for the move with `ticket`) unless a later move's bounds are in
  /// already or the moves were retired; updates of one slot never overlap. Returns whether it ran.
  template <class Update>
  bool Apply(std::uint32_t index, std::uint64_t ticket, Update&& update);

  /// Makes every ticket issued so far stale, waiting for an update still running: after it, no earlier move
  /// touches the broad phase for this slot (the body leaves it). Call under the body's write lock.
  void Retire(std::uint32_t index);

 private:
  static constexpr std::uint64_t kBusy = std::uint64_t{1} << 63;
  struct Slot {
    std::uint64_t issued = 0;               // written under the body's write lock only
    std::atomic<std::uint64_t> applied{0};  // the ticket in the broad phase, kBusy while one goes in
  };
  // Takes the slot's busy flag, waiting while another update holds it; false (and nothing taken) once the
  // slot holds `ticket` or a later one.
  bool Acquire(Slot& slot, std::uint64_t ticket);

  std::unique_ptr<Slot[]> slots_;
};

template <class Update>
bool BroadPhaseMoveOrder::Apply(std::uint32_t index, std::uint64_t ticket, Update&& update) {
  Slot& slot = slots_[index];
  if (!Acquire(slot, ticket)) return false;
  update();
  slot.applied.store(ticket, std::memory_order_release);
  return true;
}

}  // namespace strata
