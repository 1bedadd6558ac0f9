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
  /// CPU time of the process's threads over the same builds: every service's worker and its scanner, which
  /// compares each ready tile with the world (wall time on two cores hides a scanner on the other core).
  double shared_cpu_ms = 0.0;
  double separate_cpu_ms = 0.0;
  bool same_tiles = false;  ///< every profile's navmesh had the same tile bytes both ways (NavMesh::TilesCrc)
  /// Profile tiles of the shared service that took an earlier profile's polygons (the same walkable cells).
  std::size_t polygons_taken = 0;
  double ratio() const { return separate_ms > 0.0 ? shared_ms / separate_ms : 0.0; }
  double cpu_ratio() const { return separate_cpu_ms > 0.0 ? shared_cpu_ms / separate_cpu_ms : 0.0; }
  nlohmann::json ToJson() const;
};

/// Builds the `side` x `side` tiles around `center` for `profiles` both ways, `runs` times alternated, on one
/// worker thread each.
Result<ProfileCostFigures> MeasureProfileCost(const PhysicsSystem& world,
                                              const navmesh::NavMeshSettings& settings,
                                              const std::vector<navmesh::AgentProfile>& profiles,
                                              const Vec3& center, int side, int runs);

}  // namespace strata::bench
