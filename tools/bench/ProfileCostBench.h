// ProfileCostBench: what building a navmesh for several agent profiles from one gather costs against one
// service per profile, on the same tiles of a world (the open-world bench's). Call from the main thread with
// the world idle.
#pragma once

#include <nlohmann/json.hpp>

#include "navmesh/NavMeshService.h"

namespace strata::bench {

struct ProfileCostFigures {
  int profiles = 0;
  int tiles = 0;
  double shared_ms = 0.0;    ///< one service, every profile (median of the runs)
  double separate_ms = 0.0;  ///< one service per profile, one after another (median of the runs)
  bool same_tiles = false;   ///< every profile's navmesh had the same polygons and area both ways
  double ratio() const { return separate_ms > 0.0 ? shared_ms / separate_ms : 0.0; }
  nlohmann::json ToJson() const;
};

/// Builds the `side` x `side` tiles around `center` for `profiles` both ways, `runs` times alternated, on one
/// worker thread each.
Result<ProfileCostFigures> MeasureProfileCost(const PhysicsSystem& world,
                                              const navmesh::NavMeshSettings& settings,
                                              const std::vector<navmesh::AgentProfile>& profiles,
                                              const Vec3& center, int side, int runs);

}  // namespace strata::bench
