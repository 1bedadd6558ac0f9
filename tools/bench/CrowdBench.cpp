#include "tools/bench/CrowdBench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "navmesh/Crowd.h"

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;

Result<CrowdUpdateFigures> RunCrowd(navmesh::NavMeshService& service, const AABB& block, int agents,
                                    int frames, unsigned seed) {
  navmesh::CrowdConfig config;
  config.max_agents = agents;
  Result<std::unique_ptr<navmesh::Crowd>> created = navmesh::Crowd::Create(service, 0, config);
  if (!created) return created.error();
  navmesh::Crowd& crowd = **created;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> x(block.min.x() + 2.0f, block.max.x() - 2.0f);
  std::uniform_real_distribution<float> z(block.min.z() + 2.0f, block.max.z() - 2.0f);
  const auto somewhere = [&] { return Vec3(x(random), 0.0f, z(random)); };
  std::vector<int> ids;
  for (int tries = 0; static_cast<int>(ids.size()) < agents && tries < 100 * agents; ++tries)
    if (Result<int> id = crowd.AddAgent(somewhere()); id) ids.push_back(*id);
  if (static_cast<int>(ids.size()) < agents)
    return MakeError(ErrorCode::kInvalidState, "crowd bench: could not place the agents on the block");
  for (const int id : ids) (void)crowd.SetTarget(id, somewhere());
  CrowdUpdateFigures figures;
  figures.agents = agents;
  figures.frames = frames;
  double total_ms = 0.0;
  for (int frame = 0; frame < frames; ++frame) {
    const Clock::time_point start = Clock::now();
    if (Status updated = crowd.Update(1.0f / 60.0f); !updated) return updated.error();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    total_ms += ms;
    figures.max_ms = std::max(figures.max_ms, ms);
    for (const int id : ids) {
      if (*crowd.state(id) != navmesh::CrowdAgentState::kArrived) continue;
      ++figures.arrived;
      (void)crowd.SetTarget(id, somewhere());
    }
  }
  figures.mean_ms = total_ms / frames;
  figures.off_mesh = crowd.stats().off_mesh;
  return figures;
}

}  // namespace

Result<std::vector<CrowdUpdateFigures>> MeasureCrowdUpdates(const PhysicsSystem& world,
                                                            const navmesh::NavMeshSettings& settings,
                                                            const navmesh::AgentProfile& profile,
                                                            const Vec3& center, int side,
                                                            const std::vector<int>& agent_counts, int frames,
                                                            unsigned seed) {
  navmesh::NavMeshServiceConfig config;
  config.settings = settings;
  config.profiles = {profile};
  config.max_tiles = (side + 2) * (side + 2);  // the block and the ring its edge agents ask for
  const float tile = settings.tile_size();
  const Vec3 corner(std::floor(center.x() / tile - static_cast<float>(side / 2)) * tile, -1.0f,
                    std::floor(center.z() / tile - static_cast<float>(side / 2)) * tile);
  const float span = static_cast<float>(side) * tile;
  const AABB block(corner + Vec3(0.01f, 0.0f, 0.01f), corner + Vec3(span - 0.01f, 2.0f, span - 0.01f));
  Result<std::unique_ptr<navmesh::NavMeshService>> service = navmesh::NavMeshService::Create(world, config);
  if (!service) return service.error();
  if (Status requested = (*service)->RequestBox(block); !requested) return requested.error();
  if (!(*service)->WaitUntilIdle(std::chrono::minutes(10)))
    return MakeError(ErrorCode::kInvalidState, "crowd bench: the block did not build within 10 minutes");
  std::vector<CrowdUpdateFigures> all;
  for (const int agents : agent_counts) {
    Result<CrowdUpdateFigures> figures = RunCrowd(**service, block, agents, frames, seed);
    if (!figures) return figures.error();
    all.push_back(*figures);
  }
  return all;
}

nlohmann::json ToJson(const std::vector<CrowdUpdateFigures>& figures) {
  nlohmann::json runs = nlohmann::json::array();
  for (const CrowdUpdateFigures& run : figures)
    runs.push_back({{"agents", run.agents},
                    {"frames", run.frames},
                    {"update_mean_ms", run.mean_ms},
                    {"update_max_ms", run.max_ms},
                    {"arrivals", run.arrived},
                    {"off_mesh", run.off_mesh}});
  return runs;
}

}  // namespace strata::bench
