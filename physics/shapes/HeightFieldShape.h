// HeightFieldShape: terrain as a grid of heights with holes: the triangles of the same TriangleMeshShape,
// found from the grid instead of a hierarchy. Immutable; thread-safe. Static and kinematic bodies only (no
// volume).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "physics/core/Result.h"
#include "physics/shapes/Shape.h"

namespace strata {

/// Heights at (column * cell_size, height, row * cell_size) in local space. Cell (x, z) spans columns x, x +
/// 1 and rows z, z + 1; its triangles are 2 (z (columns - 1) + x) and the one after, front faces up. A box
/// query visits the cells under the box; a ray walks the cells under its path (Amanatides and Woo).
class HeightFieldShape final : public Shape {
 public:
  /// A height that makes the cells around its sample holes (nothing there collides or is hit).
  static constexpr float kHole = std::numeric_limits<float>::quiet_NaN();
  /// Most samples in all (64 MiB of heights): a 4096 x 4096 grid, 1 m cells for a 4 km square.
  static constexpr std::uint64_t kMaxSamples = std::uint64_t{1} << 24;
  /// Largest height and extent along x or z (m): past this the float products of the triangle normals
  /// overflow.
  static constexpr float kMaxCoordinate = 1e7f;

  /// `heights` row after row (`columns` per row, `rows` rows). Fails for fewer than 2 x 2 samples or more
  /// than kMaxSamples, a count that is not columns x rows, a cell size that is not a positive
  /// finite number, an infinite height, heights or an extent beyond kMaxCoordinate, or no cell without a
  /// hole.
  static Result<ShapeRef> Create(std::uint32_t columns, std::uint32_t rows, float cell_size,
                                 std::span<const float> heights);
  HeightFieldShape(std::uint32_t columns, std::uint32_t rows, float cell_size, std::vector<float> heights);

  std::uint32_t columns() const { return columns_; }
  std::uint32_t rows() const { return rows_; }
  float cell_size() const { return cell_size_; }
  /// The sample at (column, row); NaN for a hole.
  float Height(std::uint32_t column, std::uint32_t row) const { return heights_[row * columns_ + column]; }
  /// Whether cell (x, z) is a hole (a corner of it is).
  bool IsHole(std::uint32_t x, std::uint32_t z) const;
  /// Triangle numbers run over every cell, holes included (a hole's triangles are never reported).
  std::size_t triangle_count() const { return 2 * static_cast<std::size_t>(columns_ - 1) * (rows_ - 1); }

  /// Corner `corner` (0..2) of triangle `triangle` in local space.
  Vec3 Vertex(std::uint32_t triangle, int corner) const;
  /// Unit normal of the triangle's front side, as TriangleMeshShape computes it.
  Vec3 Normal(std::uint32_t triangle) const;
  /// As TriangleMeshShape::ActiveEdges; an edge on the border or on a hole is real.
  std::uint8_t ActiveEdges(std::uint32_t triangle) const { return active_edges_[triangle]; }

  /// Appends, cell by cell, the triangles (not in holes) whose bounds overlap `local_box`.
  void QueryBox(const AABB& local_box, std::vector<std::uint32_t>& out) const;

  AABB LocalBounds() const override { return bounds_; }
  MassProperties ComputeMassProperties(float) const override { return {}; }
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  Vec3 Sample(std::uint32_t column, std::uint32_t row) const;
  // The sample indices (column, row) of a triangle's corners.
  void Corners(std::uint32_t triangle, std::uint32_t (&column)[3], std::uint32_t (&row)[3]) const;
  // The triangle across edge `edge` of `triangle` and its edge number there; false on the border.
  bool Neighbour(std::uint32_t triangle, int edge, std::uint32_t& other, int& other_edge) const;
  void ComputeActiveEdges();
  // Tests the two triangles of cell (x, z) against the ray; true when one is nearer than `best`.
  bool RayCell(std::uint32_t x, std::uint32_t z, const Vec3& origin, const Vec3& direction, float& best,
               std::uint32_t& best_triangle) const;

  std::uint32_t columns_;
  std::uint32_t rows_;
  float cell_size_;
  std::vector<float> heights_;
  std::vector<std::uint8_t> active_edges_;
  AABB bounds_;
};

}  // namespace strata
