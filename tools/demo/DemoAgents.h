// DemoAgents: the main job's walkers. Each agent belongs to one agent profile; it asks for the navmesh tiles
// around where it spawns, joins its profile's Crowd once they are built, draws a target on the ground it can
// reach from there (or takes the one it was given) and walks to it through the crowd while tiles stream in.
// When the world cuts a drawn target off (a boulder comes to rest on it, and the rebuilt navmesh leaves it
// out), the agent draws another, as game code would.
// Driven from the game thread each frame (Update), like the Crowds it owns.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmesh/Crowd.h"
#include "navmesh/NavMeshQuery.h"
#include "navmesh/NavMeshService.h"

namespace strata::demo {

/// Where an agent spawns and what it is.
struct DemoAgentPlan {
  Vec3 start = Vec3::Zero();
  int profile = 0;             ///< index into the service's profiles
  std::optional<Vec3> target;  ///< where it goes; unset: drawn on its navmesh once it joins
  bool drop_down = false;      ///< placed where only a drop link leads to its target (reported)
};

/// Agents on the bundled courtyard whose only way to their target starts with a drop: on the 1.5 m crate
/// stack east of the trench (no ramp or step leads up or down), bound for the yard and, over the bridge, for
/// its west side. A walker that drops 1.5 m gets there; one that does not stays on the stack.
std::vector<DemoAgentPlan> CourtyardDropDownAgents(int profile);

struct DemoAgentsConfig {
  float request_radius = 16.0f;  ///< tiles built around a spawn before the agent joins (m)
  float target_radius = 24.0f;   ///< how far (about) a drawn target lies from the start (m)
  float snap_distance = 4.0f;    ///< a spawn this far (x-z) from its navmesh moves onto its nearest point (m)
  unsigned seed = 1;  ///< targets drawn from it (agent by agent: one agent does not move another's)
  navmesh::CrowdAgentParams walk;
};

/// One agent's run.
struct DemoAgent {
  DemoAgentPlan plan;
  Vec3 position = Vec3::Zero();  ///< now (its spawn until it joins)
  Vec3 target = Vec3::Zero();    ///< its target once it has one (the plan's, or drawn)
  bool joined = false;
  int crowd_id = -1;
  float joined_at = -1.0f;         ///< seconds into the run
  float arrived_at = -1.0f;        ///< -1: not (yet)
  float walked = 0.0f;             ///< m
  std::vector<Vec3> planned_path;  ///< the path on its navmesh when it set off for its (last) target
  int new_targets = 0;             ///< targets drawn again after the world cut one off
  std::string problem;             ///< why it could not join or set off (empty when it did)
};

class DemoAgents {
 public:
  /// Agents on `service` (which must outlive them), one Crowd per profile that has agents; asks for the
  /// tiles around every spawn. Fails for a plan naming a profile the service lacks or bad numbers.
  static Result<std::unique_ptr<DemoAgents>> Create(navmesh::NavMeshService& service,
                                                    std::vector<DemoAgentPlan> plans,
                                                    const DemoAgentsConfig& config = {});
  DemoAgents(const DemoAgents&) = delete;
  DemoAgents& operator=(const DemoAgents&) = delete;

  /// One frame of `dt` seconds ending `time` seconds into the run: agents whose ground is built join and set
  /// off, every crowd moves.
  Status Update(float dt, float time);

  const std::vector<DemoAgent>& agents() const { return agents_; }
  std::size_t arrived() const;
  /// The profile's crowd, or null when no agent of it was planned.
  const navmesh::Crowd* crowd(int profile) const;
  /// Whether `agent` could reach its target on a navmesh without drop links (a fresh path query with them
  /// excluded; false also when it has no target).
  Result<bool> ReachesWithoutLinks(std::size_t agent) const;

 private:
  DemoAgents(navmesh::NavMeshService& service, std::vector<DemoAgentPlan> plans,
             const DemoAgentsConfig& config);
  bool GroundBuilt(const DemoAgent& agent) const;
  void Join(std::size_t index, float time);
  /// Draws a target for `agent` around where it stands and sends it there (the problem when none is found).
  void DrawTarget(std::size_t index);
  /// Sends the agent to `target` through its crowd, with the path it sets off on.
  void SetOff(std::size_t index, const Vec3& target);
  void RetargetCutOff();
  navmesh::NavMeshQuery& query(int profile);
  Status RequestSpawnTiles() const;

  navmesh::NavMeshService& service_;
  const DemoAgentsConfig config_;
  std::vector<DemoAgent> agents_;
  std::vector<std::unique_ptr<navmesh::Crowd>> crowds_;          // by profile; null where no agent is planned
  std::vector<std::unique_ptr<navmesh::NavMeshQuery>> queries_;  // by profile, where crowds_ has one
  int frame_ = 0;
};

}  // namespace strata::demo
