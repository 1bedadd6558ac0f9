// AABB: axis-aligned bounding box, the currency of the broad phase and of navmesh gathering.
// Value type; safe from any thread.
#pragma once

#include <algorithm>

#include "physics/math/Math.h"

namespace strata {

/// Axis-aligned box [min, max]. An empty box is inside out (min > max) so it overlaps nothing.
struct AABB {
  Vec3 min = Vec3::Constant(kLargeFloat);
  Vec3 max = Vec3::Constant(-kLargeFloat);

  AABB() = default;
  AABB(const Vec3& lo, const Vec3& hi) : min(lo), max(hi) {}

  static AABB FromCenterHalfExtents(const Vec3& center, const Vec3& half) {
    return {center - half, center + half};
  }

  /// True when min <= max on every axis and both corners are finite.
  bool IsValid() const { return IsFinite(min) && IsFinite(max) && (min.array() <= max.array()).all(); }
  bool IsEmpty() const { return (min.array() > max.array()).any(); }

  Vec3 Center() const { return 0.5f * (min + max); }
  Vec3 HalfExtents() const { return 0.5f * (max - min); }
  Vec3 Size() const { return max - min; }
  float SurfaceArea() const {
    const Vec3 d = Size();
    return 2.0f * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
  }

  bool Overlaps(const AABB& other) const {
    return (min.array() <= other.max.array()).all() && (other.min.array() <= max.array()).all();
  }
  bool Contains(const AABB& other) const {
    return (min.array() <= other.min.array()).all() && (other.max.array() <= max.array()).all();
  }
  bool Contains(const Vec3& p) const {
    return (min.array() <= p.array()).all() && (p.array() <= max.array()).all();
  }

  void Encapsulate(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void Encapsulate(const AABB& other) {
    min = min.cwiseMin(other.min);
    max = max.cwiseMax(other.max);
  }
  AABB Expanded(float margin) const { return {min.array() - margin, max.array() + margin}; }
  AABB Expanded(const Vec3& margin) const { return {min - margin, max + margin}; }

  /// The bounds of this box after rotating and translating it (tight for the rotated box).
  AABB Transformed(const Pose& pose) const {
    const Vec3 center = pose.ToWorld(Center());
    const Mat3 abs_rotation = pose.rotation.toRotationMatrix().cwiseAbs();
    const Vec3 half = abs_rotation * HalfExtents();
    return {center - half, center + half};
  }

  /// Slab test: entry fraction along origin + t * direction for t in [0, max_fraction], or a negative
  /// value when the ray misses. `inverse_direction` may hold +/-Inf for axis-parallel rays.
  float RayEntry(const Vec3& origin, const Vec3& inverse_direction, float max_fraction) const {
    float t_min = 0.0f;
    float t_max = max_fraction;
    for (int axis = 0; axis < 3; ++axis) {
      const float inv = inverse_direction[axis];
      float t1 = (min[axis] - origin[axis]) * inv;
      float t2 = (max[axis] - origin[axis]) * inv;
      // 0 * Inf gives NaN when the origin lies on a slab plane; treat that as inside the slab.
      if (std::isnan(t1)) t1 = -kLargeFloat;
      if (std::isnan(t2)) t2 = kLargeFloat;
      if (t1 > t2) std::swap(t1, t2);
      t_min = std::max(t_min, t1);
      t_max = std::min(t_max, t2);
      if (t_min > t_max) return -1.0f;
    }
    return t_min;
  }
};

/// Component-wise reciprocal that maps 0 to +Inf (for slab tests).
inline Vec3 SafeInverse(const Vec3& direction) {
  Vec3 inverse;
  for (int axis = 0; axis < 3; ++axis)
    inverse[axis] = direction[axis] != 0.0f ? 1.0f / direction[axis] : std::numeric_limits<float>::infinity();
  return inverse;
}

}  // namespace strata
