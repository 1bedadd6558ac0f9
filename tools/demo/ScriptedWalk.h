// ScriptedWalk: the demo's player, a Character that walks a route of waypoints across the level as game code
// would drive it: each frame towards the next corner of a navmesh path to the next waypoint (straight at it
// where the navmesh has no path yet), at a walking speed, jumping and side-stepping out of the way of what
// blocks it, with the figures the demo prints. Call it from the thread that steps the world, after each step.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "navmesh/NavMeshQuery.h"
#include "navmesh/NavMeshService.h"
#include "physics/character/Character.h"

namespace strata::demo {

/// The courtyard's tour (x, z): up the stairs onto the platform, back down them, across the yard and over the
/// bridge across the trench.
std::vector<Vec3> CourtyardRoute();

/// How the walk went.
struct WalkReport {
  std::size_t waypoints = 0;
  std::size_t reached = 0;      ///< waypoints reached, in order
  float finished_at = -1.0f;    ///< seconds in, when it reached the last one (-1: not)
  float distance = 0.0f;        ///< walked, m
  float highest = 0.0f;         ///< highest feet above the start, m
  float grounded = 0.0f;        ///< share of updates that ended on walkable ground
  double mean_update_us = 0.0;  ///< Character::Update, wall clock
  double max_update_us = 0.0;
  int sidesteps = 0;  ///< times it was blocked and walked around
};

/// A character walking a route.
class ScriptedWalk {
 public:
  /// A player standing on the ground under the route's first point (`route` in x, z; y is found by a ray cast
  /// down from `top`), walking at `speed` m/s and asking `service` for the tiles it walks through (its paths
  /// come from them). Fails where no ground is under a waypoint.
  static Result<std::unique_ptr<ScriptedWalk>> Create(PhysicsSystem& world, navmesh::NavMeshService& service,
                                                      const std::vector<Vec3>& route, float top, float bottom,
                                                      float speed);

  /// One frame: steers towards the next waypoint and updates the character.
  Status Update(float dt, float time);
  const Character& character() const { return *character_; }
  /// The route's points on the ground.
  const std::vector<Vec3>& route() const { return route_; }
  /// Feet positions, one per update.
  const std::vector<Vec3>& trail() const { return trail_; }
  WalkReport report() const;

 private:
  ScriptedWalk(std::unique_ptr<Character> character, navmesh::NavMeshService& service,
               std::unique_ptr<navmesh::NavMeshQuery> query, std::vector<Vec3> route, float speed);
  /// Every half second: if it hardly moved, it walks around what blocks it for a while.
  void Steer(float time, const Vec3& feet);
  /// Where to walk towards now: the next corner of the navmesh path to the next waypoint (found again now and
  /// then), or the waypoint itself.
  Vec3 Aim(float time, const Vec3& feet);

  std::unique_ptr<Character> character_;
  navmesh::NavMeshService& service_;
  std::unique_ptr<navmesh::NavMeshQuery> query_;
  std::vector<Vec3> route_;
  std::vector<Vec3> path_;  // corners to the next waypoint
  std::size_t corner_ = 0;
  float path_time_ = -1.0f;
  float request_time_ = -1.0f;
  float speed_;
  std::size_t next_ = 1;
  float start_height_;
  float finished_at_ = -1.0f;
  float last_check_time_ = 0.0f;
  Vec3 last_check_feet_ = Vec3::Zero();
  float sidestep_until_ = -1.0f;
  int sidesteps_ = 0;  // also picks the next way around
  bool jump_ = false;  // jump in the next update
  std::size_t grounded_updates_ = 0;
  double total_update_us_ = 0.0;
  double max_update_us_ = 0.0;
  std::vector<Vec3> trail_;
};

}  // namespace strata::demo
