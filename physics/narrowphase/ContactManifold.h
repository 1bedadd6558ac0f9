// ContactManifold: up to four contact points between two bodies sharing one normal, the narrow phase's
// output and the solver's input. Plain data, written by one narrow-phase job and read by the solver.
#pragma once

#include <cstdint>

#include "physics/body/BodyID.h"
#include "physics/math/Math.h"

namespace strata {

/// One contact point as a pair of surface points; separation < 0 means the bodies overlap there.
struct ContactPoint {
  Vec3 position_a;   ///< on the surface of A, world space
  Vec3 position_b;   ///< on the surface of B, world space
  float separation;  ///< (position_b - position_a) . normal
};

/// Contact between body A and body B, or between their sub-shapes (a mesh triangle; 0 for a shape without).
struct ContactManifold {
  static constexpr int kMaxPoints = 4;
  BodyID body_a;
  BodyID body_b;
  std::uint32_t sub_shape_a = 0;
  std::uint32_t sub_shape_b = 0;
  Vec3 normal = Vec3::UnitY();  ///< unit, from A towards B
  int count = 0;
  ContactPoint points[kMaxPoints];

  float MinSeparation() const {
    float smallest = kLargeFloat;
    for (int i = 0; i < count; ++i) smallest = std::min(smallest, points[i].separation);
    return smallest;
  }
};

}  // namespace strata
