#include "navmesh/Validation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace strata::navmesh {

namespace {

struct Point2 {
  float x, z;
};

float Cross(Point2 o, Point2 a, Point2 b) {
  return (a.x - o.x) * (b.z - o.z) - (a.z - o.z) * (b.x - o.x);
}

float SquaredDistanceToSegment(Point2 p, Point2 a, Point2 b) {
  const float dx = b.x - a.x, dz = b.z - a.z;
  const float length_squared = dx * dx + dz * dz;
  float t = length_squared > 0.0f ? ((p.x - a.x) * dx + (p.z - a.z) * dz) / length_squared : 0.0f;
  t = std::clamp(t, 0.0f, 1.0f);
  const float ex = a.x + t * dx - p.x, ez = a.z + t * dz - p.z;
  return ex * ex + ez * ez;
}

bool SegmentsIntersect(Point2 a, Point2 b, Point2 c, Point2 d) {
  const float d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

bool InsideConvex(const std::vector<Point2>& polygon, Point2 p) {
  bool positive = false, negative = false;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const float side = Cross(polygon[i], polygon[(i + 1) % polygon.size()], p);
    positive |= side > 0.0f;
    negative |= side < 0.0f;
  }
  return !(positive && negative);
}

/// x-z distance between two convex polygons (0 when they overlap).
float PolygonDistance(const std::vector<Point2>& a, const std::vector<Point2>& b) {
  if (InsideConvex(a, b[0]) || InsideConvex(b, a[0])) return 0.0f;
  float best = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Point2 a0 = a[i], a1 = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Point2 b0 = b[j], b1 = b[(j + 1) % b.size()];
      if (SegmentsIntersect(a0, a1, b0, b1)) return 0.0f;
      best = std::min({best, SquaredDistanceToSegment(a0, b0, b1), SquaredDistanceToSegment(b0, a0, a1)});
    }
  }
  return std::sqrt(best);
}

std::vector<Point2> Rectangle(const AABB& box) {
  return {{box.min.x(), box.min.z()},
          {box.max.x(), box.min.z()},
          {box.max.x(), box.max.z()},
          {box.min.x(), box.max.z()}};
}

// In tile coordinate order: island numbers and triangle order must not depend on which worker published a
// tile first.
template <class Function>
void ForEachGroundPoly(const dtNavMesh& mesh, Function&& function) {
  for (const dtMeshTile* tile : TilesInOrder(mesh))
    for (int p = 0; p < tile->header->polyCount; ++p)
      if (tile->polys[p].getType() == DT_POLYTYPE_GROUND) function(*tile, p);
}

}  // namespace

float ClearanceToBox(const NavMesh& navmesh, const AABB& world_box, float vertical_margin) {
  // Polygons are relative to the navmesh origin; so is the box here.
  const AABB box(navmesh.ToLocal(world_box.min), navmesh.ToLocal(world_box.max));
  const std::vector<Point2> rectangle = Rectangle(box);
  return navmesh.Read([&](const dtNavMesh& mesh) {
    float clearance = std::numeric_limits<float>::max();
    ForEachGroundPoly(mesh, [&](const dtMeshTile& tile, int p) {
      const dtPoly& poly = tile.polys[p];
      std::vector<Point2> polygon;
      float low = std::numeric_limits<float>::max(), high = -low;
      for (int i = 0; i < poly.vertCount; ++i) {
        const float* v = &tile.verts[poly.verts[i] * 3];
        polygon.push_back({v[0], v[2]});
        low = std::min(low, v[1]);
        high = std::max(high, v[1]);
      }
      if (high < box.min.y() - vertical_margin || low > box.max.y() - vertical_margin) return;
      clearance = std::min(clearance, PolygonDistance(polygon, rectangle));
    });
    return clearance;
  });
}

bool PathCrossesBox(const PathResult& path, const AABB& box) {
  const std::vector<Point2> rectangle = Rectangle(box);
  for (std::size_t i = 1; i < path.points.size(); ++i) {
    const Point2 a{path.points[i - 1].x(), path.points[i - 1].z()}, b{path.points[i].x(), path.points[i].z()};
    if (PolygonDistance({a, b}, rectangle) == 0.0f) return true;
  }
  return false;
}

std::vector<TileCoord> TilesOnPath(const NavMesh& navmesh, const PathResult& path) {
  return navmesh.Read([&](const dtNavMesh& mesh) {
    std::vector<TileCoord> tiles;
    for (const dtPolyRef ref : path.polys) {
      const dtMeshTile* tile = nullptr;
      const dtPoly* poly = nullptr;
      if (dtStatusFailed(mesh.getTileAndPolyByRef(ref, &tile, &poly))) continue;
      const TileCoord coord{tile->header->x + navmesh.origin_tile().x,
                            tile->header->y + navmesh.origin_tile().z};
      if (std::find(tiles.begin(), tiles.end(), coord) == tiles.end()) tiles.push_back(coord);
    }
    return tiles;
  });
}

namespace {
// Each ground polygon's island (polygons joined by Detour links, across tiles too), numbered from 0 in the
// order ForEachGroundPoly meets them.
std::unordered_map<dtPolyRef, int> LabelIslands(const dtNavMesh& mesh, int& islands) {
  std::unordered_map<dtPolyRef, dtPolyRef> parent;
  const auto find = [&](dtPolyRef ref) {
    while (parent[ref] != ref) ref = parent[ref] = parent[parent[ref]];
    return ref;
  };
  const auto ref_of = [&](const dtMeshTile& tile, int p) {
    return mesh.getPolyRefBase(&tile) | static_cast<dtPolyRef>(p);
  };
  ForEachGroundPoly(mesh, [&](const dtMeshTile& tile, int p) { parent[ref_of(tile, p)] = ref_of(tile, p); });
  ForEachGroundPoly(mesh, [&](const dtMeshTile& tile, int p) {
    const dtPolyRef self = ref_of(tile, p);
    for (unsigned int link = tile.polys[p].firstLink; link != DT_NULL_LINK; link = tile.links[link].next) {
      const dtPolyRef other = tile.links[link].ref;
      if (other == 0 || !parent.contains(other)) continue;
      parent[find(self)] = find(other);
    }
  });
  std::unordered_map<dtPolyRef, int> root_label, label;
  islands = 0;
  ForEachGroundPoly(mesh, [&](const dtMeshTile& tile, int p) {
    const auto [root, fresh] = root_label.try_emplace(find(ref_of(tile, p)), islands);
    if (fresh) ++islands;
    label[ref_of(tile, p)] = root->second;
  });
  return label;
}
}  // namespace

int CountIslands(const NavMesh& navmesh) {
  return navmesh.Read([](const dtNavMesh& mesh) {
    int islands = 0;
    LabelIslands(mesh, islands);
    return islands;
  });
}

NavMeshTriangles TrianglesByIsland(const NavMesh& navmesh) {
  NavMeshTriangles out;
  navmesh.Read([&](const dtNavMesh& mesh) {
    const std::unordered_map<dtPolyRef, int> islands = LabelIslands(mesh, out.islands);
    ForEachGroundPoly(mesh, [&](const dtMeshTile& tile, int p) {
      const int island = islands.at(mesh.getPolyRefBase(&tile) | static_cast<dtPolyRef>(p));
      const TileCoord coord{tile.header->x + navmesh.origin_tile().x,
                            tile.header->y + navmesh.origin_tile().z};
      for (int t = 0; t < tile.detailMeshes[p].triCount; ++t) {
        for (int k = 0; k < 3; ++k)
          out.vertices.push_back(navmesh.ToWorld(DetailTriangleCorner(tile, p, t, k)));
        out.island.push_back(island);
        out.tile.push_back(coord);
      }
    });
  });
  return out;
}

}  // namespace strata::navmesh
