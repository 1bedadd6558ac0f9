#include "physics/core/IndexPairSet.h"

#include <algorithm>
#include <bit>

namespace strata {

void IndexPairSet::Clear() {
  keys_.clear();
  slots_.clear();
}

void IndexPairSet::Seal() {
  slots_.clear();
  if (keys_.empty()) return;
  // At most half full, so that a miss (the common answer) ends within a probe or two.
  const std::size_t size = std::bit_ceil(std::max<std::size_t>(2 * keys_.size(), 8));
  slots_.assign(size, kEmpty);
  shift_ = 64 - std::countr_zero(size);
  const std::size_t mask = size - 1;
  for (const std::uint64_t key : keys_) {
    std::size_t slot = Slot(key);
    while (slots_[slot] != kEmpty && slots_[slot] != key) slot = (slot + 1) & mask;
    slots_[slot] = key;
  }
}

}  // namespace strata
