// QuickHull: builds the convex hull of a point cloud as polygon faces (coplanar triangles merged).
// Pure function over its input; safe from any thread.
#pragma once

#include <span>
#include <vector>

#include "physics/core/Result.h"
#include "physics/math/AABB.h"

namespace strata {

/// A planar, convex face of a hull: vertex indices counter-clockwise seen from outside, and its plane.
struct HullFace {
  std::vector<int> vertices;
  Vec3 normal;   ///< outward unit normal
  float offset;  ///< plane: normal . x == offset
};

/// A closed convex polyhedron: only the points that are hull vertices, and its faces.
struct HullData {
  std::vector<Vec3> vertices;
  std::vector<HullFace> faces;
};

/// Convex hull of `points`. Fails with kDegenerateShape when fewer than 4 points span a volume
/// (all coincident, collinear or coplanar) and kInvalidArgument for NaN/Inf coordinates.
Result<HullData> BuildConvexHull(std::span<const Vec3> points);

}  // namespace strata
