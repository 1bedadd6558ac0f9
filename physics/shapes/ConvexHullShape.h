// ConvexHullShape: a convex polyhedron built from a point cloud with QuickHull. Immutable; thread-safe.
#pragma once

#include <span>

#include "physics/core/Result.h"
#include "physics/shapes/ConvexShape.h"
#include "physics/shapes/QuickHull.h"

namespace strata {

/// Convex polyhedron. The GJK core is the hull scaled towards its interior point so that every face
/// moves in by at least the core radius.
class ConvexHullShape final : public ConvexShape {
 public:
  /// Fails for fewer than 4 points, NaN/Inf, or points without volume (coincident, collinear, coplanar).
  static Result<ShapeRef> Create(std::span<const Vec3> points);
  ConvexHullShape(HullData hull, const Vec3& interior_point, float core_radius, float core_scale);

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
  Vec3 CoreSupport(const Vec3& direction) const override {
    return interior_point_ + core_scale_ * (Support(direction) - interior_point_);
  }
  void GetSupportingFace(const Vec3& direction, SupportingFace& face) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  HullData hull_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<Vec3> edge_directions_;
  std::vector<std::array<int, 2>> edge_faces_;
  AABB bounds_;
  Vec3 interior_point_;
  float core_scale_;
};

}  // namespace strata
