// ShapeQueries: the narrow-phase answers of the point and distance queries (WorldQuery::CollidePoint and
// ClosestPoint): whether a shape holds a point, and the closest points between a convex query (a shape or a
// point) and any shape. Pure functions; any thread.
#pragma once

#include <optional>
#include <vector>

#include "physics/narrowphase/ConvexSupport.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

/// Whether `shape` at `pose` holds `point`: inside a convex solid (its surface included); for meshes and
/// height fields, an odd number of crossings of their triangles straight up from the point (inside a closed
/// mesh, below a height field's surface).
bool ShapeContainsPoint(const Shape& shape, const Pose& pose, const Vec3& point,
                        std::vector<Triangle>& triangles);

/// A convex query as a distance query sees it: a support mapping (world space) and a radius around it.
struct DistanceQuery {
  const ConvexSupport& support;
  float radius = 0.0f;
  AABB bounds;  ///< world bounds of the query, radius included
};

/// Closest points of a query and a shape.
struct ClosestPoints {
  float distance = 0.0f;  ///< between the surfaces, >= 0 (0 when they touch or overlap)
  Vec3 on_shape = Vec3::Zero();
  Vec3 on_query = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();  ///< unit, from the shape towards the query (meaningless at distance 0)
};

/// The closest points of `query` and `shape` at `pose` if they are within `max_distance`; a shape made of
/// triangles answers with its nearest triangle.
std::optional<ClosestPoints> ClosestPointsTo(const DistanceQuery& query, const Shape& shape, const Pose& pose,
                                             float max_distance, std::vector<Triangle>& triangles);

}  // namespace strata
