#include "navmesh/DropLinks.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace strata::navmesh {

namespace {

/// What one column of the rasterized geometry offers an agent standing at `floor`: the top of what it would
/// stand on or bump into (the highest surface below its head), or nothing for an empty column.
std::optional<float> ColumnTop(const rcHeightfield& solid, int x, int z, float floor, float agent_height) {
  if (x < 0 || z < 0 || x >= solid.width || z >= solid.height) return std::nullopt;
  std::optional<float> top;
  for (const rcSpan* span = solid.spans[x + z * solid.width]; span != nullptr; span = span->next) {
    const float bottom = solid.bmin[1] + static_cast<float>(span->smin) * solid.ch;
    if (bottom >= floor + agent_height) break;  // overhead, above the agent
    top = solid.bmin[1] + static_cast<float>(span->smax) * solid.ch;
  }
  return top;
}

/// Whether `compact` holds walkable ground at (x, z) within `climb` of `height`. In the border around the
/// tile, whose erosion the edge of the heightfield distorts, any flat ground counts: the link's end then
/// joins the next tile's polygons only if that tile has ground there.
bool WalkableAt(const rcCompactHeightfield& compact, int x, int z, float height, float climb) {
  if (x < 0 || z < 0 || x >= compact.width || z >= compact.height) return false;
  const int border = compact.borderSize;
  if (x < border || z < border || x >= compact.width - border || z >= compact.height - border) return true;
  const rcCompactCell& cell = compact.cells[x + z * compact.width];
  for (unsigned i = cell.index; i < cell.index + static_cast<unsigned>(cell.count); ++i) {
    if (compact.areas[i] == RC_NULL_AREA) continue;
    const float floor = compact.bmin[1] + static_cast<float>(compact.spans[i].y) * compact.ch;
    if (std::abs(floor - height) <= climb) return true;
  }
  return false;
}

struct Probe {
  const NavMeshSettings& settings;
  const rcHeightfield& solid;
  const rcCompactHeightfield& compact;

  int CellX(float x) const { return static_cast<int>(std::floor((x - solid.bmin[0]) / solid.cs)); }
  int CellZ(float z) const { return static_cast<int>(std::floor((z - solid.bmin[2]) / solid.cs)); }

  // Walks from `start` (on the ledge, at its floor) along `out`: across the ledge, over its edge, down to
  // the ground and an agent's width onto it. The landing point, or nothing.
  std::optional<Vec3> Drop(const Vec3& start, const Vec3& out) const {
    const float step = 0.5f * solid.cs;
    const float climb = settings.agent_max_climb, height = settings.agent_height;
    const float reach = 2.0f * settings.agent_radius + 6.0f * solid.cs;
    std::optional<float> ground;
    float landed_at = 0.0f;
    for (float along = step; along <= reach + settings.agent_radius + 2.0f * solid.cs; along += step) {
      const Vec3 at = start + along * out;
      const std::optional<float> top = ColumnTop(solid, CellX(at.x()), CellZ(at.z()), start.y(), height);
      if (!top) return std::nullopt;                      // off the geometry: no ground to land on
      if (*top > start.y() + climb) return std::nullopt;  // a wall or a step up: not a ledge
      if (!ground) {
        if (*top >= start.y() - climb) {
          if (along > reach) return std::nullopt;  // no edge within reach: a wide walkable top
          continue;                                // still on the ledge
        }
        if (start.y() - *top > settings.agent_max_drop) return std::nullopt;
        ground = *top, landed_at = along;
        continue;
      }
      if (std::abs(*top - *ground) > climb) return std::nullopt;  // the landing is not flat ground
      // An agent's width past the foot of the ledge, where its eroded walkable area begins.
      if (along - landed_at < settings.agent_radius + solid.cs) continue;
      if (!WalkableAt(compact, CellX(at.x()), CellZ(at.z()), *ground, climb)) return std::nullopt;
      return Vec3(at.x(), *ground, at.z());
    }
    return std::nullopt;
  }
};

Vec3 MeshVertex(const rcPolyMesh& mesh, unsigned short index) {
  const unsigned short* v = &mesh.verts[index * 3];
  return {mesh.bmin[0] + static_cast<float>(v[0]) * mesh.cs,
          mesh.bmin[1] + static_cast<float>(v[1]) * mesh.ch,
          mesh.bmin[2] + static_cast<float>(v[2]) * mesh.cs};
}

}  // namespace

std::vector<DropLink> FindDropLinks(const NavMeshSettings& settings, const rcPolyMesh& mesh,
                                    const rcHeightfield& solid, const rcCompactHeightfield& compact) {
  std::vector<DropLink> links;
  if (settings.agent_max_drop <= 0.0f) return links;
  const Probe probe{settings, solid, compact};
  constexpr float kSpacing = 2.0f;  // one link per this much ledge
  for (int p = 0; p < mesh.npolys && links.size() < kMaxDropLinksPerTile; ++p) {
    if (mesh.areas[p] != RC_WALKABLE_AREA) continue;
    const unsigned short* poly = &mesh.polys[p * 2 * mesh.nvp];
    int count = 0;
    Vec3 centre = Vec3::Zero();
    while (count < mesh.nvp && poly[count] != RC_MESH_NULL_IDX) centre += MeshVertex(mesh, poly[count++]);
    centre /= static_cast<float>(count);
    for (int e = 0; e < count && links.size() < kMaxDropLinksPerTile; ++e) {
      // Only outer edges: no polygon beside it, in this tile or (a portal) the next.
      if (poly[mesh.nvp + e] != RC_MESH_NULL_IDX) continue;
      const Vec3 a = MeshVertex(mesh, poly[e]), b = MeshVertex(mesh, poly[(e + 1) % count]);
      Vec3 out(b.z() - a.z(), 0.0f, a.x() - b.x());
      if (out.squaredNorm() < 1e-8f) continue;
      out.normalize();
      if (out.dot(0.5f * (a + b) - centre) < 0.0f) out = -out;
      const float length = (b - a).norm();
      const int samples = std::max(1, static_cast<int>(length / kSpacing));
      for (int s = 0; s < samples && links.size() < kMaxDropLinksPerTile; ++s) {
        const Vec3 top = a + ((static_cast<float>(s) + 0.5f) / static_cast<float>(samples)) * (b - a);
        if (const std::optional<Vec3> bottom = probe.Drop(top, out)) links.push_back({top, *bottom});
      }
    }
  }
  return links;
}

}  // namespace strata::navmesh
