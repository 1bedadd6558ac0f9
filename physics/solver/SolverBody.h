// SolverBody and SolverPose: the hot per-body data of one step's solve, copied out of Body when the step
// starts and written back when it ends, so the solver loops touch two compact arrays instead of Body.
// Index 0 of both arrays is the fixed body (zero velocity, zero inverse mass, identity pose) that stands in
// for static and sleeping bodies; active body k sits at index k + 1. Each slot is written by one job at a
// time.
#pragma once

#include "physics/math/Math.h"

namespace strata {

/// What the velocity solve reads and writes: 4-wide vectors (w = 0) so the loops map to SIMD registers.
struct alignas(16) SolverBody {
  Vec4 linear_velocity = Vec4::Zero();   ///< of the centre of mass, m/s
  Vec4 angular_velocity = Vec4::Zero();  ///< rad/s, world
  Vec4 inverse_inertia[3] = {Vec4::Zero(), Vec4::Zero(),
                             Vec4::Zero()};  ///< world, by column (0 unless dynamic)
  /// How far the centre of mass moved and the body turned (rotation vector) since the step began: contacts
  /// track their separation from these instead of re-reading poses every substep.
  Vec4 delta_position = Vec4::Zero();
  Vec4 delta_rotation = Vec4::Zero();
  float inverse_mass = 0.0f;  ///< 0 for static, kinematic and sleeping bodies

  /// Inverse inertia times `v` (w of `v` must be 0).
  Vec4 InverseInertiaTimes(const Vec4& v) const {
    return inverse_inertia[0] * v.x() + inverse_inertia[1] * v.y() + inverse_inertia[2] * v.z();
  }
};

/// Where a solver body is: integration and position correction move it.
struct alignas(16) SolverPose {
  Vec4 center_of_mass = Vec4::Zero();  ///< world, w = 0
  Quat rotation = Quat::Identity();
};

/// The velocity a dynamic body gains per substep from gravity and applied forces and torques, and, for a
/// body whose spin precesses, its inertia (shape axes) for the gyroscopic step of each substep.
struct alignas(16) SolverVelocityStep {
  Vec4 linear = Vec4::Zero();
  Vec4 angular = Vec4::Zero();
  Mat3 inertia = Mat3::Zero();
  bool gyroscopic = false;
};

/// Makes a 4-wide vector (w = 0) from a 3-vector.
inline Vec4 ToVec4(const Vec3& v) {
  return {v.x(), v.y(), v.z(), 0.0f};
}
/// Drops w.
inline Vec3 ToVec3(const Vec4& v) {
  return v.head<3>();
}
/// Cross product of two 4-wide vectors (w of the result is 0).
inline Vec4 Cross(const Vec4& a, const Vec4& b) {
  return a.cross3(b);
}

}  // namespace strata
