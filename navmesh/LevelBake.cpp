#include "navmesh/LevelBake.h"

#include <algorithm>

#include "navmesh/TileBuilder.h"

namespace strata::navmesh {

Result<NavMeshServiceConfig> ConfigForLevel(NavMeshServiceConfig config, const AABB& level_bounds) {
  if (!level_bounds.IsValid())
    return MakeError(ErrorCode::kInvalidArgument,
                     "navmesh: the level has no geometry to bake (empty bounds)");
  // Its extent first: a level no navmesh could hold gets no origin of its own.
  const Result<int> tiles = NavMeshService::MaxTilesToCover(level_bounds, config.settings.tile_size());
  if (!tiles) return tiles.error();
  // Near the world origin the navmesh keeps it (its file is then exactly RecastDemo's). Farther out than
  // 2^17 cells (26 km at 0.2 m), where a float no longer resolves 1/64 of a cell, the navmesh gets its own
  // origin at the level's centre tile, unless the caller chose one.
  const double near_reach = static_cast<double>(config.settings.cell_size) * 131072.0;
  const double reach =
      std::max(level_bounds.min.cwiseAbs().maxCoeff(), level_bounds.max.cwiseAbs().maxCoeff());
  if (reach > near_reach && config.settings.origin_tile == TileCoord{})
    config.settings.origin_tile = TileGrid(config.settings.tile_size()).TileAt(level_bounds.Center());
  if (Status valid = config.settings.Validate(); !valid) return valid.error();
  if (Status reach_check = CheckReach(level_bounds, config.settings, "the level"); !reach_check)
    return reach_check.error();
  config.max_tiles = std::max(*tiles, 1);
  return config;
}

namespace {
// Requests the shard's tiles one by one; returns how many.
Result<std::size_t> RequestShard(NavMeshService& service, const AABB& level_bounds,
                                 const LevelBakeOptions& options) {
  const TileGrid& grid = service.grid();
  std::vector<TileCoord> tiles = grid.TilesInBox(level_bounds);
  std::sort(tiles.begin(), tiles.end());
  std::size_t requested = 0;
  for (std::size_t i = static_cast<std::size_t>(options.shard); i < tiles.size();
       i += static_cast<std::size_t>(options.shard_count)) {
    // A box just inside the tile, so it covers that tile alone.
    const AABB bounds = grid.Bounds(tiles[i]);
    const Vec3 inset(0.01f, 0.0f, 0.01f);
    if (Status status = service.RequestBox(AABB(bounds.min + inset, bounds.max - inset)); !status)
      return status.error();
    ++requested;
  }
  return requested;
}

bool SameParameters(const NavMesh& a, const NavMesh& b) {
  const dtNavMeshParams pa = a.Read([](const dtNavMesh& mesh) { return *mesh.getParams(); });
  const dtNavMeshParams pb = b.Read([](const dtNavMesh& mesh) { return *mesh.getParams(); });
  return a.tile_size() == b.tile_size() && a.origin() == b.origin() && a.origin_tile() == b.origin_tile() &&
         pa.tileWidth == pb.tileWidth && pa.tileHeight == pb.tileHeight && pa.maxTiles == pb.maxTiles &&
         pa.maxPolys == pb.maxPolys;
}
}  // namespace

Result<LevelBake> BakeLevel(const PhysicsSystem& world, const AABB& level_bounds,
                            const LevelBakeOptions& options) {
  using Clock = std::chrono::steady_clock;
  const Result<NavMeshServiceConfig> config = ConfigForLevel(options.service, level_bounds);
  if (!config) return config.error();
  Result<std::unique_ptr<NavMeshService>> service = NavMeshService::Create(world, *config);
  if (!service) return service.error();
  LevelBake bake{std::move(*service), static_cast<std::size_t>(config->max_tiles), 0.0};

  if (options.shard_count < 1 || options.shard < 0 || options.shard >= options.shard_count)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh bake: shard " + std::to_string(options.shard) +
                                                      " of " + std::to_string(options.shard_count) +
                                                      " (want 0 <= shard < count)");
  const Clock::time_point start = Clock::now();
  if (options.shard_count == 1) {
    if (Status requested = bake.service->RequestBox(level_bounds); !requested) return requested.error();
  } else {
    Result<std::size_t> requested = RequestShard(*bake.service, level_bounds, options);
    if (!requested) return requested.error();
    bake.tiles = *requested;
  }
  const Clock::time_point deadline = start + options.timeout;
  const auto report = [&] {
    if (options.progress) options.progress(bake.service->stats().builds, bake.tiles);
  };
  while (!bake.service->WaitUntilIdle(options.progress_interval)) {
    report();
    if (Clock::now() >= deadline)
      return MakeError(ErrorCode::kInvalidState,
                       "navmesh bake: " + std::to_string(bake.service->stats().builds) + " of " +
                           std::to_string(bake.tiles) + " tiles built in " +
                           std::to_string(options.timeout.count()) + " ms");
  }
  report();
  bake.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  if (bake.service->stats().failures > 0)
    return MakeError(ErrorCode::kCapacityExceeded, "navmesh bake: " + bake.service->last_error());
  return bake;
}

}  // namespace strata::navmesh

namespace strata::navmesh {

Result<std::unique_ptr<NavMesh>> MergeShards(const std::vector<std::filesystem::path>& shard_files) {
  if (shard_files.empty()) return MakeError(ErrorCode::kInvalidArgument, "navmesh merge: no shard files");
  Result<std::unique_ptr<NavMesh>> merged = NavMesh::Load(shard_files.front());
  if (!merged) return merged.error();
  NavMesh& into = **merged;
  for (std::size_t f = 1; f < shard_files.size(); ++f) {
    const std::string name = shard_files[f].string();
    Result<std::unique_ptr<NavMesh>> shard = NavMesh::Load(shard_files[f]);
    if (!shard) return shard.error();
    if (!SameParameters(into, **shard))
      return MakeError(ErrorCode::kInvalidArgument,
                       "navmesh merge: " + name + " is not a shard of the same level as " +
                           shard_files.front().string() + " (tile size, origin or tile table differ)");
    const std::vector<TileCoord> present = into.Tiles();
    for (const TileCoord tile : (*shard)->Tiles()) {
      if (std::find(present.begin(), present.end(), tile) != present.end())
        return MakeError(ErrorCode::kInvalidArgument, "navmesh merge: tile (" + std::to_string(tile.x) +
                                                          ", " + std::to_string(tile.z) + ") of " + name +
                                                          " is in an earlier shard too");
      const TileCoord local{tile.x - (*shard)->origin_tile().x, tile.z - (*shard)->origin_tile().z};
      TileData data = (*shard)->Read([&](const dtNavMesh& mesh) {
        const dtMeshTile* found = mesh.getTileAt(local.x, local.z, 0);
        return TileData::CopyOf({found->data, static_cast<std::size_t>(found->dataSize)});
      });
      if (Status added = into.ReplaceTile(tile, std::move(data)); !added)
        return MakeError(added.error().code, "navmesh merge: " + name + ": " + added.message());
    }
  }
  return merged;
}

}  // namespace strata::navmesh
