#include "navmesh/TileBuilder.h"

#include <DetourNavMeshBuilder.h>
#include <Recast.h>

#include "navmesh/DropLinks.h"
#include "navmesh/NavMesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <tuple>

namespace strata::navmesh {

namespace {

/// The area of drop links (ground is RC_WALKABLE_AREA), so a query filter may cost them apart.
constexpr unsigned char kDropArea = 1;

template <class T, void (*Free)(T*)>
struct RecastDeleter {
  void operator()(T* object) const { Free(object); }
};
using Heightfield = std::unique_ptr<rcHeightfield, RecastDeleter<rcHeightfield, rcFreeHeightField>>;
using CompactHeightfield =
    std::unique_ptr<rcCompactHeightfield, RecastDeleter<rcCompactHeightfield, rcFreeCompactHeightfield>>;
using ContourSet = std::unique_ptr<rcContourSet, RecastDeleter<rcContourSet, rcFreeContourSet>>;
using PolyMesh = std::unique_ptr<rcPolyMesh, RecastDeleter<rcPolyMesh, rcFreePolyMesh>>;
using PolyMeshDetail =
    std::unique_ptr<rcPolyMeshDetail, RecastDeleter<rcPolyMeshDetail, rcFreePolyMeshDetail>>;

Error BuildError(TileCoord tile, const char* stage) {
  return MakeError(ErrorCode::kCapacityExceeded, "navmesh tile (" + std::to_string(tile.x) + ", " +
                                                     std::to_string(tile.z) + "): " + stage + " failed");
}

/// Recast's configuration in cells, derived from the settings in metres.
rcConfig MakeConfig(const NavMeshSettings& settings, const AABB& box) {
  rcConfig config{};
  config.cs = settings.cell_size;
  config.ch = settings.cell_height;
  config.walkableSlopeAngle = settings.agent_max_slope;
  config.walkableHeight = static_cast<int>(std::ceil(settings.agent_height / settings.cell_height));
  config.walkableClimb = static_cast<int>(std::floor(settings.agent_max_climb / settings.cell_height));
  config.walkableRadius = static_cast<int>(std::ceil(settings.agent_radius / settings.cell_size));
  config.maxEdgeLen = static_cast<int>(settings.edge_max_length / settings.cell_size);
  config.maxSimplificationError = settings.edge_max_error;
  config.minRegionArea = settings.region_min_size * settings.region_min_size;
  config.mergeRegionArea = settings.region_merge_size * settings.region_merge_size;
  config.maxVertsPerPoly = settings.verts_per_poly;
  config.tileSize = settings.tile_cells;
  config.borderSize = settings.border_cells();
  config.width = config.tileSize + 2 * config.borderSize;
  config.height = config.width;
  config.detailSampleDist =
      settings.detail_sample_distance < 0.9f ? 0.0f : settings.cell_size * settings.detail_sample_distance;
  config.detailSampleMaxError = settings.cell_height * settings.detail_sample_max_error;
  rcVcopy(config.bmin, box.min.data());
  rcVcopy(config.bmax, box.max.data());
  return config;
}

/// Recast's output for one tile, and the walkable cells it came from (where drop links land).
struct RecastMeshes {
  PolyMesh poly;
  PolyMeshDetail detail;
  CompactHeightfield compact;
};

/// A tile's triangles rasterized once for every profile of a group. Each span's area is a walkability code:
/// the number of the group's distinct slope limits its steepest-allowed triangle meets (0: none), so that
/// Recast's merge (the larger area wins) keeps, for every limit at once, what a build for that limit alone
/// would keep.
struct SharedRaster {
  /// A span whose floor lies inside a convex body: column, and the span's place in it counted from below.
  struct BuriedSpan {
    int column;
    int height_index;
  };
  Heightfield solid;
  std::vector<float> slope_limits;   ///< the group's distinct agent_max_slope values, ascending
  std::vector<unsigned char> codes;  ///< every span's code, column by column, bottom up
  std::vector<BuriedSpan> buried;    ///< ascending, so a column's entries are together
};

template <class Visit>
void ForEachSpan(rcHeightfield& field, Visit visit) {
  for (int i = 0; i < field.width * field.height; ++i)
    for (rcSpan* span = field.spans[i]; span != nullptr; span = span->next) visit(*span);
}

/// Recast rasterizes surfaces, so the floor under a closed crate looks like a room with a ceiling. Finds the
/// spans whose floor lies inside a convex body (tested half a cell above it), once for every profile: each
/// takes them out before erosion, so its radius is kept from the body's sides as from any wall.
std::vector<SharedRaster::BuriedSpan> FindBuriedSpans(const std::vector<SolidVolume>& solids,
                                                      const rcHeightfield& field) {
  std::vector<SharedRaster::BuriedSpan> buried;
  const float cell = field.cs;
  for (const SolidVolume& solid : solids) {
    const int x0 = std::max(0, static_cast<int>(std::floor((solid.bounds.min.x() - field.bmin[0]) / cell)));
    const int z0 = std::max(0, static_cast<int>(std::floor((solid.bounds.min.z() - field.bmin[2]) / cell)));
    const int x1 = std::min(field.width - 1,
                            static_cast<int>(std::floor((solid.bounds.max.x() - field.bmin[0]) / cell)));
    const int z1 = std::min(field.height - 1,
                            static_cast<int>(std::floor((solid.bounds.max.z() - field.bmin[2]) / cell)));
    for (int z = z0; z <= z1; ++z) {
      for (int x = x0; x <= x1; ++x) {
        int height_index = 0;
        for (const rcSpan* span = field.spans[x + z * field.width]; span != nullptr;
             span = span->next, ++height_index) {
          const Vec3 point(field.bmin[0] + (static_cast<float>(x) + 0.5f) * cell,
                           field.bmin[1] + (static_cast<float>(span->smax) + 0.5f) * field.ch,
                           field.bmin[2] + (static_cast<float>(z) + 0.5f) * cell);
          if (solid.Contains(point, 0.0f)) buried.push_back({x + z * field.width, height_index});
        }
      }
    }
  }
  std::sort(buried.begin(), buried.end(), [](const auto& a, const auto& b) {
    return std::tie(a.column, a.height_index) < std::tie(b.column, b.height_index);
  });
  buried.erase(std::unique(buried.begin(), buried.end(),
                           [](const auto& a, const auto& b) {
                             return a.column == b.column && a.height_index == b.height_index;
                           }),
               buried.end());
  return buried;
}

/// Takes the buried spans out of one profile's compact heightfield. Its spans are the raw spans the profile's
/// filters left walkable, in the same order, so a buried span's place among them is the count of walkable
/// spans below it in its column.
void RemoveBuriedSpans(const std::vector<SharedRaster::BuriedSpan>& buried, const rcHeightfield& field,
                       rcCompactHeightfield& compact) {
  auto next = buried.begin();
  while (next != buried.end()) {
    const int column = next->column;
    unsigned compact_index = compact.cells[column].index;
    int height_index = 0;
    for (const rcSpan* span = field.spans[column]; span != nullptr; span = span->next, ++height_index) {
      if (next == buried.end() || next->column != column) break;
      if (span->area == RC_NULL_AREA) {
        if (next->height_index == height_index) ++next;  // buried, and not walkable for this profile anyway
        continue;
      }
      if (next->height_index == height_index) {
        compact.areas[compact_index] = RC_NULL_AREA;
        ++next;
      }
      ++compact_index;
    }
    while (next != buried.end() && next->column == column) ++next;
  }
}

Result<SharedRaster> Rasterize(const rcConfig& config, TileCoord tile, const TileGeometry& geometry,
                               std::vector<float> slope_limits) {
  rcContext context(false);
  const int vertex_count = static_cast<int>(geometry.vertices.size() / 3);
  const int triangle_count = static_cast<int>(geometry.triangle_count());
  SharedRaster raster{Heightfield(rcAllocHeightfield()), std::move(slope_limits), {}, {}};
  if (!raster.solid || !rcCreateHeightfield(&context, *raster.solid, config.width, config.height, config.bmin,
                                            config.bmax, config.cs, config.ch))
    return BuildError(tile, "heightfield");
  std::vector<unsigned char> codes(static_cast<std::size_t>(triangle_count), 0);
  std::vector<unsigned char> walkable(codes.size());
  for (const float limit : raster.slope_limits) {
    std::fill(walkable.begin(), walkable.end(), RC_NULL_AREA);
    rcMarkWalkableTriangles(&context, limit, geometry.vertices.data(), vertex_count,
                            geometry.triangles.data(), triangle_count, walkable.data());
    for (std::size_t i = 0; i < codes.size(); ++i) codes[i] += walkable[i] != RC_NULL_AREA;
  }
  if (!rcRasterizeTriangles(&context, geometry.vertices.data(), vertex_count, geometry.triangles.data(),
                            codes.data(), triangle_count, *raster.solid, config.walkableClimb))
    return BuildError(tile, "rasterization");
  ForEachSpan(*raster.solid,
              [&](const rcSpan& span) { raster.codes.push_back(static_cast<unsigned char>(span.area)); });
  raster.buried = FindBuriedSpans(geometry.solids, *raster.solid);
  return raster;
}

/// Sets every span's area for an agent whose slope limit is `limit`: walkable where the code says a triangle
/// that flat made the span's top.
void SetAreasForSlope(SharedRaster& raster, float limit) {
  const auto found = std::lower_bound(raster.slope_limits.begin(), raster.slope_limits.end(), limit);
  const auto needed = static_cast<unsigned char>(raster.slope_limits.end() - found);
  std::size_t next = 0;
  ForEachSpan(*raster.solid, [&](rcSpan& span) {
    span.area = raster.codes[next++] >= needed ? RC_WALKABLE_AREA : RC_NULL_AREA;
  });
}

/// One profile's walkable cells before erosion: its slope limit, ledge and headroom filters and the buried
/// spans applied to the group's rasterization.
Result<CompactHeightfield> WalkableCells(const rcConfig& config, float slope_limit, TileCoord tile,
                                         SharedRaster& raster) {
  SetAreasForSlope(raster, slope_limit);
  rcHeightfield& solid = *raster.solid;
  rcContext context(false);
  rcFilterLowHangingWalkableObstacles(&context, config.walkableClimb, solid);
  rcFilterLedgeSpans(&context, config.walkableHeight, config.walkableClimb, solid);
  rcFilterWalkableLowHeightSpans(&context, config.walkableHeight, solid);
  CompactHeightfield compact(rcAllocCompactHeightfield());
  if (!compact ||
      !rcBuildCompactHeightfield(&context, config.walkableHeight, config.walkableClimb, solid, *compact))
    return BuildError(tile, "compact heightfield");
  RemoveBuriedSpans(raster.buried, solid, *compact);
  return compact;
}

/// Whether Recast makes the same polygons of two profiles' walkable cells: the cells, their spans, their
/// links to neighbours and areas are the same, and so is every setting from erosion on. A walkable cell
/// field remembers its agent's height and climb, but erosion, regions, contours and the meshes read neither;
/// the height reaches the tile only as the top of its bounds, which CreateDetourData takes per profile.
bool SamePolygonsFrom(const rcConfig& a, const rcCompactHeightfield& cells_a, const rcConfig& b,
                      const rcCompactHeightfield& cells_b) {
  const auto downstream = [](const rcConfig& c) {
    return std::make_tuple(c.walkableRadius, c.borderSize, c.minRegionArea, c.mergeRegionArea,
                           c.maxSimplificationError, c.maxEdgeLen, c.maxVertsPerPoly, c.detailSampleDist,
                           c.detailSampleMaxError);
  };
  if (downstream(a) != downstream(b)) return false;
  if (cells_a.width != cells_b.width || cells_a.height != cells_b.height ||
      cells_a.spanCount != cells_b.spanCount)
    return false;
  const auto column_count =
      static_cast<std::size_t>(cells_a.width) * static_cast<std::size_t>(cells_a.height);
  const auto span_count = static_cast<std::size_t>(cells_a.spanCount);
  return std::memcmp(cells_a.cells, cells_b.cells, column_count * sizeof(rcCompactCell)) == 0 &&
         std::memcmp(cells_a.spans, cells_b.spans, span_count * sizeof(rcCompactSpan)) == 0 &&
         std::memcmp(cells_a.areas, cells_b.areas, span_count) == 0;
}

/// Erosion to detail mesh, from one profile's walkable cells (eroded in place and kept for drop links).
Result<RecastMeshes> BuildMeshes(const rcConfig& config, TileCoord tile, CompactHeightfield compact) {
  rcContext context(false);
  if (!rcErodeWalkableArea(&context, config.walkableRadius, *compact)) return BuildError(tile, "erosion");
  if (!rcBuildDistanceField(&context, *compact)) return BuildError(tile, "distance field");
  if (!rcBuildRegions(&context, *compact, config.borderSize, config.minRegionArea, config.mergeRegionArea))
    return BuildError(tile, "regions");

  ContourSet contours(rcAllocContourSet());
  if (!contours ||
      !rcBuildContours(&context, *compact, config.maxSimplificationError, config.maxEdgeLen, *contours))
    return BuildError(tile, "contours");
  RecastMeshes meshes{PolyMesh(rcAllocPolyMesh()), PolyMeshDetail(rcAllocPolyMeshDetail()), nullptr};
  if (!meshes.poly || !rcBuildPolyMesh(&context, *contours, config.maxVertsPerPoly, *meshes.poly))
    return BuildError(tile, "polygon mesh");
  if (!meshes.detail || !rcBuildPolyMeshDetail(&context, *meshes.poly, *compact, config.detailSampleDist,
                                               config.detailSampleMaxError, *meshes.detail))
    return BuildError(tile, "detail mesh");
  meshes.compact = std::move(compact);
  return meshes;
}

/// `top` is the top of this profile's walkable cell field (its bmax.y), which the tile's bounds reach to.
Result<TileData> CreateDetourData(const NavMeshSettings& settings, const rcConfig& config, TileCoord tile,
                                  RecastMeshes& meshes, float top, const std::vector<DropLink>& drops) {
  rcPolyMesh& poly = *meshes.poly;
  if (poly.nverts >= 0xffff) return BuildError(tile, "Detour data (too many vertices)");
  for (int i = 0; i < poly.npolys; ++i)
    poly.flags[i] = poly.areas[i] == RC_WALKABLE_AREA ? kGroundPolyFlag : 0;

  dtNavMeshCreateParams params{};
  params.verts = poly.verts;
  params.vertCount = poly.nverts;
  params.polys = poly.polys;
  params.polyAreas = poly.areas;
  params.polyFlags = poly.flags;
  params.polyCount = poly.npolys;
  params.nvp = poly.nvp;
  params.detailMeshes = meshes.detail->meshes;
  params.detailVerts = meshes.detail->verts;
  params.detailVertsCount = meshes.detail->nverts;
  params.detailTris = meshes.detail->tris;
  params.detailTriCount = meshes.detail->ntris;
  params.walkableHeight = settings.agent_height;
  params.walkableRadius = settings.agent_radius;
  params.walkableClimb = settings.agent_max_climb;
  params.tileX = tile.x;
  params.tileY = tile.z;
  params.tileLayer = 0;
  rcVcopy(params.bmin, poly.bmin);
  rcVcopy(params.bmax, poly.bmax);
  params.bmax[1] = top;
  params.cs = config.cs;
  params.ch = config.ch;
  params.buildBvTree = true;
  // Drop links: one-way off-mesh connections, each snapping to the polygons within its radius at both ends.
  std::vector<float> link_points, link_radii;
  std::vector<unsigned short> link_flags;
  std::vector<unsigned char> link_areas, link_directions;
  std::vector<unsigned int> link_ids;
  for (std::size_t i = 0; i < drops.size(); ++i) {
    for (const Vec3* point : {&drops[i].top, &drops[i].bottom})
      link_points.insert(link_points.end(), point->data(), point->data() + 3);
    link_radii.push_back(std::max(settings.agent_radius, 3.0f * settings.cell_size));
    link_flags.push_back(kDropLinkFlag);
    link_areas.push_back(kDropArea);
    link_directions.push_back(0);
    link_ids.push_back(static_cast<unsigned int>(i));
  }
  params.offMeshConVerts = link_points.data();
  params.offMeshConRad = link_radii.data();
  params.offMeshConFlags = link_flags.data();
  params.offMeshConAreas = link_areas.data();
  params.offMeshConDir = link_directions.data();
  params.offMeshConUserID = link_ids.data();
  params.offMeshConCount = static_cast<int>(drops.size());
  unsigned char* bytes = nullptr;
  int size = 0;
  if (!dtCreateNavMeshData(&params, &bytes, &size)) return BuildError(tile, "Detour data");
  return TileData(bytes, size);
}

Vec3 ToNavMeshSpace(const Vec3& world, const NavMeshSettings& settings) {
  return (world.cast<double>() - settings.origin()).cast<float>();
}

/// `geometry` relative to the navmesh origin (in double, so the far level loses nothing more than its
/// own float positions already did).
TileGeometry MoveToNavMeshSpace(const TileGeometry& geometry, const NavMeshSettings& settings) {
  const Vec3d origin = settings.origin();
  TileGeometry local;
  local.triangles = geometry.triangles;
  local.bodies = geometry.bodies;
  local.vertices.resize(geometry.vertices.size());
  for (std::size_t i = 0; i < geometry.vertices.size(); ++i)
    local.vertices[i] = static_cast<float>(geometry.vertices[i] - origin[static_cast<Eigen::Index>(i % 3)]);
  const auto move_box = [&](const AABB& box) {
    return box.IsValid() ? AABB(ToNavMeshSpace(box.min, settings), ToNavMeshSpace(box.max, settings)) : box;
  };
  local.bounds = move_box(geometry.bounds);
  for (const SolidVolume& solid : geometry.solids) {
    SolidVolume moved{move_box(solid.bounds), solid.planes};
    for (SolidVolume::Plane& plane : moved.planes)
      plane.offset = static_cast<float>(plane.offset - plane.normal.cast<double>().dot(origin));
    local.solids.push_back(std::move(moved));
  }
  return local;
}

}  // namespace

Status CheckReach(const AABB& box, const NavMeshSettings& settings, const std::string& what) {
  const Vec3d origin = settings.origin();
  const double reach = std::max((box.min.cast<double>() - origin).cwiseAbs().maxCoeff(),
                                (box.max.cast<double>() - origin).cwiseAbs().maxCoeff());
  const double limit = settings.max_coordinate();
  if (reach <= limit) return Status::Ok();  // (a NaN box fails here too)
  char message[320];
  std::snprintf(message, sizeof(message),
                "navmesh: %s reaches %.4g m from the navmesh origin (%.4g, %.4g); navmesh geometry must lie "
                "within %.4g m of it (2^22 cells of %.3g m: farther out a float cannot resolve a cell for "
                "Recast); move the navmesh origin (origin_tile) nearer",
                what.c_str(), reach, origin.x(), origin.z(), limit, static_cast<double>(settings.cell_size));
  return MakeError(ErrorCode::kInvalidArgument, message);
}

AABB TileGatherBox(const NavMeshSettings& settings, TileCoord tile) {
  const float border = static_cast<float>(settings.border_cells()) * settings.cell_size;
  return TileGrid(settings.tile_size()).Bounds(tile, border);
}

namespace {

/// What a rasterization depends on: profiles equal in all of it share one.
auto RasterKey(const NavMeshSettings& settings) {
  return std::make_tuple(settings.cell_size, settings.cell_height, settings.tile_cells,
                         settings.border_cells(), settings.origin_tile.x, settings.origin_tile.z,
                         static_cast<int>(std::floor(settings.merge_climb() / settings.cell_height)));
}

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// One profile's part of a group's build.
struct ProfileBuild {
  rcConfig config{};
  CompactHeightfield cells;  ///< its walkable cells, until its meshes are built from them
  float top = 0.0f;          ///< the cells' bmax.y
  std::size_t source = 0;    ///< the build whose meshes it takes (itself when it builds its own)
  double ms = 0.0;           ///< its own Recast time
  std::optional<Result<RecastMeshes>> meshes;
};

/// Each member's walkable cells. Where two members' cells and later settings agree (on open ground a person
/// and a critter often do), the later one takes the earlier one's polygons instead of building them again.
std::vector<ProfileBuild> FindWalkableCells(std::span<const NavMeshSettings> profiles,
                                            const std::vector<std::size_t>& members, const AABB& box,
                                            TileCoord tile, SharedRaster& raster) {
  std::vector<ProfileBuild> group(members.size());
  for (std::size_t i = 0; i < members.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    ProfileBuild& build = group[i];
    const NavMeshSettings& settings = profiles[members[i]];
    build.source = i;
    build.config = MakeConfig(settings, box);
    Result<CompactHeightfield> cells = WalkableCells(build.config, settings.agent_max_slope, tile, raster);
    if (!cells) {
      build.meshes = cells.error();
      continue;
    }
    build.top = (*cells)->bmax[1];
    build.cells = std::move(*cells);
    for (std::size_t j = 0; j < i; ++j) {
      if (group[j].cells && SamePolygonsFrom(group[j].config, *group[j].cells, build.config, *build.cells)) {
        build.source = j;
        build.cells.reset();
        break;
      }
    }
    build.ms = MillisecondsSince(start);
  }
  return group;
}

/// Erosion to detail mesh for every build that takes no other's polygons.
void BuildOwnMeshes(std::vector<ProfileBuild>& group, TileCoord tile) {
  for (ProfileBuild& build : group) {
    if (!build.cells) continue;
    const auto start = std::chrono::steady_clock::now();
    build.meshes = BuildMeshes(build.config, tile, std::move(build.cells));
    build.ms += MillisecondsSince(start);
  }
}

/// Builds the profiles `members` (indices into `profiles`, one raster key) from one rasterization.
void BuildGroup(std::span<const NavMeshSettings> profiles, const std::vector<std::size_t>& members,
                TileCoord tile, const TileGeometry& geometry, std::vector<Result<BuiltTile>>& out) {
  const auto start = std::chrono::steady_clock::now();
  const NavMeshSettings& first = profiles[members.front()];
  const auto fail_all = [&](const Error& error) {
    for (const std::size_t member : members) out[member] = error;
  };
  for (const std::size_t member : members) out[member] = BuiltTile{tile, {}, 0, 0.0, -1};
  if (geometry.triangle_count() == 0) return;
  const std::string name = "tile (" + std::to_string(tile.x) + ", " + std::to_string(tile.z) + ")";
  if (Status reach = CheckReach(TileGatherBox(first, tile), first, name); !reach)
    return fail_all(reach.error());
  if (Status reach = CheckReach(geometry.bounds, first, "a triangle in " + name); !reach)
    return fail_all(reach.error());

  // Recast and Detour see the tile relative to the navmesh origin.
  const TileCoord local_tile{tile.x - first.origin_tile.x, tile.z - first.origin_tile.z};
  const bool at_world_origin = first.origin_tile == TileCoord{};
  const TileGeometry moved = at_world_origin ? TileGeometry() : MoveToNavMeshSpace(geometry, first);
  const TileGeometry& local = at_world_origin ? geometry : moved;
  NavMeshSettings local_settings = first;
  local_settings.origin_tile = {};
  AABB box = TileGatherBox(local_settings, local_tile);
  // Vertically the heightfield spans the geometry (with a cell to spare above, whatever the agent).
  box.min.y() = local.bounds.min.y() - first.cell_height;
  box.max.y() = local.bounds.max.y() + first.cell_height;
  std::vector<float> slopes;
  for (const std::size_t member : members) slopes.push_back(profiles[member].agent_max_slope);
  std::sort(slopes.begin(), slopes.end());
  slopes.erase(std::unique(slopes.begin(), slopes.end()), slopes.end());
  rcConfig raster_config = MakeConfig(first, box);
  raster_config.walkableClimb = std::get<6>(RasterKey(first));
  Result<SharedRaster> raster = Rasterize(raster_config, tile, local, std::move(slopes));
  if (!raster) return fail_all(raster.error());
  const double raster_ms = MillisecondsSince(start) / static_cast<double>(members.size());  // shared evenly

  std::vector<ProfileBuild> group = FindWalkableCells(profiles, members, box, tile, *raster);
  BuildOwnMeshes(group, tile);
  for (std::size_t i = 0; i < members.size(); ++i) {
    ProfileBuild& member = group[i];
    const NavMeshSettings& settings = profiles[members[i]];
    Result<RecastMeshes>& meshes = *group[member.source].meshes;
    if (!meshes) {
      out[members[i]] = meshes.error();
      continue;
    }
    BuiltTile& built = *out[members[i]];
    built.recast_ms = raster_ms + member.ms;
    if (member.source != i) built.polygons_from = static_cast<int>(members[member.source]);
    if (meshes->poly->npolys == 0) continue;
    const std::vector<DropLink> drops =
        FindDropLinks(settings, *meshes->poly, *raster->solid, *meshes->compact);
    Result<TileData> data = CreateDetourData(settings, member.config, local_tile, *meshes, member.top, drops);
    if (!data) {
      out[members[i]] = data.error();
      continue;
    }
    built.polygons = meshes->poly->npolys;
    built.data = std::move(*data);
  }
}

}  // namespace

std::vector<Result<BuiltTile>> BuildTileForProfiles(std::span<const NavMeshSettings> profiles, TileCoord tile,
                                                    const TileGeometry& geometry) {
  std::vector<Result<BuiltTile>> out;
  out.reserve(profiles.size());
  for (std::size_t i = 0; i < profiles.size(); ++i) out.emplace_back(BuiltTile{tile, {}, 0, 0.0, -1});
  std::map<decltype(RasterKey(profiles[0])), std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < profiles.size(); ++i) groups[RasterKey(profiles[i])].push_back(i);
  for (const auto& [key, members] : groups) BuildGroup(profiles, members, tile, geometry, out);
  return out;
}

Result<BuiltTile> BuildTile(const NavMeshSettings& settings, TileCoord tile, const TileGeometry& geometry) {
  return std::move(BuildTileForProfiles(std::span(&settings, 1), tile, geometry).front());
}

}  // namespace strata::navmesh
