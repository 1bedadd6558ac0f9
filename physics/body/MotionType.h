// MotionType: how a body moves. Value type.
#pragma once

#include <cstdint>

namespace strata {

/// Static: never moves. Kinematic: moved by velocity set by the game, infinite mass. Dynamic: simulated.
enum class MotionType : std::uint8_t { kStatic, kKinematic, kDynamic };

/// How a dynamic body's motion is checked for collisions. Discrete: contacts found at the start of the step
/// (speculatively, up to its motion this step). LinearCast: in addition, a body that moved far for its size
/// is swept from its old to its new position and stopped at the first hit, so thin walls cannot be skipped.
enum class MotionQuality : std::uint8_t { kDiscrete, kLinearCast };

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
