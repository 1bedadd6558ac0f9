// ShapeCast: sweeps a convex shape along a straight line (no rotation) against another shape and finds the
// first time of impact, by conservative advancement on GJK distances: step forward by the distance over
// the closing speed, which can never pass the first touch. Used by the step's linear casts (fast bodies
// with MotionQuality::kLinearCast). Pure functions; call from any thread.
#pragma once

#include <optional>
#include <vector>

#include "physics/shapes/ConvexShape.h"

namespace strata {

/// Where a sweep first touches.
struct ShapeCastHit {
  float fraction = 1.0f;        ///< of the displacement travelled before touching, [0, 1]
  Vec3 normal = Vec3::UnitY();  ///< unit, from the target towards the swept shape
  Vec3 point = Vec3::Zero();    ///< on the target, world
};

/// Sweeps `shape` from `start` by `displacement` against `target` at `target_pose`, by the cast
/// CollisionDispatch::Default() holds for the target's type; nullopt when it does not touch within the
/// sweep, or when it already overlaps at the start (the contacts handle that). Hits are reported
/// `tolerance` metres before touching. `triangles` is scratch for targets made of triangles.
std::optional<ShapeCastHit> CastConvexShape(const ConvexShape& shape, const Pose& start,
                                            const Vec3& displacement, const Shape& target,
                                            const Pose& target_pose, float tolerance,
                                            std::vector<Triangle>& triangles);

// The casts CollisionDispatch::Default() registers (arguments as CastConvexShape).

/// Onto a convex target: conservative advancement on the GJK distance.
std::optional<ShapeCastHit> CastOntoConvex(const ConvexShape& shape, const Pose& start,
                                           const Vec3& displacement, const Shape& target,
                                           const Pose& target_pose, float tolerance,
                                           std::vector<Triangle>& triangles);
/// Onto a shape made of triangles: each triangle near the sweep (Shape::GetTrianglesInBox), nearest first.
std::optional<ShapeCastHit> CastOntoTriangles(const ConvexShape& shape, const Pose& start,
                                              const Vec3& displacement, const Shape& target,
                                              const Pose& target_pose, float tolerance,
                                              std::vector<Triangle>& triangles);

}  // namespace strata
