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

Result<LevelBake> BakeLevel(const PhysicsSystem& world, const AABB& level_bounds,
                            const LevelBakeOptions& options) {
  using Clock = std::chrono::steady_clock;
  const Result<NavMeshServiceConfig> config = ConfigForLevel(options.service, level_bounds);
  if (!config) return config.error();
  Result<std::unique_ptr<NavMeshService>> service = NavMeshService::Create(world, *config);
  if (!service) return service.error();
  LevelBake bake{std::move(*service), static_cast<std::size_t>(config->max_tiles), 0.0};

  const Clock::time_point start = Clock::now();
  if (Status requested = bake.service->RequestBox(level_bounds); !requested) return requested.error();
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
