// AgentProfile: one kind of walker (a person, a large machine, a critter) and what its navmesh needs of the
// ground: its height and radius, the step it climbs, the slope it walks and the ledge it drops down. A
// NavMeshService builds one navmesh per profile from one gather of each tile. Value type; any thread.
#pragma once

#include <string>

#include "navmesh/NavMeshSettings.h"

namespace strata::navmesh {

struct AgentProfile {
  std::string name = "default";
  float height = NavMeshSettings().agent_height;        ///< clearance it needs (m)
  float radius = NavMeshSettings().agent_radius;        ///< its walkable area keeps this far from walls (m)
  float max_climb = NavMeshSettings().agent_max_climb;  ///< highest step it walks up (m)
  float max_slope = NavMeshSettings().agent_max_slope;  ///< steepest slope it walks (degrees)
  float max_drop = NavMeshSettings().agent_max_drop;    ///< deepest ledge it drops down (m; 0: none)
  int max_tiles = 0;  ///< its tile budget (NavMeshServiceConfig::max_tiles when 0)

  /// A person: 0.4 m radius, 1.8 m tall, 0.5 m steps, 45 degree slopes, drops of 2 m.
  static AgentProfile Person();
  /// A large machine: 2.5 m radius, 6 m tall, 1 m steps, 35 degree slopes, drops of 3 m.
  static AgentProfile Machine();
  /// A critter: 0.25 m radius, 0.5 m tall, 0.25 m steps, 50 degree slopes, drops of 1 m.
  static AgentProfile Critter();
  /// The profile of one of the names above, or an error listing them.
  static Result<AgentProfile> Named(const std::string& name);
  /// This agent's fields read from `settings` (what a single-agent service builds for).
  static AgentProfile FromSettings(const NavMeshSettings& settings, std::string name = "default");

  /// `shared` (cells, tiles, regions, origin) with this agent's height, radius, climb and slope.
  NavMeshSettings Apply(NavMeshSettings shared) const;
  /// A non-empty name of letters, digits, '_' or '-' (it names files and command-line choices) and, with
  /// `shared`, settings that validate.
  Status Validate(const NavMeshSettings& shared) const;
};

}  // namespace strata::navmesh
