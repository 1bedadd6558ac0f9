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
  LevelBake bake{std::move(*service), static_cast<std::size_t>(config->max_tiles), 0.0, {}};
  const std::vector<TileCoord> level_tiles = bake.service->grid().TilesInBox(level_bounds);
  bake.coverage.shard = options.shard;
  bake.coverage.shard_count = options.shard_count;
  if (!level_tiles.empty()) {
    bake.coverage.first = bake.coverage.last = level_tiles.front();
    for (const TileCoord tile : level_tiles) {
      bake.coverage.first = {std::min(bake.coverage.first.x, tile.x),
                             std::min(bake.coverage.first.z, tile.z)};
      bake.coverage.last = {std::max(bake.coverage.last.x, tile.x), std::max(bake.coverage.last.z, tile.z)};
    }
  }

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

std::string DescribeTiles(const std::vector<TileCoord>& tiles, std::size_t shown) {
  std::string text;
  for (std::size_t i = 0; i < tiles.size() && i < shown; ++i)
    text += (i ? ", (" : "(") + std::to_string(tiles[i].x) + ", " + std::to_string(tiles[i].z) + ")";
  if (tiles.size() > shown) text += " and " + std::to_string(tiles.size() - shown) + " more";
  return text;
}

namespace {
Error MergeError(const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, "navmesh merge: " + why);
}

// The level tiles (coordinate order) that share `shard` of `coverage.shard_count` holds.
std::vector<TileCoord> TilesOfShard(const SetCoverage& coverage, int shard) {
  std::vector<TileCoord> tiles;
  std::size_t index = 0;
  for (int x = coverage.first.x; x <= coverage.last.x; ++x)
    for (int z = coverage.first.z; z <= coverage.last.z; ++z, ++index)
      if (index % static_cast<std::size_t>(coverage.shard_count) == static_cast<std::size_t>(shard))
        tiles.push_back({x, z});
  return tiles;
}

// Which shards the files hold, checked against each other; the missing ones in `merged`.
Status CheckShardSet(const std::vector<std::filesystem::path>& files,
                     const std::vector<SetCoverage>& coverages, bool allow_partial, MergedShards& merged) {
  const SetCoverage& first = coverages.front();
  for (std::size_t f = 0; f < files.size(); ++f) {
    if (!coverages[f].known()) {
      if (allow_partial) return Status::Ok();
      return MergeError(files[f].string() +
                        " does not say which shard of which level it is (not written by a sharded bake): "
                        "the set cannot be checked (--allow-partial merges it anyway)");
    }
    if (coverages[f].shard_count != first.shard_count || coverages[f].first != first.first ||
        coverages[f].last != first.last)
      return MergeError(files[f].string() + " is a shard of another split or level than " +
                        files[0].string());
  }
  std::vector<bool> present(static_cast<std::size_t>(first.shard_count), false);
  for (std::size_t f = 0; f < files.size(); ++f) {
    if (present[static_cast<std::size_t>(coverages[f].shard)])
      return MergeError("shard " + std::to_string(coverages[f].shard) + " is given twice (" +
                        files[f].string() + ")");
    present[static_cast<std::size_t>(coverages[f].shard)] = true;
  }
  for (int shard = 0; shard < first.shard_count; ++shard) {
    if (present[static_cast<std::size_t>(shard)]) continue;
    merged.missing_shards.push_back(shard);
    for (const TileCoord tile : TilesOfShard(first, shard)) merged.missing_tiles.push_back(tile);
  }
  std::sort(merged.missing_tiles.begin(), merged.missing_tiles.end());
  if (merged.missing_shards.empty()) {
    merged.coverage = {0, 1, first.first, first.last};
    return Status::Ok();
  }
  if (allow_partial) return Status::Ok();
  std::string shards;
  for (const int shard : merged.missing_shards)
    shards += (shards.empty() ? "" : ", ") + std::to_string(shard);
  return MergeError(std::to_string(merged.missing_shards.size()) + " of " +
                    std::to_string(first.shard_count) + " shards are missing (shard " + shards +
                    "): " + std::to_string(merged.missing_tiles.size()) + " tiles are in no file: " +
                    DescribeTiles(merged.missing_tiles) + " (--allow-partial writes the others)");
}
}  // namespace

Result<MergedShards> MergeShards(const std::vector<std::filesystem::path>& shard_files, bool allow_partial) {
  if (shard_files.empty()) return MergeError("no shard files");
  MergedShards merged;
  Result<std::unique_ptr<NavMesh>> first = NavMesh::Load(shard_files.front());
  if (!first) return first.error();
  merged.navmesh = std::move(*first);
  NavMesh& into = *merged.navmesh;
  std::vector<SetCoverage> coverages{into.coverage()};
  for (std::size_t f = 1; f < shard_files.size(); ++f) {
    const std::string name = shard_files[f].string();
    Result<std::unique_ptr<NavMesh>> shard = NavMesh::Load(shard_files[f]);
    if (!shard) return shard.error();
    coverages.push_back((*shard)->coverage());
    if (!SameParameters(into, **shard))
      return MergeError(name + " is not a shard of the same level as " + shard_files.front().string() +
                        " (tile size, origin or tile table differ)");
    if ((*shard)->profile() != into.profile())
      return MergeError(name + " was built for agent profile '" + (*shard)->profile() + "', " +
                        shard_files.front().string() + " for '" + into.profile() + "'");
    const std::vector<TileCoord> present = into.Tiles();
    for (const TileCoord tile : (*shard)->Tiles()) {
      if (std::find(present.begin(), present.end(), tile) != present.end())
        return MergeError("tile (" + std::to_string(tile.x) + ", " + std::to_string(tile.z) + ") of " + name +
                          " is in an earlier shard too");
      const TileCoord local{tile.x - (*shard)->origin_tile().x, tile.z - (*shard)->origin_tile().z};
      TileData data = (*shard)->Read([&](const dtNavMesh& mesh) {
        const dtMeshTile* found = mesh.getTileAt(local.x, local.z, 0);
        return TileData::CopyOf({found->data, static_cast<std::size_t>(found->dataSize)});
      });
      if (Status added = into.ReplaceTile(tile, std::move(data)); !added)
        return MergeError(name + ": " + added.message());
    }
  }
  if (Status complete = CheckShardSet(shard_files, coverages, allow_partial, merged); !complete)
    return complete.error();
  return merged;
}

}  // namespace strata::navmesh
