// IslandBuilder: groups the step's active bodies into simulation islands (bodies joined by contacts),
// so islands solve in parallel and a resting island sleeps and wakes as one. Link is lock-free and runs
// from the narrow-phase jobs as contacts appear: a union-find over an array of atomic links where every link
// points to a lower index, joined by compare-exchange on the higher root and shortened with atomic min.
// Finalize then numbers islands and lists their bodies and constraints in O(bodies + constraints) on one
// thread. Reset and Finalize run alone; Link from any number of threads in between.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace strata {

/// Lock-free union-find plus the islands it yields.
class IslandBuilder {
 public:
  /// Starts `body_count` singleton islands over body indices [0, body_count). Allocates only to grow.
  void Reset(std::uint32_t body_count);

  /// Joins the islands of bodies `a` and `b`. Lock-free; returns how many links it followed (a profile
  /// figure).
  std::uint32_t Link(std::uint32_t a, std::uint32_t b);

  /// After every Link: islands numbered by their lowest body, each listing its bodies in ascending order and
  /// the constraints k whose `constraint_body[k]` is one of its bodies, in ascending k.
  void Finalize(std::span<const std::uint32_t> constraint_body);

  std::uint32_t body_count() const { return body_count_; }
  std::uint32_t island_count() const { return static_cast<std::uint32_t>(island_body_begin_.size()) - 1; }
  /// Island of `body` (after Finalize).
  std::uint32_t island_of(std::uint32_t body) const { return body_island_[body]; }
  std::span<const std::uint32_t> bodies(std::uint32_t island) const {
    return std::span(island_bodies_)
        .subspan(island_body_begin_[island], island_body_begin_[island + 1] - island_body_begin_[island]);
  }
  std::span<const std::uint32_t> constraints(std::uint32_t island) const {
    return std::span(island_constraints_)
        .subspan(island_constraint_begin_[island],
                 island_constraint_begin_[island + 1] - island_constraint_begin_[island]);
  }
  /// Offset of the island's first constraint in the concatenation of all islands' constraint lists.
  std::uint32_t constraint_offset(std::uint32_t island) const { return island_constraint_begin_[island]; }
  /// The bodies of islands [first, end), island after island.
  std::span<const std::uint32_t> bodies(std::uint32_t first, std::uint32_t end) const {
    return std::span(island_bodies_)
        .subspan(island_body_begin_[first], island_body_begin_[end] - island_body_begin_[first]);
  }
  /// How many constraints islands [first, end) have.
  std::uint32_t constraint_count(std::uint32_t first, std::uint32_t end) const {
    return island_constraint_begin_[end] - island_constraint_begin_[first];
  }

  /// Lowest body of `body`'s island so far (lock-free; shortens the path it walked). For tests and profiles.
  std::uint32_t FindLowest(std::uint32_t body, std::uint32_t* hops = nullptr);

 private:
  template <class IslandOf>
  void CountingSort(std::uint32_t count, IslandOf&& island_of, std::vector<std::uint32_t>& begin,
                    std::vector<std::uint32_t>& out);

  std::unique_ptr<std::atomic<std::uint32_t>[]> links_;
  std::uint32_t capacity_ = 0;
  std::uint32_t body_count_ = 0;
  std::vector<std::uint32_t> body_island_;
  std::vector<std::uint32_t> island_body_begin_{0};
  std::vector<std::uint32_t> island_bodies_;
  std::vector<std::uint32_t> island_constraint_begin_{0};
  std::vector<std::uint32_t> island_constraints_;
  std::vector<std::uint32_t> cursor_;
};

}  // namespace strata
