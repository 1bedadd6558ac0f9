// SleepSpheres: the movement record of SleepRule::kPointMovement: for three points of a body, the smallest
// sphere holding every place the point has been since the body last moved too far. Plain data, one per body
// slot; the step's finish jobs each touch only their own islands' bodies.
#pragma once

#include <array>

#include "physics/body/Body.h"

namespace strata {

struct SleepSpheres {
  struct Sphere {
    Vec3 center = Vec3::Zero();
    float radius = -1.0f;  ///< < 0: no record yet
  };
  std::array<Sphere, 3> spheres;

  /// The points the rule watches: the centre of mass, and the centre of mass moved out along the body's two
  /// longest local bounds axes by their half extents.
  static std::array<Vec3, 3> TestPoints(const Body& body) {
    const Vec3 center = body.CenterOfMass();
    const Vec3 half = body.local_bounds().HalfExtents();
    Eigen::Index shortest = 0;
    half.minCoeff(&shortest);
    const Mat3 axes = body.rotation().toRotationMatrix();
    std::array<Vec3, 3> points{center, center, center};
    int next = 1;
    for (Eigen::Index axis = 0; axis < 3; ++axis)
      if (axis != shortest) points[next++] += half[axis] * axes.col(axis);
    return points;
  }

  /// Grows each sphere to hold its point's new place. Returns false, and starts the record again from the
  /// points, when a sphere grew wider than `max_radius` (or there was no record).
  bool StayedWithin(const std::array<Vec3, 3>& points, float max_radius) {
    bool within = true;
    for (std::size_t i = 0; i < spheres.size() && within; ++i)
      within = Grow(spheres[i], points[i], max_radius);
    if (within) return true;
    for (std::size_t i = 0; i < spheres.size(); ++i) spheres[i] = {points[i], 0.0f};
    return false;
  }

 private:
  // The smallest sphere holding `sphere` and `point`.
  static bool Grow(Sphere& sphere, const Vec3& point, float max_radius) {
    if (sphere.radius < 0.0f) return false;
    const Vec3 offset = point - sphere.center;
    const float distance = offset.norm();
    if (distance <= sphere.radius) return true;
    const float radius = 0.5f * (sphere.radius + distance);
    sphere.center += ((radius - sphere.radius) / distance) * offset;
    sphere.radius = radius;
    return radius <= max_radius;
  }
};

}  // namespace strata
