#include "tools/demo/DemoAgents.h"

#include <cmath>
#include <cstdio>
#include <random>

namespace strata::demo {

namespace {

// Spawns that wait for their ground ask for it again this often (frames): a request is cheap, and a tile
// evicted meanwhile comes back.
constexpr int kRequestEveryFrames = 60;
// Waiting agents look at their tiles' states this often (frames): tens of thousands of agents would
// otherwise read the tile table every frame.
constexpr int kJoinCheckEveryFrames = 5;

}  // namespace

std::vector<DemoAgentPlan> CourtyardDropDownAgents(int profile) {
  // The stack's top is x 52-56, z 40-44, 1.5 m up; the bridge crosses the trench (x 40-48) at z 30-34.
  return {{Vec3(53.8f, 1.5f, 42.6f), profile, Vec3(58.0f, 0.0f, 30.0f), true},
          {Vec3(54.4f, 1.5f, 41.4f), profile, Vec3(33.0f, 0.0f, 26.0f), true}};
}

Result<std::unique_ptr<DemoAgents>> DemoAgents::Create(navmesh::NavMeshService& service,
                                                       std::vector<DemoAgentPlan> plans,
                                                       const DemoAgentsConfig& config) {
  if (!std::isfinite(config.request_radius) || config.request_radius < 0.0f ||
      !std::isfinite(config.target_radius) || config.target_radius <= 0.0f ||
      !std::isfinite(config.snap_distance) || config.snap_distance <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument,
                     "demo agents: request radius >= 0, target radius and snap distance > 0");
  for (const DemoAgentPlan& plan : plans) {
    if (plan.profile < 0 || plan.profile >= service.profile_count())
      return MakeError(ErrorCode::kInvalidArgument,
                       "demo agents: no profile " + std::to_string(plan.profile) + " in the service");
    if (!IsFinite(plan.start) || (plan.target && !IsFinite(*plan.target)))
      return MakeError(ErrorCode::kInvalidArgument, "demo agents: a spawn or target is not finite");
  }
  std::unique_ptr<DemoAgents> agents(new DemoAgents(service, std::move(plans), config));
  std::vector<int> per_profile(static_cast<std::size_t>(service.profile_count()), 0);
  for (const DemoAgent& agent : agents->agents_) ++per_profile[static_cast<std::size_t>(agent.plan.profile)];
  for (int profile = 0; profile < service.profile_count(); ++profile) {
    const int count = per_profile[static_cast<std::size_t>(profile)];
    if (count == 0) continue;
    navmesh::CrowdConfig crowd_config;
    crowd_config.max_agents = count;
    Result<std::unique_ptr<navmesh::Crowd>> crowd = navmesh::Crowd::Create(service, profile, crowd_config);
    if (!crowd) return crowd.error();
    agents->crowds_[static_cast<std::size_t>(profile)] = std::move(*crowd);
    Result<std::unique_ptr<navmesh::NavMeshQuery>> query =
        navmesh::NavMeshQuery::Create(service.navmesh(profile));
    if (!query) return query.error();
    agents->queries_[static_cast<std::size_t>(profile)] = std::move(*query);
  }
  if (Status requested = agents->RequestSpawnTiles(); !requested) return requested.error();
  return agents;
}

DemoAgents::DemoAgents(navmesh::NavMeshService& service, std::vector<DemoAgentPlan> plans,
                       const DemoAgentsConfig& config)
    : service_(service),
      config_(config),
      crowds_(static_cast<std::size_t>(service.profile_count())),
      queries_(static_cast<std::size_t>(service.profile_count())) {
  agents_.reserve(plans.size());
  for (DemoAgentPlan& plan : plans) {
    DemoAgent agent;
    agent.position = plan.start;
    agent.plan = std::move(plan);
    agents_.push_back(std::move(agent));
  }
}

Status DemoAgents::RequestSpawnTiles() const {
  for (const DemoAgent& agent : agents_) {
    if (agent.joined) continue;
    const navmesh::ProfileMask mask = navmesh::ProfileMask{1} << agent.plan.profile;
    if (Status requested = service_.RequestAround(agent.plan.start, config_.request_radius, mask); !requested)
      return requested;
  }
  return Status::Ok();
}

bool DemoAgents::GroundBuilt(const DemoAgent& agent) const {
  for (const navmesh::TileCoord tile :
       service_.grid().TilesInCircle(agent.plan.start, config_.request_radius))
    if (!service_.IsPublished(tile, agent.plan.profile)) return false;
  return true;
}

navmesh::NavMeshQuery& DemoAgents::query(int profile) {
  return *queries_[static_cast<std::size_t>(profile)];
}

void DemoAgents::Join(std::size_t index, float time) {
  DemoAgent& agent = agents_[index];
  agent.joined = true;
  agent.joined_at = time;
  navmesh::NavMeshQuery& ground_query = query(agent.plan.profile);
  ground_query.set_search_extents(Vec3(config_.snap_distance, 8.0f, config_.snap_distance));
  const Result<navmesh::NearestPoly> ground = ground_query.FindNearestPoly(agent.plan.start);
  if (!ground) {
    char why[96];
    std::snprintf(why, sizeof(why), "no navmesh within %.1f m of its spawn", config_.snap_distance);
    agent.problem = why;
    return;
  }
  const Result<int> id =
      crowds_[static_cast<std::size_t>(agent.plan.profile)]->AddAgent(ground->point, config_.walk);
  if (!id) {
    agent.problem = id.error().message;
    return;
  }
  agent.crowd_id = *id;
  agent.position = ground->point;
  if (agent.plan.target)
    SetOff(index, *agent.plan.target);
  else
    DrawTarget(index);
}

void DemoAgents::SetOff(std::size_t index, const Vec3& target) {
  DemoAgent& agent = agents_[index];
  navmesh::NavMeshQuery& path_query = query(agent.plan.profile);
  path_query.set_search_extents(Vec3(2.0f, 4.0f, 2.0f));
  agent.target = target;
  agent.planned_path.clear();
  if (const Result<navmesh::PathResult> path = path_query.FindPath(agent.position, target); path)
    agent.planned_path = path->points;
  if (Status sent = crowds_[static_cast<std::size_t>(agent.plan.profile)]->SetTarget(agent.crowd_id, target);
      !sent)
    agent.problem = sent.message();
}

void DemoAgents::DrawTarget(std::size_t index) {
  DemoAgent& agent = agents_[index];
  navmesh::NavMeshQuery& target_query = query(agent.plan.profile);
  target_query.set_search_extents(Vec3(2.0f, 4.0f, 2.0f));
  // Its own generator: how many draws another agent took does not move this one's target.
  std::mt19937 random(config_.seed * 1'000'003u + static_cast<unsigned>(index) * 7919u +
                      static_cast<unsigned>(agent.new_targets));
  const Result<Vec3> drawn = target_query.RandomPointAround(agent.position, config_.target_radius, random);
  if (!drawn) {
    agent.problem = drawn.error().message;
    return;
  }
  SetOff(index, *drawn);
}

void DemoAgents::RetargetCutOff() {
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    DemoAgent& agent = agents_[i];
    if (agent.crowd_id < 0 || agent.arrived_at >= 0.0f || agent.plan.target || !agent.problem.empty())
      continue;
    const navmesh::Crowd& crowd = *crowds_[static_cast<std::size_t>(agent.plan.profile)];
    // Waiting for a tile that is built means the target is not on the rebuilt navmesh; stuck means no way
    // leads there any more.
    const bool waiting_on_built =
        *crowd.state(agent.crowd_id) == navmesh::CrowdAgentState::kWaiting &&
        service_.IsPublished(service_.grid().TileAt(agent.target), agent.plan.profile);
    if (!waiting_on_built && !*crowd.stuck(agent.crowd_id)) continue;
    ++agent.new_targets;
    DrawTarget(i);
  }
}

Status DemoAgents::Update(float dt, float time) {
  if (frame_ % kRequestEveryFrames == kRequestEveryFrames - 1)
    if (Status requested = RequestSpawnTiles(); !requested) return requested;
  if (frame_ % kJoinCheckEveryFrames == 0)
    for (std::size_t i = 0; i < agents_.size(); ++i)
      if (!agents_[i].joined && GroundBuilt(agents_[i])) Join(i, time);
  ++frame_;
  for (const std::unique_ptr<navmesh::Crowd>& crowd : crowds_)
    if (crowd)
      if (Status moved = crowd->Update(dt); !moved) return moved;
  for (DemoAgent& agent : agents_) {
    if (agent.crowd_id < 0) continue;
    const navmesh::Crowd& crowd = *crowds_[static_cast<std::size_t>(agent.plan.profile)];
    const Vec3 now = *crowd.position(agent.crowd_id);
    agent.walked += (now - agent.position).norm();
    agent.position = now;
    if (agent.arrived_at < 0.0f && *crowd.state(agent.crowd_id) == navmesh::CrowdAgentState::kArrived)
      agent.arrived_at = time;
  }
  RetargetCutOff();
  return Status::Ok();
}

std::size_t DemoAgents::arrived() const {
  std::size_t count = 0;
  for (const DemoAgent& agent : agents_) count += agent.arrived_at >= 0.0f;
  return count;
}

const navmesh::Crowd* DemoAgents::crowd(int profile) const {
  if (profile < 0 || profile >= static_cast<int>(crowds_.size())) return nullptr;
  return crowds_[static_cast<std::size_t>(profile)].get();
}

Result<bool> DemoAgents::ReachesWithoutLinks(std::size_t index) const {
  if (index >= agents_.size()) return MakeError(ErrorCode::kInvalidArgument, "demo agents: no such agent");
  const DemoAgent& agent = agents_[index];
  if (agent.crowd_id < 0) return false;
  Result<std::unique_ptr<navmesh::NavMeshQuery>> query =
      navmesh::NavMeshQuery::Create(service_.navmesh(agent.plan.profile));
  if (!query) return query.error();
  (*query)->set_search_extents(Vec3(config_.snap_distance, 8.0f, config_.snap_distance));
  (*query)->set_links_allowed(false);
  const Result<navmesh::PathResult> path = (*query)->FindPath(agent.plan.start, agent.target);
  if (!path) return path.error();
  return path->reached_end;
}

}  // namespace strata::demo
