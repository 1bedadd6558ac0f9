#include "physics/broadphase/TreeGenerations.h"

#include <algorithm>
#include <cassert>
#include <limits>

namespace strata {

TreeGenerations::TreeGenerations(const std::array<std::uint32_t, kMaxTrees>& roots) {
  Record& first = records_[0];
  first.generation = next_generation_++;
  first.state.store(kCurrent, std::memory_order_relaxed);
  for (std::uint32_t tree = 0; tree < kMaxTrees; ++tree)
    first.roots[tree].store(roots[tree], std::memory_order_relaxed);
  for (std::uint32_t r = 1; r < kRecordCount; ++r)
    for (auto& root : records_[r].roots) root.store(kNoRoot, std::memory_order_relaxed);
  current_.store(0, std::memory_order_release);
}

TreeGenerations::PinToken TreeGenerations::Pin() const {
  const std::uint64_t word = current_.fetch_add(1, std::memory_order_acq_rel);
  const auto record = static_cast<std::uint32_t>(word >> kCountBits);
  return {record, records_[record].generation};
}

void TreeGenerations::Unpin(std::uint32_t record) const {
  const std::int64_t before = records_[record].balance.fetch_add(1, std::memory_order_acq_rel);
  // Only a retired record can come back to zero: its balance started at minus the pins it handed out.
  if (before + 1 == 0) records_[record].state.store(kReleased, std::memory_order_release);
}

std::atomic<std::uint32_t>& TreeGenerations::CurrentRootSlot(std::uint32_t tree) {
  const auto record = static_cast<std::uint32_t>(current_.load(std::memory_order_acquire) >> kCountBits);
  return records_[record].roots[tree];
}

std::uint64_t TreeGenerations::current_generation() const {
  const auto record = static_cast<std::uint32_t>(current_.load(std::memory_order_acquire) >> kCountBits);
  return records_[record].generation;
}

std::uint32_t TreeGenerations::FindFreeRecord() const {
  const std::uint32_t used = records_used_.load(std::memory_order_relaxed);
  for (std::uint32_t r = 0; r < used; ++r)
    if (records_[r].state.load(std::memory_order_acquire) == kFree) return r;
  return used;  // never handed out, so free (kRecordCount when all are taken)
}

bool TreeGenerations::CanPublish() const {
  return FindFreeRecord() < kRecordCount;
}

void TreeGenerations::Publish(const std::array<std::uint32_t, kMaxTrees>& roots,
                              std::vector<std::uint32_t>& retired) {
  const std::uint32_t fresh = FindFreeRecord();
  assert(fresh < kRecordCount);
  Record& next = records_[fresh];
  if (fresh + 1 > records_used_.load(std::memory_order_relaxed))
    records_used_.store(fresh + 1, std::memory_order_relaxed);
  next.generation = next_generation_++;
  next.balance.store(0, std::memory_order_relaxed);
  for (std::uint32_t tree = 0; tree < kMaxTrees; ++tree)
    next.roots[tree].store(roots[tree], std::memory_order_relaxed);
  next.state.store(kCurrent, std::memory_order_relaxed);

  const auto old_record = static_cast<std::uint32_t>(current_.load(std::memory_order_relaxed) >> kCountBits);
  Record& old = records_[old_record];
  // Mark it retired before it stops being current, so the unpin that brings it to zero sees the state.
  old.state.store(kRetired, std::memory_order_relaxed);
  const std::uint64_t word =
      current_.exchange(static_cast<std::uint64_t>(fresh) << kCountBits, std::memory_order_acq_rel);
  const auto pins = static_cast<std::int64_t>(word & kCountMask);
  if (old.balance.fetch_sub(pins, std::memory_order_acq_rel) - pins == 0)
    old.state.store(kReleased, std::memory_order_release);

  if (!retired.empty()) {
    retired_node_count_.fetch_add(retired.size(), std::memory_order_relaxed);
    if (retired_size_ == retired_.size()) {
      std::vector<RetiredNodes> wider(2 * retired_.size());
      for (std::size_t i = 0; i < retired_size_; ++i) wider[i] = std::move(RetiredAt(i));
      retired_.swap(wider);
      retired_first_ = 0;
    }
    RetiredNodes& slot = RetiredAt(retired_size_++);
    slot.generation = old.generation;
    slot.nodes.swap(retired);
    retired.clear();
  }
}

void TreeGenerations::Reclaim(const std::function<void(std::uint32_t)>& free_node) {
  std::uint64_t oldest_alive = std::numeric_limits<std::uint64_t>::max();
  const std::uint32_t used = records_used_.load(std::memory_order_relaxed);
  for (std::uint32_t r = 0; r < used; ++r) {
    Record& record = records_[r];
    const std::uint8_t state = record.state.load(std::memory_order_acquire);
    if (state == kReleased) {
      record.state.store(kFree, std::memory_order_relaxed);
    } else if (state != kFree) {
      oldest_alive = std::min(oldest_alive, record.generation);
    }
  }
  while (retired_size_ > 0 && RetiredAt(0).generation < oldest_alive) {
    RetiredNodes& oldest = RetiredAt(0);
    for (const std::uint32_t node : oldest.nodes) free_node(node);
    retired_node_count_.fetch_sub(oldest.nodes.size(), std::memory_order_relaxed);
    oldest.nodes.clear();
    retired_first_ = (retired_first_ + 1) % retired_.size();
    --retired_size_;
  }
}

std::uint32_t TreeGenerations::pinned_old_generations() const {
  std::uint32_t count = 0;
  for (const Record& record : records_)
    if (record.state.load(std::memory_order_acquire) == kRetired) ++count;
  return count;
}

}  // namespace strata
