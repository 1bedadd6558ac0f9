// IslandBuilder: groups dynamic bodies connected by contacts into simulation islands (union-find with
// path halving), so a resting group can sleep and wake as one. Single-threaded; runs inside the step.
#pragma once

#include <cstdint>
#include <vector>

namespace strata {

/// Union-find over dense solver indices [0, count).
class IslandBuilder {
 public:
  /// Starts `count` singleton islands.
  void Reset(std::uint32_t count);
  /// Joins the islands of `a` and `b`.
  void Link(std::uint32_t a, std::uint32_t b);
  /// Representative of `a`'s island (the lowest index in it, so the result is deterministic).
  std::uint32_t Find(std::uint32_t a);

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace strata
