// Math vocabulary of the engine: Eigen aliases and the few helpers every subsystem needs.
// Everything here is a value type or a pure function; safe from any thread.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace strata {

using Vec3 = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;  ///< only where float positions would round motion away (large worlds)
using Vec4 = Eigen::Vector4f;
using Mat3 = Eigen::Matrix3f;
using Quat = Eigen::Quaternionf;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kLargeFloat = 1e30f;

/// True when every component is a finite number (no NaN, no Inf).
inline bool IsFinite(const Vec3& v) {
  return v.allFinite();
}
inline bool IsFinite(const Quat& q) {
  return q.coeffs().allFinite();
}
inline bool IsFinite(float f) {
  return std::isfinite(f);
}

/// atan2(y, x) within 1e-5 rad, by an odd polynomial on [0, 1] and the octant: the joints take their angles
/// every solver pass, where libm's atan2f was a twentieth of a ragdoll step. Pure arithmetic, so the same
/// answer on every platform; (0, 0) gives 0.
inline float FastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float big = std::max(ax, ay), small = std::min(ax, ay);
  if (big == 0.0f) return 0.0f;
  const float t = small / big, t2 = t * t;
  float angle =
      t * (0.99997726f +
           t2 * (-0.33262347f +
                 t2 * (0.19354346f + t2 * (-0.11643287f + t2 * (0.05265332f + t2 * -0.01172120f)))));
  if (ay > ax) angle = 0.5f * kPi - angle;
  if (x < 0.0f) angle = kPi - angle;
  return y < 0.0f ? -angle : angle;
}

/// A unit vector perpendicular to `n` (n must be unit length).
inline Vec3 AnyPerpendicular(const Vec3& n) {
  // Pick the axis least aligned with n so the cross product is well conditioned.
  const Vec3 axis = std::abs(n.x()) < 0.57735f ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(axis).normalized();
}

/// Cross-product matrix: Skew(a) * b == a.cross(b).
inline Mat3 Skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

/// Rigid transform (rotation then translation) of a shape or body.
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat rotation = Quat::Identity();

  Vec3 ToWorld(const Vec3& local) const { return rotation * local + position; }
  Vec3 ToLocal(const Vec3& world) const { return rotation.conjugate() * (world - position); }
  Vec3 DirectionToWorld(const Vec3& local) const { return rotation * local; }
  Vec3 DirectionToLocal(const Vec3& world) const { return rotation.conjugate() * world; }
};

}  // namespace strata
