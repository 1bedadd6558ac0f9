// Validation: checks of a built navmesh that tests and tools share: clearance around obstacles, whether a
// path crosses a box, which tiles a path visits, connectivity (islands of linked polygons), and the surface
// as triangles by island.
// Each function takes the NavMesh's read lock for its duration; safe from any thread.
#pragma once

#include <vector>

#include "navmesh/NavMesh.h"
#include "navmesh/NavMeshQuery.h"
#include "physics/math/AABB.h"

namespace strata::navmesh {

/// Smallest x-z distance between `box` and any walkable polygon at a height where the box blocks an agent:
/// from `vertical_margin` below its bottom to `vertical_margin` below its top (so polygons on top of the box
/// do not count). 0 when one overlaps it; a large number when none is near.
float ClearanceToBox(const NavMesh& navmesh, const AABB& box, float vertical_margin);

/// True when a straight-path segment passes through `box` in x-z (heights ignored).
bool PathCrossesBox(const PathResult& path, const AABB& box);

/// The distinct tiles a path's polygon corridor passes through, in order of first visit.
std::vector<TileCoord> TilesOnPath(const NavMesh& navmesh, const PathResult& path);

/// Number of islands of polygons connected through Detour links (across tile borders too).
int CountIslands(const NavMesh& navmesh);

/// The walkable surface as triangles (Detour's detail triangles of every ground polygon), for export and
/// viewers: world vertices, three per triangle, and per triangle the island of its polygon (numbered
/// 0 .. islands - 1 in the order islands are first met) and its tile.
struct NavMeshTriangles {
  std::vector<Vec3> vertices;
  std::vector<int> island;
  std::vector<TileCoord> tile;
  int islands = 0;
};
NavMeshTriangles TrianglesByIsland(const NavMesh& navmesh);

}  // namespace strata::navmesh
