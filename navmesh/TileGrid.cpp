#include "navmesh/TileGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::navmesh {

namespace {
// A tile index for `coordinate`, held inside int (a converted float beyond it would be undefined).
int TileIndex(float coordinate, float tile_size) {
  constexpr double kLimit = 1 << 30;
  const double index = std::floor(static_cast<double>(coordinate) / tile_size);
  if (std::isnan(index)) return 0;
  return static_cast<int>(std::clamp(index, -kLimit, kLimit));
}
}  // namespace

TileCoord TileGrid::TileAt(const Vec3& position) const {
  return {TileIndex(position.x(), tile_size_), TileIndex(position.z(), tile_size_)};
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
  ForEachTileInCircle(center, radius, [&](TileCoord tile) { tiles.push_back(tile); });
  return tiles;
}

std::uint64_t TileGrid::TileCount(const AABB& box) const {
  if (!box.IsValid()) return 0;
  // In double: a box millions of kilometres wide has more tiles than an int holds.
  auto span = [&](float low, float high) {
    return std::floor(static_cast<double>(high) / tile_size_) -
           std::floor(static_cast<double>(low) / tile_size_) + 1.0;
  };
  const double count = span(box.min.x(), box.max.x()) * span(box.min.z(), box.max.z());
  return count >= 1.8e19 ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>(count);
}

std::vector<TileCoord> TileGrid::TilesInBox(const AABB& box) const {
  std::vector<TileCoord> tiles;
  if (!box.IsValid() || TileCount(box) > kMaxListedTiles) return tiles;
  const TileCoord low = TileAt(box.min);
  const TileCoord high = TileAt(box.max);
  for (int z = low.z; z <= high.z; ++z)
    for (int x = low.x; x <= high.x; ++x) tiles.push_back({x, z});
  return tiles;
}

}  // namespace strata::navmesh
