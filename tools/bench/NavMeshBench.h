// NavMeshBench: what the background navmesh costs. Per tile: gather and Recast time, and the gather's
// overhead against building the same tile from pre-collected triangles; time from RequestAround to ready;
// the physics step with and without navmesh jobs running. Prints figures only; call from the main thread.
#pragma once

#include <string>

#include "navmesh/NavMeshSettings.h"

namespace strata::bench {

struct NavMeshBenchOptions {
  std::string level;          ///< level mesh file
  int crates = 2000;          ///< dynamic bodies that keep the step busy (debris: not gathered)
  int repeats = 5;            ///< builds per tile for the gather/Recast split (median taken)
  int step_blocks = 6;        ///< alternating blocks of steps with and without jobs
  int steps_per_block = 120;  ///< 60 Hz steps per block
  int physics_threads = 1;
  int navmesh_threads = 1;
  navmesh::NavMeshSettings settings;
  std::string json;  ///< also write the figures here (empty: no file)
};

/// Runs every part and prints it (and writes the figures as JSON when asked); returns a process exit code.
int RunNavMeshBench(const NavMeshBenchOptions& options);

}  // namespace strata::bench
