// TileBuilder: turns the triangles gathered for one tile into Detour tile data with Recast (rasterize,
// filter, compact, erode, regions, contours, polygon mesh, detail mesh, dtCreateNavMeshData).
// Pure function of its inputs; any number of threads may build different tiles at once.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "navmesh/NavMeshSettings.h"
#include "navmesh/TileData.h"
#include "navmesh/TileGather.h"
#include "navmesh/TileGrid.h"

namespace strata::navmesh {

/// A built tile and what it took.
struct BuiltTile {
  TileCoord coord;
  TileData data;  ///< empty when nothing in the tile is walkable
  int polygons = 0;
  double recast_ms = 0.0;
  /// The profile (index among those built together) whose polygons this one took, because their walkable
  /// cells came out the same; -1 when it built its own. The tile is the same bytes either way.
  int polygons_from = -1;
};

/// Ok when `box` (world) lies within settings.max_coordinate() of the navmesh origin on every axis;
/// otherwise an error that names `what`, how far it reaches and the limit.
Status CheckReach(const AABB& box, const NavMeshSettings& settings, const std::string& what);

/// The box a tile's geometry is gathered from: the tile grown by its border, from `min_y` to `max_y`.
AABB TileGatherBox(const NavMeshSettings& settings, TileCoord tile);

/// Builds tile `tile` from `geometry` (world-space triangles around it), in coordinates relative to the
/// navmesh origin. Fails only when Recast or Detour
/// cannot allocate or the tile would exceed Detour's limits; a tile with nothing walkable is not an error.
Result<BuiltTile> BuildTile(const NavMeshSettings& settings, TileCoord tile, const TileGeometry& geometry);

/// Builds tile `tile` from one gather for several agent profiles, one result each, in order. Profiles that
/// agree on the cell sizes, tile, border, origin and merge climb share one rasterization (each then filters,
/// erodes and builds its own polygons, or takes those of an earlier profile whose walkable cells came out the
/// same); every profile's tile is the bytes BuildTile gives it alone.
std::vector<Result<BuiltTile>> BuildTileForProfiles(std::span<const NavMeshSettings> profiles, TileCoord tile,
                                                    const TileGeometry& geometry);

}  // namespace strata::navmesh
