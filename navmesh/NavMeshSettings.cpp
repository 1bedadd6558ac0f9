#include "navmesh/NavMeshSettings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

namespace strata::navmesh {

namespace {

Status OutOfRange(const char* field, double value, const char* range) {
  return MakeError(ErrorCode::kInvalidArgument, std::string("navmesh settings: ") + field + " = " +
                                                    std::to_string(value) + " is out of range " + range);
}

bool InRange(float value, float low, float high) {
  return std::isfinite(value) && value >= low && value <= high;
}

}  // namespace

int NavMeshSettings::border_cells() const {
  return static_cast<int>(std::ceil(std::max(agent_radius, raster_border_radius) / cell_size)) + 3;
}

Vec3d NavMeshSettings::origin() const {
  const double side = tile_size();
  return {static_cast<double>(origin_tile.x) * side, 0.0, static_cast<double>(origin_tile.z) * side};
}

Status NavMeshSettings::Validate() const {
  if (!InRange(cell_size, 0.01f, 10.0f)) return OutOfRange("cell_size", cell_size, "[0.01, 10]");
  if (!InRange(cell_height, 0.01f, 10.0f)) return OutOfRange("cell_height", cell_height, "[0.01, 10]");
  if (tile_cells < 8 || tile_cells > 1024) return OutOfRange("tile_cells", tile_cells, "[8, 1024]");
  if (!InRange(agent_height, cell_height, 100.0f))
    return OutOfRange("agent_height", agent_height, "[cell_height, 100]");
  if (!InRange(agent_radius, 0.0f, 50.0f)) return OutOfRange("agent_radius", agent_radius, "[0, 50]");
  if (!InRange(agent_max_climb, 0.0f, 100.0f))
    return OutOfRange("agent_max_climb", agent_max_climb, "[0, 100]");
  if (!InRange(agent_max_slope, 0.0f, 89.9f))
    return OutOfRange("agent_max_slope", agent_max_slope, "[0, 89.9]");
  if (!InRange(agent_max_drop, 0.0f, 100.0f)) return OutOfRange("agent_max_drop", agent_max_drop, "[0, 100]");
  if (region_min_size < 0 || region_min_size > 1000)
    return OutOfRange("region_min_size", region_min_size, "[0, 1000]");
  if (region_merge_size < 0 || region_merge_size > 1000)
    return OutOfRange("region_merge_size", region_merge_size, "[0, 1000]");
  if (!InRange(edge_max_length, 0.0f, 1000.0f))
    return OutOfRange("edge_max_length", edge_max_length, "[0, 1000]");
  if (!InRange(edge_max_error, 0.1f, 100.0f))
    return OutOfRange("edge_max_error", edge_max_error, "[0.1, 100]");
  if (verts_per_poly < 3 || verts_per_poly > 6) return OutOfRange("verts_per_poly", verts_per_poly, "[3, 6]");
  if (!InRange(detail_sample_distance, 0.0f, 1000.0f))
    return OutOfRange("detail_sample_distance", detail_sample_distance, "[0, 1000]");
  if (!InRange(detail_sample_max_error, 0.0f, 1000.0f))
    return OutOfRange("detail_sample_max_error", detail_sample_max_error, "[0, 1000]");
  if (std::isnan(raster_border_radius) || raster_border_radius > 50.0f)
    return OutOfRange("raster_border_radius", raster_border_radius, "[agent_radius, 50] or negative");
  if (std::isnan(raster_merge_climb) || raster_merge_climb > agent_max_climb)
    return OutOfRange("raster_merge_climb", raster_merge_climb, "[0, agent_max_climb] or negative");
  // Far enough out that the origin itself is past what any level could reach from the world origin.
  constexpr int kMaxOriginTile = 1 << 26;
  if (std::abs(origin_tile.x) > kMaxOriginTile || std::abs(origin_tile.z) > kMaxOriginTile)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh settings: origin_tile is beyond 2^26 tiles");
  // Detour stores cell counts of a tile side in 16 bits, with the border on both sides.
  if (tile_cells + 2 * border_cells() > 4096)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh settings: agent_radius / cell_size is too large");
  return Status::Ok();
}

}  // namespace strata::navmesh
