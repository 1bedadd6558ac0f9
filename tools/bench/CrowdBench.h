// CrowdBench: what one crowd update costs on the game thread for 64, 256 and 1,024 agents walking to random
// targets over a built block of an open world. Call from the main thread with the world idle.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "navmesh/NavMeshService.h"

namespace strata::bench {

struct CrowdUpdateFigures {
  int agents = 0;
  int frames = 0;
  double mean_ms = 0.0;  ///< per update
  double max_ms = 0.0;
  std::size_t arrived = 0;  ///< agents that reached a target during the run (they then get another)
  std::size_t off_mesh = 0;
};

/// Builds the `side` x `side` tiles around `center` for `profile`, then for each agent count runs `frames`
/// updates of 1/60 s with agents placed and sent to targets at random (`seed`).
Result<std::vector<CrowdUpdateFigures>> MeasureCrowdUpdates(const PhysicsSystem& world,
                                                            const navmesh::NavMeshSettings& settings,
                                                            const navmesh::AgentProfile& profile,
                                                            const Vec3& center, int side,
                                                            const std::vector<int>& agent_counts, int frames,
                                                            unsigned seed);
nlohmann::json ToJson(const std::vector<CrowdUpdateFigures>& figures);

}  // namespace strata::bench
