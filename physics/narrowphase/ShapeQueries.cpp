#include "physics/narrowphase/ShapeQueries.h"

#include "physics/narrowphase/Gjk.h"

namespace strata {

namespace {

// Straight up, tipped a little off the axes: a ray along an axis through a grid of triangles (a height
// field's, a level's floor) would run through shared edges and vertices and count one crossing twice.
const Vec3 kCrossingDirection = Vec3(0.0123f, 1.0f, 0.0217f).normalized();

// Whether the ray from `origin` along `direction` (t > 0) crosses triangle (a, b, c) (Moller-Trumbore).
bool Crosses(const Vec3& origin, const Vec3& direction, const Triangle& triangle) {
  const Vec3 edge1 = triangle.vertices[1] - triangle.vertices[0];
  const Vec3 edge2 = triangle.vertices[2] - triangle.vertices[0];
  const Vec3 p = direction.cross(edge2);
  const float determinant = edge1.dot(p);
  if (std::abs(determinant) < 1e-12f) return false;  // the ray runs along the triangle's plane
  const float inverse = 1.0f / determinant;
  const Vec3 s = origin - triangle.vertices[0];
  const float u = s.dot(p) * inverse;
  if (u < 0.0f || u > 1.0f) return false;
  const Vec3 q = s.cross(edge1);
  const float v = direction.dot(q) * inverse;
  if (v < 0.0f || u + v > 1.0f) return false;
  return edge2.dot(q) * inverse > 0.0f;
}

// Closest points of the query and one convex support with `radius` around it, if within `max_distance`.
std::optional<ClosestPoints> Closest(const DistanceQuery& query, const ConvexSupport& target, float radius,
                                     float max_distance) {
  const float radii = query.radius + radius;
  const GjkResult closest = GjkClosestPoints(query.support, target, max_distance + radii);
  ClosestPoints result;
  if (closest.overlapping) {
    result.on_shape = result.on_query = query.support.Center();
    return result;
  }
  if (closest.distance - radii > max_distance) return std::nullopt;
  const Vec3 normal = (closest.point_a - closest.point_b) / std::max(closest.distance, 1e-12f);
  result.distance = std::max(0.0f, closest.distance - radii);
  result.normal = normal;
  result.on_shape = closest.point_b + radius * normal;
  result.on_query = closest.point_a - query.radius * normal;
  return result;
}

}  // namespace

bool ShapeContainsPoint(const Shape& shape, const Pose& pose, const Vec3& point,
                        std::vector<Triangle>& triangles) {
  if (shape.IsConvex()) {
    const PosedConvex solid(static_cast<const ConvexShape&>(shape), pose, false);
    const GjkResult closest = GjkClosestPoints(PointSupport(point), solid, 0.0f);
    return closest.overlapping || closest.distance <= 1e-6f;
  }
  const AABB bounds = shape.WorldBounds(pose);
  if (!bounds.Contains(Vec3(point.x(), std::min(point.y(), bounds.max.y()), point.z()))) return false;
  // The ray from the point to above the shape, and the triangles near it.
  const float rise = bounds.max.y() - point.y() + 1.0f;
  const Vec3 top = point + (rise / kCrossingDirection.y()) * kCrossingDirection;
  AABB column(point, point);
  column.Encapsulate(top);
  triangles.clear();
  shape.GetTrianglesInBox(column.Expanded(1e-4f), pose, triangles);
  int crossings = 0;
  for (const Triangle& triangle : triangles)
    crossings += Crosses(point, kCrossingDirection, triangle) ? 1 : 0;
  return (crossings & 1) != 0;
}

std::optional<ClosestPoints> ClosestPointsTo(const DistanceQuery& query, const Shape& shape, const Pose& pose,
                                             float max_distance, std::vector<Triangle>& triangles) {
  if (shape.IsConvex()) {
    const MeasuredConvex measured(static_cast<const ConvexShape&>(shape), pose);
    return Closest(query, measured.support, measured.radius, max_distance);
  }
  triangles.clear();
  shape.GetTrianglesInBox(query.bounds.Expanded(max_distance), pose, triangles);
  std::optional<ClosestPoints> nearest;
  for (const Triangle& triangle : triangles) {
    const TriangleSupport support(triangle.vertices[0], triangle.vertices[1], triangle.vertices[2]);
    const float reach = nearest ? nearest->distance : max_distance;
    std::optional<ClosestPoints> found = Closest(query, support, 0.0f, reach);
    if (found && (!nearest || found->distance < nearest->distance)) nearest = found;
  }
  return nearest;
}

}  // namespace strata
