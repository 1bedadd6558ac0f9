// IndexPairSet: a set of unordered pairs of 32-bit indices (the body pairs joints keep from colliding),
// looked up once for every pair the broad phase finds. Filled and sealed by one thread; after Seal, any
// number of threads may call Contains at once.
#pragma once

#include <cstdint>
#include <vector>

namespace strata {

class IndexPairSet {
 public:
  /// Empties the set; its memory is kept for the next fill.
  void Clear();
  /// Adds the pair {a, b} (either order). Not seen by Contains until Seal.
  void Add(std::uint32_t a, std::uint32_t b) { keys_.push_back(Key(a, b)); }
  /// Builds the lookup table from the pairs added since Clear.
  void Seal();
  bool Contains(std::uint32_t a, std::uint32_t b) const {
    if (slots_.empty()) return false;
    const std::uint64_t key = Key(a, b);
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t slot = Slot(key);; slot = (slot + 1) & mask) {
      if (slots_[slot] == key) return true;
      if (slots_[slot] == kEmpty) return false;
    }
  }
  bool empty() const { return keys_.empty(); }
  std::size_t size() const { return keys_.size(); }

 private:
  // No pair is {0xffffffff, 0xffffffff}: that is the invalid index.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  static std::uint64_t Key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
  }
  // Fibonacci hashing: the high bits of the product mix every bit of the key.
  std::size_t Slot(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }

  std::vector<std::uint64_t> keys_;
  std::vector<std::uint64_t> slots_;  // open addressing, linear probing, at most half full
  int shift_ = 63;
};

}  // namespace strata
