// BodyID: the handle every API uses for a body: a 32-bit slot index plus the slot's generation, so a
// handle to a destroyed body is detected instead of silently reaching its successor. Value type.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>

namespace strata {

/// Slot index + generation. Default-constructed ids are invalid.
struct BodyID {
  static constexpr std::uint32_t kInvalidIndex = std::numeric_limits<std::uint32_t>::max();

  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;

  bool IsInvalid() const { return index == kInvalidIndex; }
  friend bool operator==(const BodyID&, const BodyID&) = default;
  friend auto operator<=>(const BodyID&, const BodyID&) = default;
};

}  // namespace strata

template <>
struct std::hash<strata::BodyID> {
  std::size_t operator()(const strata::BodyID& id) const noexcept {
    return std::hash<std::uint64_t>()((static_cast<std::uint64_t>(id.generation) << 32) | id.index);
  }
};
