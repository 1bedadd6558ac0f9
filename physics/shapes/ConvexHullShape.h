// ConvexHullShape: a convex polyhedron built from a point cloud with QuickHull. Immutable; thread-safe.
#pragma once

#include <span>

#include "physics/core/Result.h"
#include "physics/shapes/ConvexShape.h"
#include "physics/shapes/QuickHull.h"

namespace strata {

/// Convex polyhedron, its edges and corners rounded by a convex radius inside its faces (Jolt's convention):
/// the core is the hull with every face plane moved in by the radius, and the shape is that core plus the
/// radius, so the faces stay where the points put them. A sharp hull (radius 0) keeps a core scaled towards
/// its interior point, every face at least a small core radius in, for GJK's sake.
class ConvexHullShape final : public ConvexShape {
 public:
  /// Fails for fewer than 4 points, NaN/Inf, or points without volume (coincident, collinear, coplanar).
  /// The hull is rounded by kDefaultConvexRadius, or a quarter of its interior's depth (the distance from
  /// the vertices' centroid to the nearest face) where that is less.
  static Result<ShapeRef> Create(std::span<const Vec3> points);
  /// Fails as above, and for a convex radius that is negative, not finite, or over half the interior's depth.
  static Result<ShapeRef> Create(std::span<const Vec3> points, float convex_radius);
  /// Unchecked: the Create forms say what they need. `rounded_core` is the core of a rounded hull (no
  /// vertices for a sharp one, whose core is the hull scaled by `core_scale` towards `interior_point`).
  ConvexHullShape(HullData hull, const Vec3& interior_point, float core_radius, float core_scale,
                  HullData rounded_core);

  const std::vector<Vec3>& vertices() const { return hull_.vertices; }
  const std::vector<HullFace>& faces() const { return hull_.faces; }
  /// Each undirected edge once, as vertex index pairs.
  const std::vector<std::array<int, 2>>& edges() const { return edges_; }
  /// One unit direction per set of parallel edges (the separating-axis candidates).
  const std::vector<Vec3>& edge_directions() const { return edge_directions_; }
  /// The two faces each edge joins (same order as edges()).
  const std::vector<std::array<int, 2>>& edge_faces() const { return edge_faces_; }

  AABB LocalBounds() const override { return bounds_; }
  MassProperties ComputeMassProperties(float density) const override;
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;
  Vec3 Support(const Vec3& direction) const override;
  Vec3 CoreSupport(const Vec3& direction) const override;
  /// The hull's own face, to its sharp edges: manifolds clip these (Jolt does the same).
  void GetSupportingFace(const Vec3& direction, SupportingFace& face) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  bool CastRaySharp(const Vec3& origin, const Vec3& direction, float max_fraction, ShapeRayHit& hit) const;
  static Vec3 Farthest(const std::vector<Vec3>& points, const Vec3& direction);
  /// The rounded core's point nearest to `point` (the point itself inside).
  Vec3 ClosestOnCore(const Vec3& point) const;

  HullData hull_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<Vec3> edge_directions_;
  std::vector<std::array<int, 2>> edge_faces_;
  AABB bounds_;
  Vec3 interior_point_;
  float core_scale_;
  HullData core_;
};

}  // namespace strata
