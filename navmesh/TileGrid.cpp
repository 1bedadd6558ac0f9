#include "navmesh/TileGrid.h"

#include <cmath>

namespace strata::navmesh {

TileCoord TileGrid::TileAt(const Vec3& position) const {
  return {static_cast<int>(std::floor(position.x() / tile_size_)),
          static_cast<int>(std::floor(position.z() / tile_size_))};
}

AABB TileGrid::Bounds(TileCoord tile, float border, float min_y, float max_y) const {
  const float x = static_cast<float>(tile.x) * tile_size_;
  const float z = static_cast<float>(tile.z) * tile_size_;
  return {Vec3(x - border, min_y, z - border), Vec3(x + tile_size_ + border, max_y, z + tile_size_ + border)};
}

Vec3 TileGrid::Center(TileCoord tile) const {
  return {(static_cast<float>(tile.x) + 0.5f) * tile_size_, 0.0f,
          (static_cast<float>(tile.z) + 0.5f) * tile_size_};
}

float TileGrid::SquaredDistance(TileCoord tile, const Vec3& position) const {
  const AABB bounds = Bounds(tile);
  const float dx = std::max({bounds.min.x() - position.x(), 0.0f, position.x() - bounds.max.x()});
  const float dz = std::max({bounds.min.z() - position.z(), 0.0f, position.z() - bounds.max.z()});
  return dx * dx + dz * dz;
}

std::vector<TileCoord> TileGrid::TilesInCircle(const Vec3& center, float radius) const {
  std::vector<TileCoord> tiles;
  if (!IsFinite(center) || !std::isfinite(radius) || radius < 0.0f) return tiles;
  const TileCoord low = TileAt(center - Vec3(radius, 0.0f, radius));
  const TileCoord high = TileAt(center + Vec3(radius, 0.0f, radius));
  for (int z = low.z; z <= high.z; ++z)
    for (int x = low.x; x <= high.x; ++x)
      if (SquaredDistance({x, z}, center) <= radius * radius) tiles.push_back({x, z});
  return tiles;
}

std::vector<TileCoord> TileGrid::TilesInBox(const AABB& box) const {
  std::vector<TileCoord> tiles;
  if (!box.IsValid()) return tiles;
  const TileCoord low = TileAt(box.min);
  const TileCoord high = TileAt(box.max);
  for (int z = low.z; z <= high.z; ++z)
    for (int x = low.x; x <= high.x; ++x) tiles.push_back({x, z});
  return tiles;
}

}  // namespace strata::navmesh
