#include "navmesh/Crowd.h"

#include <DetourCrowd.h>
#include <DetourNavMeshQuery.h>

#include <algorithm>
#include <cmath>

namespace strata::navmesh {

namespace {

float PlanarDistance(const Vec3& a, const Vec3& b) {
  const float dx = a.x() - b.x(), dz = a.z() - b.z();
  return std::sqrt(dx * dx + dz * dz);  // not std::hypot: its overflow care costs, every agent every frame
}

constexpr int kMaxRoutePolys = 1024;
constexpr int kMaxRouteCorners = 256;
constexpr int kRouteSearchNodes = 4096;
constexpr float kCornerPassed = 1.0f;  // a route corner this near (x-z, m) is behind the agent

Vec3 FromDetour(const float* v) {
  return {v[0], v[1], v[2]};
}

/// Whether an agent at `at` has turned corner `k` of `corners` (not the last): it is near it, or ahead of it
/// along the way on. Its corridor takes it round a corner wherever is shortest, not through the corner point.
bool CornerPassed(const Vec3& at, const std::vector<Vec3>& corners, std::size_t k) {
  const Vec3 corner = corners[k], onward = corners[k + 1] - corner, from_corner = at - corner;
  return PlanarDistance(at, corner) < kCornerPassed ||
         from_corner.x() * onward.x() + from_corner.z() * onward.z() > 0.0f;
}

/// The point `reach` metres along the way from `at` through `corners` (from `next` on), and whether the way
/// ends before it (the point is then the last corner).
std::pair<Vec3, bool> AlongRoute(const Vec3& at, const std::vector<Vec3>& corners, std::size_t next,
                                 float reach) {
  Vec3 from = at;
  float left = reach;
  for (std::size_t k = next; k < corners.size(); ++k) {
    const float length = (corners[k] - from).norm();
    if (length >= left) return {from + (left / length) * (corners[k] - from), false};
    left -= length;
    from = corners[k];
  }
  return {corners.back(), true};
}

}  // namespace

Result<std::unique_ptr<Crowd>> Crowd::Create(NavMeshService& service, int profile,
                                             const CrowdConfig& config) {
  if (profile < 0 || profile >= service.profile_count())
    return MakeError(ErrorCode::kInvalidArgument,
                     "crowd: the service has no profile " + std::to_string(profile));
  if (config.max_agents < 1 || config.max_agents > 65536)
    return MakeError(ErrorCode::kInvalidArgument, "crowd: max_agents must be in [1, 65536]");
  if (!std::isfinite(config.lookahead) || config.lookahead < 0.0f || config.request_every_updates < 1 ||
      !std::isfinite(config.arrive_distance) || config.arrive_distance <= 0.0f ||
      !std::isfinite(config.stuck_seconds) || config.stuck_seconds <= 0.0f ||
      !std::isfinite(config.corridor_reach) || config.corridor_reach < 1.0f)
    return MakeError(
        ErrorCode::kInvalidArgument,
        "crowd: lookahead >= 0, request_every_updates >= 1, arrive_distance and stuck_seconds > 0, "
        "corridor_reach >= 1 m");
  std::unique_ptr<Crowd> crowd(new Crowd(service, profile, config));
  const float radius = service.profile_settings(profile).agent_radius;
  const bool ready = crowd->navmesh_.Read([&](const dtNavMesh&) {
    // DetourCrowd's neighbour grid has cells of three times the radius it is given: twice the agents' radius
    // gives cells of 2.4 m for people, so a neighbour query (6 radii around) reads 9 cells, not 25.
    return crowd->crowd_->init(config.max_agents, 2.0f * radius, &crowd->navmesh_.detour());
  });
  const bool route_ready = crowd->route_query_ && crowd->navmesh_.Read([&](const dtNavMesh& mesh) {
    return dtStatusSucceed(crowd->route_query_->init(&mesh, kRouteSearchNodes));
  });
  if (!ready || !route_ready)
    return MakeError(ErrorCode::kCapacityExceeded, "crowd: DetourCrowd could not allocate");
  // Local avoidance sampled coarsely (RecastDemo's "low" quality: 5 directions, 2 rings, one refinement):
  // the default refines five times, which for a thousand agents costs several milliseconds a frame.
  dtObstacleAvoidanceParams avoidance = *crowd->crowd_->getObstacleAvoidanceParams(0);
  avoidance.adaptiveDivs = 5;
  avoidance.adaptiveRings = 2;
  avoidance.adaptiveDepth = 1;
  crowd->crowd_->setObstacleAvoidanceParams(0, &avoidance);
  return crowd;
}

Crowd::Crowd(NavMeshService& service, int profile, const CrowdConfig& config)
    : service_(service),
      profile_(profile),
      config_(config),
      navmesh_(service.navmesh(profile)),
      crowd_(dtAllocCrowd()),
      route_query_(dtAllocNavMeshQuery()),
      route_polys_(kMaxRoutePolys),
      route_corners_(3 * kMaxRouteCorners),
      agents_(static_cast<std::size_t>(config.max_agents)) {}

void Crowd::CrowdFree::operator()(dtCrowd* crowd) const {
  dtFreeCrowd(crowd);
}

void Crowd::QueryFree::operator()(dtNavMeshQuery* query) const {
  dtFreeNavMeshQuery(query);
}

Status Crowd::Check(int agent) const {
  if (agent < 0 || agent >= static_cast<int>(agents_.size()) ||
      !agents_[static_cast<std::size_t>(agent)].active)
    return MakeError(ErrorCode::kStaleBodyId, "crowd: no agent " + std::to_string(agent));
  return Status::Ok();
}

Result<int> Crowd::AddAgent(const Vec3& position, const CrowdAgentParams& params) {
  if (!IsFinite(position) || !std::isfinite(params.max_speed) || params.max_speed <= 0.0f ||
      !std::isfinite(params.max_acceleration) || params.max_acceleration <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument,
                     "crowd: an agent needs a finite position, speed and acceleration");
  const NavMeshSettings& settings = service_.profile_settings(profile_);
  dtCrowdAgentParams detour{};
  detour.radius = settings.agent_radius;
  detour.height = settings.agent_height;
  detour.maxAcceleration = params.max_acceleration;
  detour.maxSpeed = params.max_speed;
  detour.collisionQueryRange = settings.agent_radius * 6.0f;
  detour.pathOptimizationRange = settings.agent_radius * 30.0f;
  // Corridors are straightened by the periodic topology pass, not a raycast per agent per frame. No
  // separation: it pushes agents apart across the whole query range (15 m for a machine), so two agents whose
  // ways cross near their targets hold each other off; avoidance alone keeps them from walking into another.
  detour.updateFlags = DT_CROWD_ANTICIPATE_TURNS | DT_CROWD_OPTIMIZE_TOPO | DT_CROWD_OBSTACLE_AVOIDANCE;
  detour.obstacleAvoidanceType = 0;
  const Vec3 local = navmesh_.ToLocal(position);
  const int index = navmesh_.Read([&](const dtNavMesh&) {
    const dtNavMeshQuery& query = *crowd_->getNavMeshQuery();
    dtPolyRef ref = 0;
    float nearest[3];
    // DetourCrowd's own placement box is sized from the radius init was given (twice the agents').
    const float extents[3] = {2.0f * settings.agent_radius, 1.5f * settings.agent_radius,
                              2.0f * settings.agent_radius};
    query.findNearestPoly(local.data(), extents, crowd_->getFilter(0), &ref, nearest);
    return ref == 0 ? -2 : crowd_->addAgent(nearest, &detour);
  });
  if (index == -2)
    return MakeError(ErrorCode::kInvalidArgument, "crowd: the position is not on the built navmesh");
  if (index < 0) return MakeError(ErrorCode::kCapacityExceeded, "crowd: the crowd is full");
  Agent& agent = agents_[static_cast<std::size_t>(index)];
  agent = Agent{};
  agent.active = true;
  return index;
}

Status Crowd::RemoveAgent(int agent) {
  if (Status valid = Check(agent); !valid) return valid;
  crowd_->removeAgent(agent);
  agents_[static_cast<std::size_t>(agent)] = Agent{};
  return Status::Ok();
}

Status Crowd::SetTarget(int agent, const Vec3& target) {
  if (Status valid = Check(agent); !valid) return valid;
  if (!IsFinite(target)) return MakeError(ErrorCode::kInvalidArgument, "crowd: the target is not finite");
  Agent& record = agents_[static_cast<std::size_t>(agent)];
  record.has_target = true;
  record.target = target;
  record.best_distance = PlanarDistance(PositionOf(agent), target);
  record.since_progress = 0.0f;
  navmesh_.Read([&](const dtNavMesh&) {
    Retarget(agent);
    return 0;
  });
  return Status::Ok();
}

void Crowd::Retarget(int agent) {
  Agent& record = agents_[static_cast<std::size_t>(agent)];
  const dtNavMeshQuery& query = *crowd_->getNavMeshQuery();
  const float extents[3] = {1.0f, 4.0f, 1.0f};
  dtPolyRef ref = 0;
  float nearest[3];
  const auto find = [&](const Vec3& world) {
    query.findNearestPoly(navmesh_.ToLocal(world).data(), extents, crowd_->getFilter(0), &ref, nearest);
    return ref != 0;
  };
  // The target itself when its tile is built; else the farthest built ground on the straight way to it,
  // to walk to and wait at while the tiles beyond are built.
  record.target_on_mesh = find(record.target);
  if (!record.target_on_mesh) {
    const Vec3 from = PositionOf(agent);
    const Vec3 way(record.target.x() - from.x(), 0.0f, record.target.z() - from.z());
    const float length = way.norm();
    const float step = 0.25f * service_.profile_settings(profile_).tile_size();
    for (float along = length - step; along > 0.0f && ref == 0; along -= step)
      find(from + (along / length) * way + Vec3(0.0f, record.target.y() - from.y(), 0.0f) * (along / length));
  }
  record.route.clear();
  record.goal_ref = ref;
  if (ref == 0) {
    crowd_->resetMoveTarget(agent);  // nothing built on its way yet: stand and wait
    return;
  }
  record.goal = FromDetour(nearest);
  PlanRoute(agent);
  Steer(agent, true);
}

float Crowd::Reach(int agent) const {
  // Two seconds of walking at least: each move of the corridor is a path request, and DetourCrowd's path
  // queue searches only so many nodes a frame for all its agents.
  return std::max(config_.corridor_reach, 2.0f * crowd_->getAgent(agent)->params.maxSpeed);
}

void Crowd::PlanRoute(int agent) {
  Agent& record = agents_[static_cast<std::size_t>(agent)];
  record.route.clear();
  record.route_next = 0;
  record.route_version = navmesh_.version();
  const dtCrowdAgent& detour = *crowd_->getAgent(agent);
  const Vec3 at = FromDetour(detour.npos);
  const dtPolyRef start = detour.corridor.getFirstPoly();
  if (start == 0 || PlanarDistance(at, record.goal) <= Reach(agent)) return;
  int polys = 0;
  route_query_->findPath(start, record.goal_ref, at.data(), record.goal.data(), crowd_->getFilter(0),
                         route_polys_.data(), &polys, kMaxRoutePolys);
  if (polys == 0) return;
  // A partial route (the search ran out of nodes) ends at the polygon nearest the goal.
  Vec3 end = record.goal;
  if (route_polys_[static_cast<std::size_t>(polys - 1)] != record.goal_ref)
    route_query_->closestPointOnPoly(route_polys_[static_cast<std::size_t>(polys - 1)], record.goal.data(),
                                     end.data(), nullptr);
  int corners = 0;
  route_query_->findStraightPath(at.data(), end.data(), route_polys_.data(), polys, route_corners_.data(),
                                 nullptr, nullptr, &corners, kMaxRouteCorners);
  for (int k = 1; k < corners; ++k)
    record.route.push_back(FromDetour(&route_corners_[3 * static_cast<std::size_t>(k)]));
}

void Crowd::Steer(int agent, bool now) {
  Agent& record = agents_[static_cast<std::size_t>(agent)];
  if (record.route.empty()) {
    if (now) {
      crowd_->requestMoveTarget(agent, record.goal_ref, record.goal.data());
      record.corridor_end = record.goal;
    }
    return;
  }
  const Vec3 at = FromDetour(crowd_->getAgent(agent)->npos);
  while (record.route_next + 1 < record.route.size() && CornerPassed(at, record.route, record.route_next))
    ++record.route_next;
  if (!now && PlanarDistance(at, record.corridor_end) > 0.5f * Reach(agent)) return;
  if (!now && record.route_version != navmesh_.version()) {
    // Tiles ahead changed since the route was planned: plan it again before following it further.
    PlanRoute(agent);
    return Steer(agent, true);
  }
  const auto [point, at_goal] = AlongRoute(at, record.route, record.route_next, Reach(agent));
  dtPolyRef ref = 0;
  float nearest[3];
  const float extents[3] = {1.0f, 4.0f, 1.0f};
  crowd_->getNavMeshQuery()->findNearestPoly(point.data(), extents, crowd_->getFilter(0), &ref, nearest);
  if (at_goal || ref == 0) {
    record.route.clear();
    crowd_->requestMoveTarget(agent, record.goal_ref, record.goal.data());
    record.corridor_end = record.goal;
    return;
  }
  crowd_->requestMoveTarget(agent, ref, nearest);
  record.corridor_end = point;
}

void Crowd::ReplanStaleCorridors() {
  const std::uint64_t version = navmesh_.version();
  if (version == seen_version_) return;
  seen_version_ = version;
  const dtNavMeshQuery& query = *crowd_->getNavMeshQuery();
  for (int i = 0; i < static_cast<int>(agents_.size()); ++i) {
    const Agent& record = agents_[static_cast<std::size_t>(i)];
    if (!record.active || !record.has_target || record.state == CrowdAgentState::kArrived) continue;
    const dtPathCorridor& corridor = crowd_->getAgent(i)->corridor;
    bool stale = false;
    for (int k = 0; k < corridor.getPathCount() && !stale; ++k)
      stale = !query.isValidPolyRef(corridor.getPath()[k], crowd_->getFilter(0));
    if (stale) ++stats_.replans;
    // A replaced tile's polygons are never walked on; a target that was not built may be now.
    if (stale || !record.target_on_mesh) Retarget(i);
  }
}

void Crowd::RequestTiles() {
  // A share of the agents each update, all of them every request_every_updates: the cost is spread over the
  // frames, and tiles many agents want are queued once.
  const float tile = service_.profile_settings(profile_).tile_size();
  const ProfileMask mask = ProfileMask{1} << profile_;
  const std::size_t share = static_cast<std::size_t>(config_.request_every_updates);
  around_.clear();
  ahead_.clear();
  for (std::size_t i = stats_.updates % share; i < agents_.size(); i += share) {
    const Agent& record = agents_[i];
    if (!record.active) continue;
    const Vec3 at = PositionOf(static_cast<int>(i));
    around_.push_back(at);
    if (!record.has_target || record.state == CrowdAgentState::kArrived) continue;
    // Ahead on its way, not only around it: the tiles its straight line to the target crosses (circles of
    // half a tile, a tile apart, touch every tile the line crosses).
    const Vec3 way(record.target.x() - at.x(), 0.0f, record.target.z() - at.z());
    const float distance = way.norm();
    const float length = std::min(config_.lookahead, distance);
    for (float along = tile; along <= length; along += tile) ahead_.push_back(at + (along / distance) * way);
  }
  (void)service_.RequestAroundPoints(around_, 0.75f * tile, mask);
  (void)service_.RequestAroundPoints(ahead_, 0.5f * tile, mask);
}

void Crowd::UpdateStates(float dt) {
  const dtNavMeshQuery& query = *crowd_->getNavMeshQuery();
  std::size_t stuck = 0;
  for (int i = 0; i < static_cast<int>(agents_.size()); ++i) {
    Agent& record = agents_[static_cast<std::size_t>(i)];
    if (!record.active) continue;
    ++stats_.agent_updates;
    const dtCrowdAgent& agent = *crowd_->getAgent(i);
    const bool on_mesh = agent.state == DT_CROWDAGENT_STATE_OFFMESH ||
                         (agent.state == DT_CROWDAGENT_STATE_WALKING &&
                          query.isValidPolyRef(agent.corridor.getFirstPoly(), crowd_->getFilter(0)));
    if (!on_mesh) ++stats_.off_mesh;
    if (!record.has_target) {
      record.state = CrowdAgentState::kIdle;
      continue;
    }
    // DetourCrowd drops a target whose polygon went with a replaced tile and cannot be found again near
    // where it was; the agent would stand (or coast) there for ever. Plan it again from here.
    if (record.goal_ref != 0 && record.state != CrowdAgentState::kArrived &&
        (agent.targetState == DT_CROWDAGENT_TARGET_NONE ||
         agent.targetState == DT_CROWDAGENT_TARGET_FAILED)) {
      ++stats_.replans;
      Retarget(i);
    }
    const Vec3 at = navmesh_.ToWorld(Vec3(agent.npos[0], agent.npos[1], agent.npos[2]));
    const float distance = PlanarDistance(at, record.target);
    // A target off the walkable ground (in a rock, on a wall) is reached at the navmesh point nearest it.
    const bool at_nearest_ground =
        record.target_on_mesh && record.goal_ref != 0 &&
        PlanarDistance(FromDetour(agent.npos), record.goal) <= config_.arrive_distance;
    if (distance <= config_.arrive_distance || at_nearest_ground) {
      record.state = CrowdAgentState::kArrived;
      continue;
    }
    const float speed = std::sqrt(agent.vel[0] * agent.vel[0] + agent.vel[2] * agent.vel[2]);
    record.state =
        !record.target_on_mesh && speed < 0.1f ? CrowdAgentState::kWaiting : CrowdAgentState::kWalking;
    if (record.state == CrowdAgentState::kWaiting) {
      stats_.waiting_seconds += dt;
      record.since_progress = 0.0f;  // waiting for tiles is counted apart from being stuck
      continue;
    }
    if (distance < record.best_distance - 0.1f) {
      record.best_distance = distance;
      record.since_progress = 0.0f;
    } else {
      record.since_progress += dt;
    }
    stuck += record.since_progress >= config_.stuck_seconds;
  }
  stats_.stuck_agents = stuck;
}

Status Crowd::Update(float dt) {
  if (!std::isfinite(dt) || dt <= 0.0f || dt > 1.0f)
    return MakeError(ErrorCode::kInvalidArgument, "crowd: dt must be in (0, 1] seconds");
  RequestTiles();
  navmesh_.Read([&](const dtNavMesh&) {
    ReplanStaleCorridors();
    for (int i = 0; i < static_cast<int>(agents_.size()); ++i)
      if (agents_[static_cast<std::size_t>(i)].active && !agents_[static_cast<std::size_t>(i)].route.empty())
        Steer(i, false);
    crowd_->update(dt, nullptr);
    UpdateStates(dt);
    return 0;
  });
  ++stats_.updates;
  return Status::Ok();
}

Vec3 Crowd::PositionOf(int agent) const {
  const dtCrowdAgent& detour = *crowd_->getAgent(agent);
  return navmesh_.ToWorld(Vec3(detour.npos[0], detour.npos[1], detour.npos[2]));
}

Result<Vec3> Crowd::position(int agent) const {
  if (Status valid = Check(agent); !valid) return valid.error();
  return PositionOf(agent);
}

Result<Vec3> Crowd::velocity(int agent) const {
  if (Status valid = Check(agent); !valid) return valid.error();
  const dtCrowdAgent& detour = *crowd_->getAgent(agent);
  return Vec3(detour.vel[0], detour.vel[1], detour.vel[2]);
}

Result<CrowdAgentState> Crowd::state(int agent) const {
  if (Status valid = Check(agent); !valid) return valid.error();
  return agents_[static_cast<std::size_t>(agent)].state;
}

Result<bool> Crowd::stuck(int agent) const {
  if (Status valid = Check(agent); !valid) return valid.error();
  const Agent& record = agents_[static_cast<std::size_t>(agent)];
  return record.has_target && record.state == CrowdAgentState::kWalking &&
         record.since_progress >= config_.stuck_seconds;
}

int Crowd::agent_count() const {
  return static_cast<int>(
      std::count_if(agents_.begin(), agents_.end(), [](const Agent& a) { return a.active; }));
}

}  // namespace strata::navmesh
