// LevelBake: builds every navmesh tile over a level with the background service and waits for the result.
// The one place that decides how many tiles a level needs, so the CLI's bake and demo, the benches and the
// tests size the tile table the same way; a bake may be split into shards (one per machine of a farm) and
// merged. BakeLevel blocks its caller; the world may step on other threads. MergeShards: any thread.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "navmesh/NavMeshService.h"

namespace strata::navmesh {

/// `config` with `max_tiles` set to the tiles that cover `level_bounds` (x-z), or an error naming the level's
/// extent when a navmesh cannot hold them. Agents of a service made from it can request any tile of the
/// level. A level more than 2^17 cells from the world origin gets the navmesh origin at its centre tile
/// (unless `config` names one), so it bakes with full float precision wherever it lies.
Result<NavMeshServiceConfig> ConfigForLevel(NavMeshServiceConfig config, const AABB& level_bounds);

/// How BakeLevel runs.
struct LevelBakeOptions {
  NavMeshServiceConfig service;  ///< max_tiles is ignored: ConfigForLevel sets it
  /// Called on the caller's thread about every `progress_interval` while tiles build: (built, total).
  std::function<void(std::size_t built, std::size_t total)> progress;
  std::chrono::milliseconds progress_interval{100};
  std::chrono::milliseconds timeout{std::chrono::minutes(30)};
  /// Scale-out: build only share `shard` of `shard_count` (0 <= shard < shard_count): the level's tiles in
  /// coordinate order, every shard_count-th from the shard-th. Each tile's bytes are those a whole bake
  /// gives it, so MergeShards of every share saves the same file as one bake.
  int shard = 0;
  int shard_count = 1;
};

/// A finished bake. The service keeps running: it owns the navmesh and the build log, and rebuilds tiles
/// that the world changes under.
struct LevelBake {
  std::unique_ptr<NavMeshService> service;
  std::size_t tiles = 0;  ///< tiles the level covers (all of them were built)
  double wall_ms = 0.0;   ///< from the request to the last tile published
  SetCoverage coverage;   ///< the level's tiles and the share built: what to Save the navmesh with
};

/// Builds every tile over `level_bounds` from `world` (or the options' shard of them). Fails for an empty or
/// too large level, bad settings, a tile that could not be built (with Recast's or Detour's reason) or a bake
/// that outlasts the timeout.
Result<LevelBake> BakeLevel(const PhysicsSystem& world, const AABB& level_bounds,
                            const LevelBakeOptions& options = {});

/// The shards' tiles in one navmesh, and what is missing from them.
struct MergedShards {
  std::unique_ptr<NavMesh> navmesh;
  SetCoverage coverage;  ///< the whole level's when every shard was given; not known otherwise
  std::vector<int> missing_shards;
  std::vector<TileCoord> missing_tiles;  ///< the level tiles those shards hold, in coordinate order
};

/// The navmesh of every shard file (each saved from a sharded bake of one level): their tiles in one navmesh
/// which, saved with the returned coverage, gives the bytes one whole bake saves. Fails, naming the file, for
/// a file that does not load, navmesh parameters (tile size, origin, table size) or a level that differ from
/// the first file's, a tile or shard in two files, and (unless `allow_partial`) a set that lacks a shard or
/// whose files do not say which shard they are; the error lists the missing tiles.
Result<MergedShards> MergeShards(const std::vector<std::filesystem::path>& shard_files,
                                 bool allow_partial = false);

/// "(x, z), (x, z), ... and N more": tiles for a message.
std::string DescribeTiles(const std::vector<TileCoord>& tiles, std::size_t shown = 8);

}  // namespace strata::navmesh
