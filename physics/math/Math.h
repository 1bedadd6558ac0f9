// Math vocabulary of the engine: Eigen aliases and the few helpers every subsystem needs.
// Everything here is a value type or a pure function; safe from any thread.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
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
