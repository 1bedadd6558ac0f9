// TriangleMeshShape: static level geometry as an indexed triangle list with its own bounding volume
// hierarchy, built once at creation (1M+ triangles load in about a second). Immutable; thread-safe.
// Only static and kinematic bodies may use it (it has no volume, so no mass).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "physics/core/Result.h"
#include "physics/shapes/Shape.h"

namespace strata {

/// Indexed triangle mesh plus BVH. Triangle i keeps its index from the input (after dropping degenerate
/// triangles the survivors keep their relative order), which is the contact and ray-hit sub-shape id.
class TriangleMeshShape final : public Shape {
 public:
  using Indices = std::array<std::uint32_t, 3>;

  /// Fails for no vertices or triangles, NaN/Inf vertices, out-of-range indices, or when every triangle
  /// is degenerate. Degenerate (zero-area) triangles are dropped.
  static Result<ShapeRef> Create(std::span<const Vec3> vertices, std::span<const Indices> triangles);
  TriangleMeshShape(std::vector<Vec3> vertices, std::vector<Indices> triangles);

  std::size_t triangle_count() const { return triangles_.size(); }
  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<Indices>& triangles() const { return triangles_; }

  /// Corner `corner` (0..2) of triangle `triangle` in local space.
  const Vec3& Vertex(std::uint32_t triangle, int corner) const {
    return vertices_[triangles_[triangle][corner]];
  }
  /// Unit normal of the triangle's front side (counter-clockwise winding).
  const Vec3& Normal(std::uint32_t triangle) const { return normals_[triangle]; }
  /// Bit k set = edge (k, k+1) is a real convex or boundary edge; unset = an internal edge between
  /// (near-)coplanar or concave neighbours, which contacts must not catch on.
  std::uint8_t ActiveEdges(std::uint32_t triangle) const { return active_edges_[triangle]; }

  /// Appends indices of triangles whose bounds overlap `local_box`.
  void QueryBox(const AABB& local_box, std::vector<std::uint32_t>& out) const;

  AABB LocalBounds() const override { return nodes_.empty() ? AABB() : nodes_[0].bounds; }
  MassProperties ComputeMassProperties(float) const override { return {}; }
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  /// BVH node: an inner node's children are at `first` and `first + 1`; a leaf covers
  /// leaf_triangles_[first, first + count).
  struct Node {
    AABB bounds;
    std::uint32_t first = 0;
    std::uint32_t count = 0;  // 0 = inner node
  };

  void BuildHierarchy();
  void ComputeActiveEdges();

  std::vector<Vec3> vertices_;
  std::vector<Indices> triangles_;
  std::vector<Vec3> normals_;
  std::vector<std::uint8_t> active_edges_;
  std::vector<std::uint32_t> leaf_triangles_;
  std::vector<Node> nodes_;
};

/// Moller-Trumbore ray/triangle test; returns the fraction or -1 (both sides count).
float RayTriangle(const Vec3& origin, const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace strata
