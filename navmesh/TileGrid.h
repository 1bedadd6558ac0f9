// TileGrid: the navmesh's square tiles on the x-z plane, keyed by integer (x, z), with their bounds and
// the tiles a circle touches. Value type; safe from any thread.
#pragma once

#include <compare>
#include <cstdint>
#include <vector>

#include "physics/math/AABB.h"

namespace strata::navmesh {

/// Integer tile coordinates: tile (x, z) covers [x, x + 1) * size on x and [z, z + 1) * size on z.
struct TileCoord {
  int x = 0;
  int z = 0;
  auto operator<=>(const TileCoord&) const = default;
};

/// Maps world positions to tiles of side `tile_size` metres, with the grid origin at the world origin.
class TileGrid {
 public:
  explicit TileGrid(float tile_size) : tile_size_(tile_size) {}

  float tile_size() const { return tile_size_; }
  TileCoord TileAt(const Vec3& position) const;
  /// The tile's column from `min_y` to `max_y`, grown by `border` metres on x and z.
  AABB Bounds(TileCoord tile, float border = 0.0f, float min_y = -1.0e4f, float max_y = 1.0e4f) const;
  Vec3 Center(TileCoord tile) const;
  /// Squared x-z distance from `position` to the tile (0 inside).
  float SquaredDistance(TileCoord tile, const Vec3& position) const;
  /// Tiles whose x-z square the circle (x-z plane) touches, in row order.
  std::vector<TileCoord> TilesInCircle(const Vec3& center, float radius) const;
  /// Calls `visit(tile)` for each tile TilesInCircle lists, in its order, without building the list.
  template <class Visit>
  void ForEachTileInCircle(const Vec3& center, float radius, Visit&& visit) const {
    if (!IsFinite(center) || !std::isfinite(radius) || radius < 0.0f) return;
    const TileCoord low = TileAt(center - Vec3(radius, 0.0f, radius));
    const TileCoord high = TileAt(center + Vec3(radius, 0.0f, radius));
    for (int z = low.z; z <= high.z; ++z)
      for (int x = low.x; x <= high.x; ++x)
        if (SquaredDistance({x, z}, center) <= radius * radius) visit(TileCoord{x, z});
  }
  /// How many tiles TilesInBox(box) lists, computed without listing them (0 for an invalid box), so a caller
  /// can refuse a box too large to list before anything is allocated.
  std::uint64_t TileCount(const AABB& box) const;
  /// Tiles whose x-z square overlaps `box`, in row order. Call with a box whose TileCount was checked:
  /// a box of more than kMaxListedTiles tiles lists none.
  std::vector<TileCoord> TilesInBox(const AABB& box) const;
  /// The most tiles TilesInBox lists (a navmesh holds at most 2^16, Detour's limit with our reference bits).
  static constexpr std::uint64_t kMaxListedTiles = std::uint64_t{1} << 20;

 private:
  float tile_size_;
};

}  // namespace strata::navmesh
