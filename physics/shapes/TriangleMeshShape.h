// TriangleMeshShape: static level geometry as an indexed triangle list with its own 4-wide bounding volume
// hierarchy (each node holds its four children's bounds side by side, each leaf its four triangles' bounds,
// so every test is one packed compare), built once at creation. Immutable; thread-safe.
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
  /// Neighbours whose normals differ by less than this (about 5 degrees) are one surface: the edge between
  /// them is internal.
  static constexpr float kCoplanarCosine = 0.996f;

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

  AABB LocalBounds() const override { return bounds_; }
  MassProperties ComputeMassProperties(float) const override { return {}; }
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  /// Four boxes side by side, tested together: a node's children or a leaf's triangles.
  struct alignas(16) Bounds4 {
    float min_x[4], min_y[4], min_z[4], max_x[4], max_y[4], max_z[4];
    /// Bit i set where box i overlaps `box`.
    int OverlapMask(const AABB& box) const;
    /// Ray entry fraction of each box (negative where it misses) into `entry`.
    void RayEntries(const Vec3& origin, const Vec3& inverse_direction, float max_fraction,
                    float* entry) const;
  };
  /// Child slot encoding: a node index, a leaf (kLeaf | leaf index) or kEmpty.
  static constexpr std::uint32_t kLeaf = 0x80000000u;
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  struct Node {
    Bounds4 bounds;
    std::uint32_t child[4];
  };
  /// Up to four triangles; empty lanes have inside-out bounds and triangle kEmpty.
  struct Leaf {
    Bounds4 bounds;
    std::uint32_t triangle[4];
  };

  void BuildHierarchy();
  void ComputeActiveEdges();

  std::vector<Vec3> vertices_;
  std::vector<Indices> triangles_;
  std::vector<Vec3> normals_;
  std::vector<std::uint8_t> active_edges_;
  std::vector<Node> nodes_;
  std::vector<Leaf> leaves_;
  std::uint32_t root_ = kEmpty;  // a node, or a leaf for meshes of up to four triangles
  AABB bounds_;
};

/// The local-space triangles a box query of `shape` (a TriangleMeshShape or anything with its QueryBox and
/// Vertex) reports for `local_box`, appended to `out`: what such a shape's CollectLocalTriangles gives.
template <class TriangleShape>
void AppendTrianglesInBox(const TriangleShape& shape, const AABB& local_box, std::vector<Triangle>& out) {
  std::vector<std::uint32_t> hits;
  shape.QueryBox(local_box, hits);
  for (const std::uint32_t t : hits)
    out.push_back({{shape.Vertex(t, 0), shape.Vertex(t, 1), shape.Vertex(t, 2)}});
}

/// Moller-Trumbore ray/triangle test; returns the fraction or -1 (both sides count).
float RayTriangle(const Vec3& origin, const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace strata
