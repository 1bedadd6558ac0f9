// Crowd: the agents of one profile walking its navmesh with DetourCrowd (corridors, local avoidance) while
// the service builds, rebuilds and evicts tiles under them. Each update asks for the tiles around every agent
// and ahead on its way, lets an agent whose target is not built yet walk to the edge of what is and wait
// there, and after every publish checks each agent's corridor and replans those that hold a polygon of a
// replaced tile. Driven from one game thread (Update and the agent calls); it reads the navmesh under its
// read lock, so the service's threads publish between updates.
#pragma once

#include <memory>
#include <vector>

#include <DetourNavMesh.h>

#include "navmesh/NavMeshService.h"

class dtCrowd;
class dtNavMeshQuery;

namespace strata::navmesh {

struct CrowdConfig {
  int max_agents = 1024;
  float lookahead = 40.0f;         ///< tiles are asked for along each agent's way this far ahead (m)
  int request_every_updates = 30;  ///< how often each agent asks for tiles (updates; a share of them each)
  /// An agent this close (x-z, m) to its target, or to the navmesh point nearest a target off the navmesh
  /// (in a rock, on a wall), has arrived.
  float arrive_distance = 0.5f;
  float stuck_seconds = 5.0f;  ///< an agent with a target that gains no ground for this long is stuck
  /// How far along its way an agent's DetourCrowd corridor reaches (m; at least two seconds of its top
  /// speed). A farther target is planned as a route of corners; the corridor follows it, moved on as the
  /// agent walks. DetourCrowd walks an agent's whole corridor every frame, so corridors across a map cost
  /// every agent every frame.
  float corridor_reach = 16.0f;
};

/// How one agent moves.
struct CrowdAgentParams {
  float max_speed = 3.5f;         ///< m/s
  float max_acceleration = 8.0f;  ///< m/s^2
};

enum class CrowdAgentState {
  kIdle,  ///< no target
  kWalking,
  kWaiting,  ///< at the edge of the built navmesh, its target's tiles not ready yet
  kArrived,
};

struct CrowdStats {
  std::size_t updates = 0;
  std::size_t replans = 0;   ///< corridors found holding a polygon of a replaced or evicted tile, replanned
  std::size_t off_mesh = 0;  ///< agent-updates that ended with an agent on no valid polygon
  std::size_t agent_updates = 0;
  double waiting_seconds = 0.0;  ///< summed over agents: time spent waiting for tiles
  std::size_t stuck_agents = 0;  ///< agents stuck now (a target, no ground gained for stuck_seconds)
};

class Crowd {
 public:
  /// A crowd on profile `profile` of `service` (which must outlive it).
  static Result<std::unique_ptr<Crowd>> Create(NavMeshService& service, int profile,
                                               const CrowdConfig& config = {});
  Crowd(const Crowd&) = delete;
  Crowd& operator=(const Crowd&) = delete;

  /// An agent at the nearest navmesh point to `position` (within a tile); fails off the built navmesh, for a
  /// full crowd or bad numbers.
  Result<int> AddAgent(const Vec3& position, const CrowdAgentParams& params = {});
  Status RemoveAgent(int agent);
  /// Sends the agent towards `target`, which may lie on tiles not built yet.
  Status SetTarget(int agent, const Vec3& target);
  /// Advances every agent by `dt` seconds.
  Status Update(float dt);

  /// An agent's position, velocity and state; an error for an id that is not a live agent.
  Result<Vec3> position(int agent) const;
  Result<Vec3> velocity(int agent) const;
  Result<CrowdAgentState> state(int agent) const;
  /// Whether the agent has a target and gained no ground on it for stuck_seconds (waiting for tiles aside).
  Result<bool> stuck(int agent) const;
  int agent_count() const;
  const CrowdStats& stats() const { return stats_; }

 private:
  struct Agent {
    bool active = false;
    bool has_target = false;
    Vec3 target = Vec3::Zero();
    bool target_on_mesh = false;  ///< its tile is built: the goal is the navmesh point nearest the target
    float best_distance = 0.0f;   ///< nearest it has come to its target (stuck detection)
    float since_progress = 0.0f;
    CrowdAgentState state = CrowdAgentState::kIdle;
    // Where it is going now (the target, or the farthest built point on its way), in the navmesh's frame:
    // reached through `route` when farther than corridor_reach.
    dtPolyRef goal_ref = 0;
    Vec3 goal = Vec3::Zero();
    std::vector<Vec3> route;     ///< corners to the goal, the start left out (empty: steering at the goal)
    std::size_t route_next = 0;  ///< the first corner not yet passed
    std::uint64_t route_version = 0;   ///< the navmesh's version when the route was planned
    Vec3 corridor_end = Vec3::Zero();  ///< where its DetourCrowd corridor ends now
  };

  Crowd(NavMeshService& service, int profile, const CrowdConfig& config);
  Status Check(int agent) const;
  Vec3 PositionOf(int agent) const;  // a live agent's
  void RequestTiles();
  void Retarget(int agent);      // navmesh read lock held
  void PlanRoute(int agent);     // navmesh read lock held
  float Reach(int agent) const;  // how far its corridor reaches: corridor_reach, or farther for a fast agent
  /// Moves the agent's corridor on along its route once it has walked half of it (`now`: at once).
  void Steer(int agent, bool now);  // navmesh read lock held
  void ReplanStaleCorridors();      // navmesh read lock held
  void UpdateStates(float dt);      // navmesh read lock held

  NavMeshService& service_;
  const int profile_;
  const CrowdConfig config_;
  NavMesh& navmesh_;
  struct CrowdFree {
    void operator()(dtCrowd* crowd) const;
  };
  std::unique_ptr<dtCrowd, CrowdFree> crowd_;
  struct QueryFree {
    void operator()(dtNavMeshQuery* query) const;
  };
  std::unique_ptr<dtNavMeshQuery, QueryFree> route_query_;  // routes: searched from the game thread
  std::vector<dtPolyRef> route_polys_;
  std::vector<float> route_corners_;
  std::vector<Agent> agents_;
  std::vector<Vec3> around_, ahead_;  // RequestTiles' points, kept between updates
  std::uint64_t seen_version_ = 0;
  CrowdStats stats_;
};

}  // namespace strata::navmesh
