// NavMeshServiceConfig: how a NavMeshService builds and refreshes tiles: the shared Recast settings, the
// agent profiles (kinds of walker), which bodies count, threads, the tile budget and the dirty tracking's
// timing, validated in one place. Value type; any thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "navmesh/AgentProfile.h"
#include "navmesh/NavMeshSettings.h"
#include "navmesh/TileGather.h"

namespace strata::navmesh {

/// A set of agent profiles, one bit per index into NavMeshServiceConfig::profiles.
using ProfileMask = std::uint32_t;
inline constexpr ProfileMask kAllProfiles = ~ProfileMask{0};

/// How the service builds and refreshes tiles.
struct NavMeshServiceConfig {
  /// Cells, tiles, regions and origin, shared by every profile; its agent fields make the one profile of a
  /// service whose `profiles` is empty.
  NavMeshSettings settings;
  /// The kinds of walker, each with its own navmesh, tile states and budget (at most kMaxProfiles). Profiles
  /// share each tile's gather and, as their cell sizes are `settings`', its rasterization: the tile border
  /// is sized for the widest agent, and walkable and steep surfaces meeting in a cell merge within the
  /// lowest climb (profile_settings() gives each profile's resolved settings).
  std::vector<AgentProfile> profiles;
  static constexpr int kMaxProfiles = 32;
  NavMeshBodyFilter filter;
  static constexpr int kMaxWorkerThreads = 64;
  int worker_threads = 1;  ///< background build threads, at most kMaxWorkerThreads
  /// The tile budget: at most this many tiles hold navmesh data at once (Detour's tile table). When a new
  /// tile needs a slot, the published tile requested longest ago (farthest from its requester among equals)
  /// is evicted, so agents can walk across a world of any size.
  int max_tiles = 1024;          ///< per profile, unless the profile sets its own
  float move_threshold = 0.25f;  ///< a counted body whose bounds move more than this (m) makes its tile stale
  std::chrono::milliseconds rebuild_delay{250};  ///< a stale tile waits this long for more changes
  std::chrono::milliseconds scan_interval{20};   ///< how often ready tiles are checked for changes
  /// Added to the service threads' nice value (Linux; 0 leaves them as created). A lower priority lets a
  /// game thread that wakes up (e.g. a step that waited for a body lock) take a core back at once instead of
  /// waiting out a background thread's time slice.
  int thread_niceness = 10;
  Status Validate() const;
};

}  // namespace strata::navmesh
