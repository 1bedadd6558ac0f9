#include "physics/narrowphase/ShapeCast.h"

#include "physics/narrowphase/CollisionDispatch.h"
#include "physics/narrowphase/Gjk.h"

namespace strata {

namespace {

constexpr int kMaxAdvances = 32;

// Conservative advancement against one convex target (translation only: along the line the distance is a
// convex function of t, so a step of distance / closing speed never passes the first touch).
std::optional<ShapeCastHit> Advance(const ConvexShape& shape, const Pose& start, const Vec3& displacement,
                                    const ConvexSupport& target, float tolerance) {
  float t = 0.0f;
  for (int advance = 0; advance < kMaxAdvances; ++advance) {
    const Pose pose{start.position + t * displacement, start.rotation};
    const PosedConvex swept(shape, pose, false);
    const GjkResult closest = GjkClosestPoints(swept, target, kLargeFloat);
    if (closest.overlapping) return std::nullopt;  // overlapping at the start, or a GJK miss: contacts' job
    const Vec3 normal = (closest.point_a - closest.point_b) / std::max(closest.distance, 1e-12f);
    if (closest.distance <= tolerance) return ShapeCastHit{t, normal, closest.point_b};
    const float closing = -displacement.dot(normal);
    if (closing <= 0.0f) return std::nullopt;  // moving away along the closest direction: never touches
    t += (closest.distance - 0.5f * tolerance) / closing;
    if (t > 1.0f) return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

std::optional<ShapeCastHit> CastOntoConvex(const ConvexShape& shape, const Pose& start,
                                           const Vec3& displacement, const Shape& target,
                                           const Pose& target_pose, float tolerance,
                                           std::vector<Triangle>& /*triangles*/) {
  return Advance(shape, start, displacement,
                 PosedConvex(static_cast<const ConvexShape&>(target), target_pose, false), tolerance);
}

std::optional<ShapeCastHit> CastOntoTriangles(const ConvexShape& shape, const Pose& start,
                                              const Vec3& displacement, const Shape& target,
                                              const Pose& target_pose, float tolerance,
                                              std::vector<Triangle>& triangles) {
  // Every triangle near the swept bounds, nearest hit wins.
  AABB swept = shape.WorldBounds(start);
  AABB end = swept;
  end.min += displacement;
  end.max += displacement;
  swept.Encapsulate(end);
  triangles.clear();
  target.GetTrianglesInBox(swept.Expanded(tolerance), target_pose, triangles);
  std::optional<ShapeCastHit> nearest;
  for (const Triangle& world : triangles) {
    const TriangleSupport triangle(world.vertices[0], world.vertices[1], world.vertices[2]);
    const std::optional<ShapeCastHit> hit = Advance(shape, start, displacement, triangle, tolerance);
    if (hit && (!nearest || hit->fraction < nearest->fraction)) nearest = hit;
  }
  return nearest;
}

std::optional<ShapeCastHit> CastConvexShape(const ConvexShape& shape, const Pose& start,
                                            const Vec3& displacement, const Shape& target,
                                            const Pose& target_pose, float tolerance,
                                            std::vector<Triangle>& triangles) {
  return CollisionDispatch::Default().Cast(shape, start, displacement, target, target_pose, tolerance,
                                           triangles);
}

}  // namespace strata
