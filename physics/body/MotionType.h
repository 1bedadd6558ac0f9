// MotionType: how a body moves. Value type.
#pragma once

#include <cstdint>

namespace strata {

/// Static: never moves. Kinematic: moved by velocity set by the game, infinite mass. Dynamic: simulated.
enum class MotionType : std::uint8_t { kStatic, kKinematic, kDynamic };

inline const char* ToString(MotionType type) {
  switch (type) {
    case MotionType::kStatic:
      return "static";
    case MotionType::kKinematic:
      return "kinematic";
    case MotionType::kDynamic:
      return "dynamic";
  }
  return "unknown";
}

}  // namespace strata
