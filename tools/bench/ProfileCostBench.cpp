#include "tools/bench/ProfileCostBench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;

/// CPU time of every thread of the process so far (ms): the services' workers and scanners, while the world
/// is idle and the main thread sleeps in WaitUntilIdle.
double ProcessCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

struct Built {
  double ms = 0.0;
  double cpu_ms = 0.0;
  std::vector<std::uint32_t> navmeshes;  ///< per profile: the CRC of its tiles
  std::size_t polygons_taken = 0;        ///< profile tiles that took another profile's polygons
};

Result<Built> BuildBlock(const PhysicsSystem& world, const navmesh::NavMeshServiceConfig& config,
                         const AABB& block) {
  const Clock::time_point start = Clock::now();
  const double cpu_start = ProcessCpuMs();
  Result<std::unique_ptr<navmesh::NavMeshService>> service = navmesh::NavMeshService::Create(world, config);
  if (!service) return service.error();
  if (Status requested = (*service)->RequestBox(block); !requested) return requested.error();
  if (!(*service)->WaitUntilIdle(std::chrono::minutes(10)))
    return MakeError(ErrorCode::kInvalidState, "profile cost: the block did not build within 10 minutes");
  if ((*service)->stats().failures > 0) return MakeError(ErrorCode::kInvalidState, (*service)->last_error());
  Built built;
  built.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  built.cpu_ms = ProcessCpuMs() - cpu_start;
  for (int p = 0; p < (*service)->profile_count(); ++p)
    built.navmeshes.push_back((*service)->navmesh(p).TilesCrc());
  built.polygons_taken = (*service)->stats().polygons_taken;
  return built;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

nlohmann::json ProfileCostFigures::ToJson() const {
  return {{"profiles", profiles},
          {"tiles", tiles},
          {"shared_ms", shared_ms},
          {"separate_ms", separate_ms},
          {"ratio", ratio()},
          {"shared_cpu_ms", shared_cpu_ms},
          {"separate_cpu_ms", separate_cpu_ms},
          {"cpu_ratio", cpu_ratio()},
          {"same_tiles", same_tiles},
          {"polygons_taken", polygons_taken}};
}

Result<ProfileCostFigures> MeasureProfileCost(const PhysicsSystem& world,
                                              const navmesh::NavMeshSettings& settings,
                                              const std::vector<navmesh::AgentProfile>& profiles,
                                              const Vec3& center, int side, int runs) {
  navmesh::NavMeshServiceConfig shared;
  shared.settings = settings;
  shared.profiles = profiles;
  shared.max_tiles = side * side;
  shared.thread_niceness = 0;
  // Whole tiles: `side` of them from the tile `side / 2` tiles before the one holding the centre.
  const float tile = settings.tile_size();
  const Vec3 corner(std::floor(center.x() / tile - static_cast<float>(side / 2)) * tile, -1.0f,
                    std::floor(center.z() / tile - static_cast<float>(side / 2)) * tile);
  const float span = static_cast<float>(side) * tile - 0.02f;
  const AABB block(corner + Vec3(0.01f, 0.0f, 0.01f), corner + Vec3(0.01f + span, 2.0f, 0.01f + span));
  // Each separate service builds what its profile builds in the shared one (the same resolved settings).
  std::vector<navmesh::NavMeshServiceConfig> separate;
  {
    Result<std::unique_ptr<navmesh::NavMeshService>> resolver =
        navmesh::NavMeshService::Create(world, shared);
    if (!resolver) return resolver.error();
    for (int p = 0; p < (*resolver)->profile_count(); ++p) {
      navmesh::NavMeshServiceConfig alone = shared;
      alone.profiles.clear();
      alone.settings = (*resolver)->profile_settings(p);
      separate.push_back(alone);
    }
  }
  ProfileCostFigures figures;
  figures.profiles = static_cast<int>(profiles.size());
  figures.tiles = side * side;
  figures.same_tiles = true;
  std::vector<double> shared_runs, separate_runs, shared_cpu_runs, separate_cpu_runs;
  for (int run = 0; run < runs; ++run) {
    Result<Built> together = BuildBlock(world, shared, block);
    if (!together) return together.error();
    shared_runs.push_back(together->ms);
    shared_cpu_runs.push_back(together->cpu_ms);
    figures.polygons_taken = together->polygons_taken;
    double apart_ms = 0.0, apart_cpu_ms = 0.0;
    for (std::size_t p = 0; p < separate.size(); ++p) {
      Result<Built> apart = BuildBlock(world, separate[p], block);
      if (!apart) return apart.error();
      apart_ms += apart->ms;
      apart_cpu_ms += apart->cpu_ms;
      figures.same_tiles = figures.same_tiles && apart->navmeshes.front() == together->navmeshes[p];
    }
    separate_runs.push_back(apart_ms);
    separate_cpu_runs.push_back(apart_cpu_ms);
  }
  figures.shared_ms = Median(shared_runs);
  figures.separate_ms = Median(separate_runs);
  figures.shared_cpu_ms = Median(shared_cpu_runs);
  figures.separate_cpu_ms = Median(separate_cpu_runs);
  return figures;
}

}  // namespace strata::bench
