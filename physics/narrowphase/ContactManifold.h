// ContactManifold: up to four contact points between two bodies sharing one normal, the narrow phase's
// output and the solver's input. Plain data, written by one narrow-phase job and read by the solver.
#pragma once

#include <algorithm>
#include <cstdint>

#include "physics/BodyID.h"
#include "physics/math/Math.h"

namespace strata {

/// How far apart two shapes may be and still get a contact (a speculative one): `distance` whatever the
/// direction, and further by as much as B closes on A along the contact's normal over the step (`travel`:
/// B's motion relative to A, world space). A contact beyond that cannot close within the step, so the step
/// gets no impulse from it and it is not made.
struct ContactReach {
  float distance = 0.0f;
  Vec3 travel = Vec3::Zero();

  /// The reach along a contact normal (from A towards B).
  float Along(const Vec3& normal) const { return distance + std::max(0.0f, -travel.dot(normal)); }
  /// The reach whatever the normal: what a test must allow before it knows the normal.
  float Max() const { return distance + travel.norm(); }
  /// The same reach with A and B the other way round.
  ContactReach Reversed() const { return {distance, -travel}; }
};

/// One contact point as a pair of surface points; separation < 0 means the bodies overlap there.
struct ContactPoint {
  Vec3 position_a;   ///< on the surface of A, world space
  Vec3 position_b;   ///< on the surface of B, world space
  float separation;  ///< (position_b - position_a) . normal
};

/// The flat face a manifold's points were pressed onto, when every point is a corner of the other body's
/// face and none was cut by this face's sides (a box resting or sliding on a floor or on a wider box). Those
/// corners stay the contact points while the bodies keep their relative turn and the corners stay inside the
/// face, however far one slides over the other: the body-pair cache then carries them along instead of
/// testing the shapes again. World space.
struct ContactFace {
  bool valid = false;
  bool on_a = false;  ///< the face is A's and the corners B's, or the other way round
  Vec3 centre = Vec3::Zero();
  Vec3 u = Vec3::UnitX();       ///< the face's first edge direction (unit)
  Vec3 v = Vec3::UnitZ();       ///< its second (unit)
  Vec3 normal = Vec3::UnitY();  ///< out of the face's body
  float half_u = 0.0f;
  float half_v = 0.0f;
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
  ContactFace face;  ///< set by colliders that know it (box on box), else not valid

  float MinSeparation() const {
    float smallest = kLargeFloat;
    for (int i = 0; i < count; ++i) smallest = std::min(smallest, points[i].separation);
    return smallest;
  }
};

}  // namespace strata
