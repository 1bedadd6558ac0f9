// TreeGenerations: which quad-tree roots are current, who still reads older ones, and when the nodes an
// older generation dropped may be freed. Pin/Unpin are wait-free and callable from any thread; Publish,
// Reclaim and the root updates of the current generation belong to the broad phase's writers.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

namespace strata {

/// Generation bookkeeping with split reference counts: a pin is a single fetch_add on the word that names
/// the current generation, so there is no window in which a reader holds a generation nobody counts.
class TreeGenerations {
 public:
  static constexpr std::uint32_t kMaxTrees = 8;
  static constexpr std::uint32_t kRecordCount = 256;
  static constexpr std::uint32_t kNoRoot = 0xffffffffu;

  /// What a reader holds: the record it counted itself in and the generation number.
  struct PinToken {
    std::uint32_t record = 0;
    std::uint64_t generation = 0;
  };

  /// Starts generation 1 with `roots` (kNoRoot for unused trees).
  explicit TreeGenerations(const std::array<std::uint32_t, kMaxTrees>& roots);

  /// Counts the caller as a reader of the current generation until Unpin.
  PinToken Pin() const;
  void Unpin(std::uint32_t record) const;
  /// Root of `tree` in a pinned generation (acquire, so the nodes it names are visible).
  std::uint32_t Root(std::uint32_t record, std::uint32_t tree) const {
    return records_[record].roots[tree].load(std::memory_order_acquire);
  }

  /// The current generation's root slot, for writers that swap in a new root with compare-exchange.
  std::atomic<std::uint32_t>& CurrentRootSlot(std::uint32_t tree);
  std::uint64_t current_generation() const;

  /// True when a record is free for the next Publish (call Reclaim first).
  bool CanPublish() const;
  /// Makes `roots` current; `retired` are the nodes only older generations can reach (taken over; the vector
  /// comes back empty with some capacity, so a steady rebuild allocates nothing). Single writer.
  void Publish(const std::array<std::uint32_t, kMaxTrees>& roots, std::vector<std::uint32_t>& retired);
  /// Frees (through `free_node`) every retired node no pinned generation can reach. Single writer.
  void Reclaim(const std::function<void(std::uint32_t)>& free_node);

  /// Nodes retired but not yet freed, and generations other than the current one still pinned.
  std::size_t retired_node_count() const { return retired_node_count_.load(std::memory_order_relaxed); }
  std::uint32_t pinned_old_generations() const;

 private:
  enum RecordState : std::uint8_t { kFree, kCurrent, kRetired, kReleased };
  static constexpr int kCountBits = 48;
  static constexpr std::uint64_t kCountMask = (std::uint64_t{1} << kCountBits) - 1;

  struct alignas(64) Record {
    // Unpins add one; Publish subtracts the pins taken through the current word. Zero after retirement
    // means the last reader has left.
    std::atomic<std::int64_t> balance{0};
    std::atomic<std::uint8_t> state{kFree};
    std::uint64_t generation = 0;  // written by the single writer before the record is published
    std::array<std::atomic<std::uint32_t>, kMaxTrees> roots;
  };
  struct RetiredNodes {
    std::uint64_t generation = 0;  // may be freed once every generation <= this one is released
    std::vector<std::uint32_t> nodes;
  };
  RetiredNodes& RetiredAt(std::size_t i) { return retired_[(retired_first_ + i) % retired_.size()]; }

  std::uint32_t FindFreeRecord() const;

  // Record index in the high 16 bits, pins taken on it in the low 48.
  mutable std::atomic<std::uint64_t> current_;
  mutable std::array<Record, kRecordCount> records_;
  // Records [0, this) have been handed out at least once; the writer's scans stop there (the lowest free
  // record is reused first, so it stays small), not at kRecordCount cache lines every step.
  std::atomic<std::uint32_t> records_used_{1};
  // A ring of retired-node lists, oldest first. Lists keep their capacity, so a steady world's rebuilds
  // allocate nothing; the ring grows only while a reader pins an old generation across many rebuilds.
  std::vector<RetiredNodes> retired_ = std::vector<RetiredNodes>(8);
  std::size_t retired_first_ = 0;
  std::size_t retired_size_ = 0;
  std::atomic<std::size_t> retired_node_count_{0};
  std::uint64_t next_generation_ = 1;
};

}  // namespace strata
