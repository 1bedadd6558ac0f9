#include "navmesh/LevelBake.h"

#include <algorithm>

#include "navmesh/TileBuilder.h"

namespace strata::navmesh {

Result<NavMeshServiceConfig> ConfigForLevel(NavMeshServiceConfig config, const AABB& level_bounds) {
  if (!level_bounds.IsValid())
    return MakeError(ErrorCode::kInvalidArgument,
                     "navmesh: the level has no geometry to bake (empty bounds)");
  if (Status reach = CheckReach(level_bounds, config.settings, "the level"); !reach) return reach.error();
  const Result<int> tiles = NavMeshService::MaxTilesToCover(level_bounds, config.settings.tile_size());
  if (!tiles) return tiles.error();
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
