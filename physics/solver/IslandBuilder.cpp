#include "physics/solver/IslandBuilder.h"

#include <numeric>

namespace strata {

void IslandBuilder::Reset(std::uint32_t count) {
  parent_.resize(count);
  std::iota(parent_.begin(), parent_.end(), 0u);
}

std::uint32_t IslandBuilder::Find(std::uint32_t a) {
  while (parent_[a] != a) {
    parent_[a] = parent_[parent_[a]];
    a = parent_[a];
  }
  return a;
}

void IslandBuilder::Link(std::uint32_t a, std::uint32_t b) {
  a = Find(a);
  b = Find(b);
  if (a == b) return;
  // The lower index becomes the root: islands get the same representative whatever the link order.
  if (a < b)
    parent_[b] = a;
  else
    parent_[a] = b;
}

}  // namespace strata
