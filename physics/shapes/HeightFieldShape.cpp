#include "physics/shapes/HeightFieldShape.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "physics/shapes/TriangleMeshShape.h"

namespace strata {

Result<ShapeRef> HeightFieldShape::Create(std::uint32_t columns, std::uint32_t rows, float cell_size,
                                          std::span<const float> heights) {
  if (columns < 2 || rows < 2 || static_cast<std::uint64_t>(columns) * rows > kMaxSamples)
    return MakeError(ErrorCode::kInvalidArgument, "height field needs 2 x 2 to " +
                                                      std::to_string(kMaxSamples) + " samples, got " +
                                                      std::to_string(columns) + " x " + std::to_string(rows));
  if (heights.size() != static_cast<std::size_t>(columns) * rows)
    return MakeError(ErrorCode::kInvalidArgument, "height field of " + std::to_string(columns) + " x " +
                                                      std::to_string(rows) + " samples got " +
                                                      std::to_string(heights.size()) + " heights");
  if (!IsFinite(cell_size) || cell_size <= 0.0f)
    return MakeError(
        ErrorCode::kInvalidArgument,
        "height field cell size must be a positive finite number, got " + std::to_string(cell_size));
  const float extent = static_cast<float>(std::max(columns, rows) - 1) * cell_size;
  if (extent > kMaxCoordinate)
    return MakeError(ErrorCode::kInvalidArgument, "height field spans " + std::to_string(extent) +
                                                      " m, more than " + std::to_string(kMaxCoordinate));
  // NaN is a hole; anything else must be a height the normals' products can take (not infinite either).
  for (std::size_t i = 0; i < heights.size(); ++i)
    if (std::abs(heights[i]) > kMaxCoordinate)
      return MakeError(ErrorCode::kInvalidArgument,
                       "height field sample " + std::to_string(i) + " (column " +
                           std::to_string(i % columns) + ", row " + std::to_string(i / columns) + ") is " +
                           std::to_string(heights[i]) + ": heights must be finite and within 1e7 m");
  auto shape = std::make_shared<HeightFieldShape>(columns, rows, cell_size,
                                                  std::vector<float>(heights.begin(), heights.end()));
  if (!shape->bounds_.IsValid())
    return MakeError(ErrorCode::kDegenerateShape, "every cell of the height field is a hole");
  return ShapeRef(std::move(shape));
}

HeightFieldShape::HeightFieldShape(std::uint32_t columns, std::uint32_t rows, float cell_size,
                                   std::vector<float> heights)
    : Shape(ShapeType::kHeightField, false),
      columns_(columns),
      rows_(rows),
      cell_size_(cell_size),
      heights_(std::move(heights)) {
  // The bounds of the cells that are not holes: a sample only holes touch adds nothing.
  for (std::uint32_t z = 0; z + 1 < rows_; ++z)
    for (std::uint32_t x = 0; x + 1 < columns_; ++x) {
      if (IsHole(x, z)) continue;
      for (std::uint32_t corner = 0; corner < 4; ++corner)
        bounds_.Encapsulate(Sample(x + (corner & 1), z + (corner >> 1)));
    }
  ComputeActiveEdges();
}

bool HeightFieldShape::IsHole(std::uint32_t x, std::uint32_t z) const {
  return std::isnan(Height(x, z)) || std::isnan(Height(x + 1, z)) || std::isnan(Height(x, z + 1)) ||
         std::isnan(Height(x + 1, z + 1));
}

Vec3 HeightFieldShape::Sample(std::uint32_t column, std::uint32_t row) const {
  return {static_cast<float>(column) * cell_size_, Height(column, row), static_cast<float>(row) * cell_size_};
}

void HeightFieldShape::Corners(std::uint32_t triangle, std::uint32_t (&column)[3],
                               std::uint32_t (&row)[3]) const {
  const std::uint32_t cell = triangle / 2, x = cell % (columns_ - 1), z = cell / (columns_ - 1);
  // Front faces up: (x, z), (x, z + 1), (x + 1, z), then (x + 1, z), (x, z + 1), (x + 1, z + 1).
  if (triangle % 2 == 0) {
    column[0] = x, column[1] = x, column[2] = x + 1;
    row[0] = z, row[1] = z + 1, row[2] = z;
  } else {
    column[0] = x + 1, column[1] = x, column[2] = x + 1;
    row[0] = z, row[1] = z + 1, row[2] = z + 1;
  }
}

Vec3 HeightFieldShape::Vertex(std::uint32_t triangle, int corner) const {
  std::uint32_t column[3], row[3];
  Corners(triangle, column, row);
  return Sample(column[corner], row[corner]);
}

Vec3 HeightFieldShape::Normal(std::uint32_t triangle) const {
  const Vec3 a = Vertex(triangle, 0);
  return (Vertex(triangle, 1) - a).cross(Vertex(triangle, 2) - a).normalized();
}

bool HeightFieldShape::Neighbour(std::uint32_t triangle, int edge, std::uint32_t& other,
                                 int& other_edge) const {
  const std::uint32_t cell = triangle / 2, x = cell % (columns_ - 1), z = cell / (columns_ - 1);
  const std::uint32_t cells_across = columns_ - 1;
  // Edges in corner order (see Corners): the first triangle's run down the left side, across the diagonal
  // and back along the near side; the second's across the diagonal, along the far side and up the right.
  if (triangle % 2 == 0) {
    switch (edge) {
      case 0:
        if (x == 0) return false;
        other = 2 * (cell - 1) + 1, other_edge = 2;
        return true;
      case 1:
        other = triangle + 1, other_edge = 0;
        return true;
      default:
        if (z == 0) return false;
        other = 2 * (cell - cells_across) + 1, other_edge = 1;
        return true;
    }
  }
  switch (edge) {
    case 0:
      other = triangle - 1, other_edge = 1;
      return true;
    case 1:
      if (z + 2 >= rows_) return false;
      other = 2 * (cell + cells_across), other_edge = 2;
      return true;
    default:
      if (x + 2 >= columns_) return false;
      other = 2 * (cell + 1), other_edge = 0;
      return true;
  }
}

void HeightFieldShape::ComputeActiveEdges() {
  // The rule of TriangleMeshShape::ComputeActiveEdges for each shared edge, with the two triangles in the
  // same roles (the lower number is the one seen first), so a grid and its mesh flag the same edges.
  active_edges_.assign(triangle_count(), 0b111);
  for (std::uint32_t z = 0; z + 1 < rows_; ++z)
    for (std::uint32_t x = 0; x + 1 < columns_; ++x) {
      if (IsHole(x, z)) continue;
      const std::uint32_t first = 2 * (z * (columns_ - 1) + x);
      for (std::uint32_t t = first; t < first + 2; ++t)
        for (int edge = 0; edge < 3; ++edge) {
          std::uint32_t other = 0;
          int other_edge = 0;
          if (!Neighbour(t, edge, other, other_edge) || other > t) continue;
          const std::uint32_t other_cell = other / 2;
          if (IsHole(other_cell % (columns_ - 1), other_cell / (columns_ - 1))) continue;
          const Vec3 opposite = Vertex(t, (edge + 2) % 3);
          const Vec3 other_normal = Normal(other);
          const bool convex = other_normal.dot(opposite - Vertex(other, 0)) < 0.0f;
          const bool flat = Normal(t).dot(other_normal) > TriangleMeshShape::kCoplanarCosine;
          if (flat || !convex) {
            active_edges_[t] &= static_cast<std::uint8_t>(~(1u << edge));
            active_edges_[other] &= static_cast<std::uint8_t>(~(1u << other_edge));
          }
        }
    }
}

void HeightFieldShape::QueryBox(const AABB& local_box, std::vector<std::uint32_t>& out) const {
  if (!bounds_.Overlaps(local_box)) return;
  // The cells under the box (a float clamp first, so a box far outside never overflows the cast).
  auto cell_range = [&](float low, float high, std::uint32_t cells, std::uint32_t& first,
                        std::uint32_t& last) {
    const float top = static_cast<float>(cells - 1);
    // One cell more on the low side: a triangle whose bounds end on the box's lower face touches it.
    first = static_cast<std::uint32_t>(std::clamp(std::floor(low / cell_size_) - 1.0f, 0.0f, top));
    last = static_cast<std::uint32_t>(std::clamp(std::floor(high / cell_size_), 0.0f, top));
  };
  std::uint32_t x0, x1, z0, z1;
  cell_range(local_box.min.x(), local_box.max.x(), columns_ - 1, x0, x1);
  cell_range(local_box.min.z(), local_box.max.z(), rows_ - 1, z0, z1);
  for (std::uint32_t z = z0; z <= z1; ++z)
    for (std::uint32_t x = x0; x <= x1; ++x) {
      if (IsHole(x, z)) continue;
      const std::uint32_t first = 2 * (z * (columns_ - 1) + x);
      for (std::uint32_t t = first; t < first + 2; ++t) {
        AABB bounds;
        for (int corner = 0; corner < 3; ++corner) bounds.Encapsulate(Vertex(t, corner));
        if (bounds.Overlaps(local_box)) out.push_back(t);
      }
    }
}

bool HeightFieldShape::RayCell(std::uint32_t x, std::uint32_t z, const Vec3& origin, const Vec3& direction,
                               float& best, std::uint32_t& best_triangle) const {
  if (IsHole(x, z)) return false;
  bool found = false;
  const std::uint32_t first = 2 * (z * (columns_ - 1) + x);
  for (std::uint32_t t = first; t < first + 2; ++t) {
    const float fraction = RayTriangle(origin, direction, Vertex(t, 0), Vertex(t, 1), Vertex(t, 2));
    if (fraction >= 0.0f && fraction <= best) best = fraction, best_triangle = t, found = true;
  }
  return found;
}

bool HeightFieldShape::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                               ShapeRayHit& hit) const {
  const float enter = bounds_.RayEntry(origin, SafeInverse(direction), max_fraction);
  if (enter < 0.0f) return false;
  // Walk the cells under the ray from where it enters the bounds (Amanatides and Woo): each cell's
  // triangles lie over the cell, so the first cell with a hit holds the nearest one.
  const Vec3 start = origin + enter * direction;
  const auto cell_of = [&](float coordinate, std::uint32_t cells) {
    return static_cast<std::uint32_t>(
        std::clamp(std::floor(coordinate / cell_size_), 0.0f, static_cast<float>(cells - 1)));
  };
  std::int64_t x = cell_of(start.x(), columns_ - 1), z = cell_of(start.z(), rows_ - 1);
  const auto crossing = [&](float from, float along, std::int64_t cell, float& next, float& step,
                            int& advance) {
    if (along == 0.0f) {
      next = kLargeFloat, step = kLargeFloat, advance = 0;
      return;
    }
    advance = along > 0.0f ? 1 : -1;
    const float line = static_cast<float>(cell + (along > 0.0f ? 1 : 0)) * cell_size_;
    next = (line - from) / along;
    step = cell_size_ / std::abs(along);
  };
  float next_x, step_x, next_z, step_z;
  int advance_x, advance_z;
  crossing(origin.x(), direction.x(), x, next_x, step_x, advance_x);
  crossing(origin.z(), direction.z(), z, next_z, step_z, advance_z);
  float best = max_fraction;
  std::uint32_t best_triangle = 0;
  bool found = false;
  while (x >= 0 && z >= 0 && x + 1 < columns_ && z + 1 < rows_) {
    found |= RayCell(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(z), origin, direction, best,
                     best_triangle);
    const float leave = std::min(next_x, next_z);
    // A hit in this cell is nearer than anything past it; so is one found in the cell before (rounding can
    // put a hit on the line between two cells a hair into either).
    if ((found && best <= leave) || leave > best) break;
    if (next_x < next_z)
      x += advance_x, next_x += step_x;
    else
      z += advance_z, next_z += step_z;
  }
  if (!found) return false;
  const Vec3 normal = Normal(best_triangle);
  hit.fraction = best;
  hit.sub_shape = best_triangle;
  hit.normal = normal.dot(direction) > 0.0f ? Vec3(-normal) : normal;
  return true;
}

void HeightFieldShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  AppendTrianglesInBox(*this, local_box, out);
}

}  // namespace strata
