// SolverBody and SolverPose: the hot per-body data of one step's solve, copied out of Body when the step
// starts and written back when it ends, so the solver loops touch two compact arrays instead of Body.
// Index 0 of both arrays is the fixed body (zero velocity, zero inverse mass, identity pose) that stands in
// for static and sleeping bodies; active body k sits at index k + 1. Each slot is written by one job at a
// time.
#pragma once

#include "physics/math/Math.h"

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

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
#if defined(__SSE2__)
  // Eigen's four-scalar constructor writes the lanes to memory one by one, and the next 4-wide load of them
  // cannot be forwarded from those stores: a stall of a dozen cycles each time, once the largest single cost
  // of a contact's set-up. Built in a register from the three lanes (no wide load of `v` either, which could
  // straddle the stores that just wrote it) and stored whole, the load is forwarded.
  Vec4 result;
  _mm_store_ps(result.data(), _mm_setr_ps(v.x(), v.y(), v.z(), 0.0f));
  return result;
#else
  return {v.x(), v.y(), v.z(), 0.0f};
#endif
}

/// Drops w.
inline Vec3 ToVec3(const Vec4& v) {
  return v.head<3>();
}
/// The world inverse inertia R I^-1 R^T (`rotation` R, `inverse_local` I^-1) as SolverBody's 4-wide columns.
/// Both products are taken a column at a time on 4-wide vectors (a third of the instructions of two scalar
/// 3x3 products), the terms summed in the order Eigen's 3x3 products sum them: x, y and z equal
/// rotation * inverse_local * rotation.transpose() to the bit (w is zero, of either sign).
inline void InverseInertiaColumns(const Mat3& rotation, const Mat3& inverse_local, Vec4 out[3]) {
  const Vec4 axes[3] = {ToVec4(rotation.col(0)), ToVec4(rotation.col(1)), ToVec4(rotation.col(2))};
  Vec4 rotated[3];  // R I^-1, by column
  for (int j = 0; j < 3; ++j)
    rotated[j] =
        axes[0] * inverse_local(0, j) + (axes[1] * inverse_local(1, j) + axes[2] * inverse_local(2, j));
  for (int j = 0; j < 3; ++j)
    out[j] = rotated[0] * rotation(j, 0) + (rotated[1] * rotation(j, 1) + rotated[2] * rotation(j, 2));
}

/// 4-wide columns times a 3-vector, summed in the order Eigen's Mat3 * Vec3 sums (x, y and z the same to the
/// bit).
inline Vec4 ColumnsTimes(const Vec4 columns[3], const Vec3& v) {
  return columns[0] * v.x() + (columns[1] * v.y() + columns[2] * v.z());
}

/// Turns `rotation` by rotation vector `turn` (w = 0) to first order and renormalises it: how integration and
/// position steps turn a body. The half turn is built whole in a register (see ToVec4).
inline void TurnBy(Quat& rotation, const Vec4& turn) {
  Quat half_turn;
  half_turn.coeffs() = 0.5f * turn;  // x, y, z and w = 0
  rotation.coeffs() += (half_turn * rotation).coeffs();
  rotation.normalize();
}

/// Cross product of two 4-wide vectors whose w is 0 (w of the result is 0).
inline Vec4 Cross(const Vec4& a, const Vec4& b) {
#if defined(__SSE2__)
  // Eigen's cross3 takes its scalar path here; in one register it is a third of the instructions. The lanes
  // take the same products and differences as the scalar formula, so the result is the same to the bit.
  const __m128 lhs = _mm_load_ps(a.data()), rhs = _mm_load_ps(b.data());
  const __m128 lhs_yzx = _mm_shuffle_ps(lhs, lhs, _MM_SHUFFLE(3, 0, 2, 1));
  const __m128 rhs_yzx = _mm_shuffle_ps(rhs, rhs, _MM_SHUFFLE(3, 0, 2, 1));
  const __m128 zxy = _mm_sub_ps(_mm_mul_ps(lhs, rhs_yzx), _mm_mul_ps(lhs_yzx, rhs));
  Vec4 result;
  _mm_store_ps(result.data(), _mm_shuffle_ps(zxy, zxy, _MM_SHUFFLE(3, 0, 2, 1)));
  return result;
#else
  return a.cross3(b);
#endif
}

}  // namespace strata
