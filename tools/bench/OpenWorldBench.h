// OpenWorldBench: agents walking across a generated open world far larger than the navmesh tile budget.
// Squads of crowd agents (person profile) walk from waypoint to waypoint (bouncing off the world's edges)
// while the world steps; the crowd asks for the tiles around and ahead of them, the service builds them in
// the background and evicts the ones left behind. Prints steps, builds,
// evictions, failures, tiles held, how often an agent stood on a ready tile, and memory over the walk
// and what several agent profiles built from one gather cost against one service each (and, with `json`,
// writes them to a file).
// Call from the main thread.
#pragma once

#include <string>
#include <vector>

#include "navmesh/NavMeshSettings.h"

namespace strata::bench {

struct OpenWorldOptions {
  float world_size = 2000.0f;     ///< side of the square world (m)
  int bodies = 20000;             ///< static obstacles and resting crates, the ground included
  int agents = 64;                ///< in squads of up to 8 that walk together
  float walk_distance = 2000.0f;  ///< each agent's walk (m)
  float agent_speed = 25.0f;      ///< m/s, the crowd agents' top speed; frames are 1/60 s of wall time
  int tile_budget = 256;          ///< the service's max_tiles
  int physics_threads = 1;
  int navmesh_threads = 1;
  unsigned seed = 7;
  navmesh::NavMeshSettings settings;
  /// Before the walk: build this many tiles a side at the world's centre for person, machine and critter
  /// from one gather and with one service each, `profile_cost_runs` times alternated (0: skip).
  int profile_cost_tiles = 8;
  int profile_cost_runs = 3;
  /// Before the walk: one crowd update's cost for these many person agents on a built block (none: skip).
  std::vector<int> crowd_agents = {64, 256, 1024};
  int crowd_frames = 300;
  std::string json;  ///< also write the figures here (empty: don't)
};

/// Runs the walk and prints its figures; returns a process exit code (1 when a tile failed to build).
int RunOpenWorldBench(const OpenWorldOptions& options);

}  // namespace strata::bench
