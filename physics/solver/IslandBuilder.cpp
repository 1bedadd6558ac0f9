#include "physics/solver/IslandBuilder.h"

#include <bit>
#include <cassert>

#include "physics/core/Atomics.h"

namespace strata {

void IslandBuilder::Reset(std::uint32_t body_count) {
  if (body_count > capacity_) {
    capacity_ = std::bit_ceil(body_count);
    links_ = std::make_unique<std::atomic<std::uint32_t>[]>(capacity_);
  }
  body_count_ = body_count;
  for (std::uint32_t i = 0; i < body_count; ++i) links_[i].store(i, std::memory_order_relaxed);
}

std::uint32_t IslandBuilder::FindLowest(std::uint32_t body, std::uint32_t* hops) {
  std::uint32_t current = body;
  std::uint32_t followed = 0;
  while (true) {
    const std::uint32_t next = links_[current].load(std::memory_order_acquire);
    if (next == current) break;
    current = next;
    ++followed;
  }
  // Links only ever point lower and stay within the island, so lowering ours to what we found is safe even
  // while others link and shorten concurrently.
  if (followed > 1) AtomicMin(links_[body], current, std::memory_order_release);
  if (hops != nullptr) *hops += followed;
  return current;
}

std::uint32_t IslandBuilder::Link(std::uint32_t a, std::uint32_t b) {
  assert(a < body_count_ && b < body_count_);
  std::uint32_t hops = 0;
  std::uint32_t low;
  while (true) {
    low = FindLowest(a, &hops);
    std::uint32_t high = FindLowest(b, &hops);
    if (low == high) return hops;
    if (low > high) std::swap(low, high);
    // Only a root (a body linked to itself) is relinked; if another thread relinked `high` first, retry from
    // where the links lead now.
    std::uint32_t expected = high;
    if (links_[high].compare_exchange_weak(expected, low, std::memory_order_acq_rel,
                                           std::memory_order_acquire))
      break;
  }
  AtomicMin(links_[a], low, std::memory_order_release);
  AtomicMin(links_[b], low, std::memory_order_release);
  return hops;
}

void IslandBuilder::Finalize(std::span<const std::uint32_t> constraint_body) {
  // Every link points lower, so walking up in index order finds each body's link already resolved: O(N).
  body_island_.resize(body_count_);
  island_body_begin_.assign(1, 0);
  for (std::uint32_t i = 0; i < body_count_; ++i) {
    const std::uint32_t link = links_[i].load(std::memory_order_relaxed);
    if (link == i) {
      body_island_[i] = static_cast<std::uint32_t>(island_body_begin_.size()) - 1;
      island_body_begin_.push_back(0);
    } else {
      body_island_[i] = body_island_[link];
    }
  }
  const std::uint32_t islands = island_count();

  // Counting sort of bodies and constraints by island keeps both lists ascending within an island.
  island_bodies_.resize(body_count_);
  CountingSort(
      body_count_, [&](std::uint32_t i) { return body_island_[i]; }, island_body_begin_, island_bodies_);
  island_constraints_.resize(constraint_body.size());
  island_constraint_begin_.assign(islands + 1, 0);
  CountingSort(
      static_cast<std::uint32_t>(constraint_body.size()),
      [&](std::uint32_t k) { return body_island_[constraint_body[k]]; }, island_constraint_begin_,
      island_constraints_);
}

template <class IslandOf>
void IslandBuilder::CountingSort(std::uint32_t count, IslandOf&& island_of, std::vector<std::uint32_t>& begin,
                                 std::vector<std::uint32_t>& out) {
  for (std::uint32_t i = 0; i < count; ++i) ++begin[island_of(i) + 1];
  for (std::size_t island = 1; island < begin.size(); ++island) begin[island] += begin[island - 1];
  cursor_.assign(begin.begin(), begin.end() - 1);
  for (std::uint32_t i = 0; i < count; ++i) out[cursor_[island_of(i)]++] = i;
}

}  // namespace strata
