#include "tools/bench/OpenWorldBench.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "navmesh/Crowd.h"
#include "navmesh/NavMeshService.h"
#include "physics/body/BodyInterface.h"
#include "physics/body/BodyManager.h"
#include "physics/shapes/BoxShape.h"
#include "physics/world/PhysicsSystem.h"
#include "tools/bench/CrowdBench.h"
#include "tools/bench/JsonReport.h"
#include "tools/bench/ProfileCostBench.h"
#include "tools/bench/Progress.h"

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;
constexpr float kStep = 1.0f / 60.0f;
constexpr int kSquadSize = 8;

double Milliseconds(Clock::duration duration) {
  return std::chrono::duration<double, std::milli>(duration).count();
}

double ResidentMegabytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

/// A flat ground, static boxes of many sizes (rocks, walls, huts) and one crate in ten bodies resting on the
/// ground (small dynamic bodies: debris the navmesh leaves out; they fall asleep).
Status Populate(PhysicsSystem& world, const OpenWorldOptions& options, std::mt19937& random) {
  const float size = options.world_size;
  BodyCreationSettings ground;
  ground.shape = *BoxShape::Create(Vec3(0.5f * size, 0.5f, 0.5f * size));
  ground.position = Vec3(0.5f * size, -0.5f, 0.5f * size);
  ground.motion_type = MotionType::kStatic;
  ground.object_layer = layers::kNonMoving;
  if (Result<BodyID> added = world.bodies().CreateAndAddBody(ground); !added) return added.error();

  std::uniform_real_distribution<float> place(5.0f, size - 5.0f);
  std::uniform_real_distribution<float> side(0.3f, 2.0f);
  std::uniform_real_distribution<float> height(0.5f, 3.0f);
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f);
  const int crates = (options.bodies - 1) / 10;
  const int obstacles = options.bodies - 1 - crates;
  const ShapeRef crate = *BoxShape::Create(Vec3(0.3f, 0.3f, 0.3f));
  std::vector<BodyID> batch;
  const auto flush = [&](Activation activation) -> Status {
    Status added = world.bodies().AddBodies(batch, activation);
    batch.clear();
    return added;
  };
  for (int i = 0; i < obstacles + crates; ++i) {
    const bool is_crate = i >= obstacles;
    BodyCreationSettings body;
    if (is_crate) {
      body.shape = crate;
      body.position = Vec3(place(random), 0.3f, place(random));
      body.motion_type = MotionType::kDynamic;
      body.object_layer = layers::kMoving;
    } else {
      const Vec3 half(side(random), height(random), side(random));
      body.shape = *BoxShape::Create(half);
      body.position = Vec3(place(random), half.y(), place(random));
      body.motion_type = MotionType::kStatic;
      body.object_layer = layers::kNonMoving;
    }
    body.rotation = Quat(Eigen::AngleAxisf(angle(random), Vec3::UnitY()));
    Result<BodyID> id = world.bodies().CreateBody(body);
    if (!id) return id.error();
    batch.push_back(*id);
    if (batch.size() == 1024 || i + 1 == obstacles || i + 1 == obstacles + crates)
      if (Status added = flush(is_crate ? Activation::kActivate : Activation::kDontActivate); !added)
        return added;
  }
  world.broad_phase().Optimize();
  return Status::Ok();
}

struct Agent {
  Vec3 position;
  Vec3 heading;  ///< unit, in the x-z plane
  int id = -1;   ///< in the crowd
};

/// Squads of up to eight, each somewhere in the world heading its own way, its agents a few metres apart.
std::vector<Agent> MakeAgents(const OpenWorldOptions& options, std::mt19937& random) {
  std::uniform_real_distribution<float> place(50.0f, options.world_size - 50.0f);
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f);
  std::uniform_real_distribution<float> spread(-6.0f, 6.0f);
  std::vector<Agent> agents;
  Vec3 squad_position = Vec3::Zero(), squad_heading = Vec3::UnitX();
  for (int i = 0; i < options.agents; ++i) {
    if (i % kSquadSize == 0) {
      const float heading = angle(random);
      squad_position = Vec3(place(random), 0.0f, place(random));
      squad_heading = Vec3(std::cos(heading), 0.0f, std::sin(heading));
    }
    agents.push_back({squad_position + Vec3(spread(random), 0.0f, spread(random)), squad_heading});
  }
  return agents;
}

/// The agent's next waypoint, kWaypoint metres on along its heading; at the world's margin the heading turns
/// back (mirror bounce).
constexpr float kWaypoint = 150.0f;
Vec3 NextWaypoint(Agent& agent, const Vec3& from, float world_size) {
  Vec3 target = from + kWaypoint * agent.heading;
  for (const int axis : {0, 2}) {
    if (target[axis] >= 10.0f && target[axis] <= world_size - 10.0f) continue;
    agent.heading[axis] = -agent.heading[axis];
    target[axis] = std::clamp(from[axis] + kWaypoint * agent.heading[axis], 10.0f, world_size - 10.0f);
  }
  return target;
}

/// The tiles around every squad built, then each agent placed on the navmesh near its spot and sent off.
Status PlaceAgents(const OpenWorldOptions& options, navmesh::NavMeshService& service, navmesh::Crowd& crowd,
                   std::vector<Agent>& agents, std::mt19937& random) {
  for (const Agent& agent : agents)
    if (Status requested = service.RequestAround(agent.position, 10.0f); !requested) return requested;
  if (!service.WaitUntilIdle(std::chrono::seconds(120)))
    return MakeError(ErrorCode::kInvalidState, "the tiles around the agents did not build within 2 minutes");
  std::uniform_real_distribution<float> nudge(-3.0f, 3.0f);
  navmesh::CrowdAgentParams params;
  params.max_speed = options.agent_speed;
  params.max_acceleration = 4.0f * options.agent_speed;
  for (Agent& agent : agents) {
    for (int attempt = 0; attempt < 20 && agent.id < 0; ++attempt) {
      const Vec3 spot =
          agent.position + (attempt == 0 ? Vec3::Zero() : Vec3(nudge(random), 0.0f, nudge(random)));
      if (Result<int> id = crowd.AddAgent(spot, params); id) agent.id = *id;
    }
    if (agent.id < 0)
      return MakeError(ErrorCode::kInvalidState, "an agent could not be placed on the navmesh");
    if (Status sent =
            crowd.SetTarget(agent.id, NextWaypoint(agent, *crowd.position(agent.id), options.world_size));
        !sent)
      return sent;
  }
  return Status::Ok();
}

struct Snapshot {
  int step = 0;
  double resident_mb = 0.0;
  navmesh::NavMeshServiceStats stats;
};

// What the walk measured.
struct WalkFigures {
  int steps = 0;
  std::size_t checks = 0, on_ready = 0, most_held = 0, late_frames = 0, most_stuck = 0;
  double crowd_ms_total = 0.0, longest_crowd_ms = 0.0, step_ms_total = 0.0, longest_step_ms = 0.0;
  double walk_ms = 0.0, lock_wait_ms = 0.0;
  navmesh::CrowdStats crowd;
  std::vector<Snapshot> snapshots;
  double on_ready_share() const {
    return checks == 0 ? 0.0 : static_cast<double>(on_ready) / static_cast<double>(checks);
  }
  double on_mesh_share() const {
    return crowd.agent_updates == 0
               ? 0.0
               : 1.0 - static_cast<double>(crowd.off_mesh) / static_cast<double>(crowd.agent_updates);
  }
};

// One frame of the crowd: the update (timed), the agents' tiles checked, arrivals sent on to their next
// waypoint.
Status UpdateCrowd(const OpenWorldOptions& options, navmesh::NavMeshService& service, navmesh::Crowd& crowd,
                   std::vector<Agent>& agents, WalkFigures& figures) {
  const Clock::time_point start = Clock::now();
  if (Status updated = crowd.Update(kStep); !updated) return updated;
  const double crowd_ms = Milliseconds(Clock::now() - start);
  figures.crowd_ms_total += crowd_ms;
  figures.longest_crowd_ms = std::max(figures.longest_crowd_ms, crowd_ms);
  for (Agent& agent : agents) {
    const Vec3 at = *crowd.position(agent.id);
    ++figures.checks;
    figures.on_ready += service.GetTileState(service.grid().TileAt(at)) == navmesh::TileState::kReady;
    if (*crowd.state(agent.id) == navmesh::CrowdAgentState::kArrived)
      (void)crowd.SetTarget(agent.id, NextWaypoint(agent, at, options.world_size));
  }
  figures.most_stuck = std::max(figures.most_stuck, crowd.stats().stuck_agents);
  figures.most_held = std::max(figures.most_held, service.stats().tiles_holding_data);
  return Status::Ok();
}

// The agents walk in frames of 60 Hz wall time while the world steps; fails if a step does.
Status WalkAgents(const OpenWorldOptions& options, PhysicsSystem& world, navmesh::NavMeshService& service,
                  navmesh::Crowd& crowd, std::vector<Agent>& agents, Progress& progress,
                  WalkFigures& figures) {
  const int steps = figures.steps;
  figures.snapshots.push_back({0, ResidentMegabytes(), service.stats()});
  const std::uint64_t lock_wait_start = ThreadBodyLockWaitNanoseconds();
  const Clock::time_point walk_start = Clock::now();
  for (int step = 0; step < steps; ++step) {
    progress.Update(static_cast<std::size_t>(step), static_cast<std::size_t>(steps));
    const Clock::time_point step_start = Clock::now();
    if (Status stepped = world.Step(kStep); !stepped) return stepped;
    const double step_ms = Milliseconds(Clock::now() - step_start);
    figures.step_ms_total += step_ms;
    figures.longest_step_ms = std::max(figures.longest_step_ms, step_ms);
    if (Status walked = UpdateCrowd(options, service, crowd, agents, figures); !walked) return walked;
    // Frames at 60 Hz of wall time, as in a game: the service builds while the frame waits for its slot.
    const Clock::time_point frame_end = walk_start + std::chrono::duration_cast<Clock::duration>(
                                                         std::chrono::duration<double>(kStep * (step + 1)));
    if (Clock::now() > frame_end) ++figures.late_frames;
    std::this_thread::sleep_until(frame_end);
    if ((step + 1) % std::max(1, steps / 4) == 0 || step + 1 == steps)
      figures.snapshots.push_back({step + 1, ResidentMegabytes(), service.stats()});
  }
  figures.walk_ms = Milliseconds(Clock::now() - walk_start);
  figures.crowd = crowd.stats();
  progress.Hide();
  figures.lock_wait_ms = static_cast<double>(ThreadBodyLockWaitNanoseconds() - lock_wait_start) * 1e-6;
  return Status::Ok();
}

void PrintWalk(const OpenWorldOptions& options, const WalkFigures& figures,
               const navmesh::NavMeshServiceStats& stats) {
  std::printf(
      "walk: %.0f ms wall for %.0f s simulated (60 Hz frames, %zu late); step %.3f ms mean, %.3f ms max; "
      "step blocked on body locks %.3f ms in all; crowd update %.3f ms mean, %.3f ms max\n",
      figures.walk_ms, figures.steps * static_cast<double>(kStep), figures.late_frames,
      figures.step_ms_total / std::max(1, figures.steps), figures.longest_step_ms, figures.lock_wait_ms,
      figures.crowd_ms_total / std::max(1, figures.steps), figures.longest_crowd_ms);
  std::printf("tiles: %zu built, %zu evictions, %zu failures; at most %zu of the %d-tile budget held\n",
              stats.builds, stats.evictions, stats.failures, figures.most_held, options.tile_budget);
  std::printf(
      "crowd: agents on the navmesh %.3f%% of agent-frames, on a ready tile %.2f%%; %zu stuck at the end "
      "(at most %zu at once), %zu replans, %.1f agent-seconds waiting for tiles\n",
      100.0 * figures.on_mesh_share(), 100.0 * figures.on_ready_share(), figures.crowd.stuck_agents,
      figures.most_stuck, figures.crowd.replans, figures.crowd.waiting_seconds);
  std::printf("memory over the walk (resident MB / tiles built / held):");
  for (const Snapshot& snapshot : figures.snapshots)
    std::printf("  step %d: %.1f / %zu / %zu", snapshot.step, snapshot.resident_mb, snapshot.stats.builds,
                snapshot.stats.tiles_holding_data);
  std::printf("\n");
}

// Person, machine and critter over a block at the centre, from one gather and from a service each.
Result<std::optional<ProfileCostFigures>> MeasureProfiles(const OpenWorldOptions& options,
                                                          const PhysicsSystem& world) {
  if (options.profile_cost_tiles <= 0) return std::optional<ProfileCostFigures>();
  const std::vector<navmesh::AgentProfile> profiles = {
      navmesh::AgentProfile::Person(), navmesh::AgentProfile::Machine(), navmesh::AgentProfile::Critter()};
  const Vec3 center(0.5f * options.world_size, 0.0f, 0.5f * options.world_size);
  Result<ProfileCostFigures> figures = MeasureProfileCost(
      world, options.settings, profiles, center, options.profile_cost_tiles, options.profile_cost_runs);
  if (!figures) return figures.error();
  std::printf(
      "profiles: person, machine and critter on %d tiles: %.1f ms from one gather, %.1f ms with a service "
      "each (%.2fx); CPU time of all the services' threads %.1f ms against %.1f ms (%.2fx); medians of %d "
      "alternated runs, one worker thread a service; same tile bytes both ways: %s; %zu of %d profile tiles "
      "took an earlier profile's polygons (the same walkable cells)\n",
      figures->tiles, figures->shared_ms, figures->separate_ms, figures->ratio(), figures->shared_cpu_ms,
      figures->separate_cpu_ms, figures->cpu_ratio(), options.profile_cost_runs,
      figures->same_tiles ? "yes" : "NO", figures->polygons_taken, figures->profiles * figures->tiles);
  return std::optional<ProfileCostFigures>(*figures);
}

// Crowd updates of 64, 256 and 1,024 person agents on a block at the centre, on this thread.
Result<std::vector<CrowdUpdateFigures>> MeasureCrowds(const OpenWorldOptions& options,
                                                      const PhysicsSystem& world) {
  if (options.crowd_agents.empty()) return std::vector<CrowdUpdateFigures>();
  const Vec3 center(0.5f * options.world_size, 0.0f, 0.5f * options.world_size);
  Result<std::vector<CrowdUpdateFigures>> figures =
      MeasureCrowdUpdates(world, options.settings, navmesh::AgentProfile::Person(), center, 8,
                          options.crowd_agents, options.crowd_frames, options.seed);
  if (!figures) return figures.error();
  for (const CrowdUpdateFigures& run : *figures)
    std::printf(
        "crowd: %4d person agents on 8 x 8 tiles: update %.3f ms mean, %.3f ms max over %d frames (one "
        "thread); "
        "%zu arrivals, %zu agent-updates off the navmesh\n",
        run.agents, run.mean_ms, run.max_ms, run.frames, run.arrived, run.off_mesh);
  return figures;
}

nlohmann::json WalkReport(const OpenWorldOptions& options, const PhysicsSystem& world,
                          const WalkFigures& figures, const navmesh::NavMeshServiceStats& stats) {
  nlohmann::json memory = nlohmann::json::array();
  for (const Snapshot& snapshot : figures.snapshots)
    memory.push_back({{"step", snapshot.step},
                      {"resident_mb", snapshot.resident_mb},
                      {"tiles_built", snapshot.stats.builds},
                      {"tiles_held", snapshot.stats.tiles_holding_data}});
  return {{"world_size_m", options.world_size},
          {"bodies", world.body_count_in_world()},
          {"agents", options.agents},
          {"walk_m", options.walk_distance},
          {"steps", figures.steps},
          {"tile_budget", options.tile_budget},
          {"physics_threads", options.physics_threads},
          {"navmesh_threads", options.navmesh_threads},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"walk_wall_ms", figures.walk_ms},
          {"late_frames", figures.late_frames},
          {"step_mean_ms", figures.step_ms_total / std::max(1, figures.steps)},
          {"step_max_ms", figures.longest_step_ms},
          {"step_body_lock_wait_ms", figures.lock_wait_ms},
          {"crowd_update_mean_ms", figures.crowd_ms_total / std::max(1, figures.steps)},
          {"crowd_update_max_ms", figures.longest_crowd_ms},
          {"on_mesh_share", figures.on_mesh_share()},
          {"stuck_agents", figures.crowd.stuck_agents},
          {"most_stuck_at_once", figures.most_stuck},
          {"replans", figures.crowd.replans},
          {"waiting_agent_seconds", figures.crowd.waiting_seconds},
          {"tiles_built", stats.builds},
          {"evictions", stats.evictions},
          {"failures", stats.failures},
          {"most_tiles_held", figures.most_held},
          {"on_ready_tile_share", figures.on_ready_share()},
          {"memory", memory}};
}

int Fail(const std::string& message) {
  std::fprintf(stderr, "strata bench-navmesh: %s\n", message.c_str());
  return 2;
}

}  // namespace

int RunOpenWorldBench(const OpenWorldOptions& options) {
  if (Status valid = options.settings.Validate(); !valid) return Fail(valid.message());
  if (!options.json.empty() && !JsonDestinationExists(options.json))
    return Fail("--json " + options.json + ": no such directory");
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(options.bodies) + 16;
  config.thread_count = options.physics_threads;
  auto created = PhysicsSystem::Create(config);
  if (!created) return Fail(created.error().message);
  PhysicsSystem& world = **created;
  std::mt19937 random(options.seed);
  const Clock::time_point populate_start = Clock::now();
  if (Status populated = Populate(world, options, random); !populated) return Fail(populated.message());
  const double populate_ms = Milliseconds(Clock::now() - populate_start);
  Result<std::optional<ProfileCostFigures>> profile_cost = MeasureProfiles(options, world);
  if (!profile_cost) return Fail(profile_cost.error().message);
  Result<std::vector<CrowdUpdateFigures>> crowds = MeasureCrowds(options, world);
  if (!crowds) return Fail(crowds.error().message);

  navmesh::NavMeshServiceConfig service_config;
  service_config.settings = options.settings;
  service_config.profiles = {navmesh::AgentProfile::Person()};
  service_config.worker_threads = options.navmesh_threads;
  service_config.max_tiles = options.tile_budget;
  auto service = navmesh::NavMeshService::Create(world, service_config);
  if (!service) return Fail(service.error().message);
  navmesh::CrowdConfig crowd_config;
  crowd_config.max_agents = options.agents;
  crowd_config.arrive_distance = 2.0f;
  auto crowd = navmesh::Crowd::Create(**service, 0, crowd_config);
  if (!crowd) return Fail(crowd.error().message);
  std::vector<Agent> agents = MakeAgents(options, random);
  if (Status placed = PlaceAgents(options, **service, **crowd, agents, random); !placed)
    return Fail(placed.message());
  WalkFigures figures;
  figures.steps = static_cast<int>(std::ceil(options.walk_distance / (options.agent_speed * kStep)));
  std::printf(
      "open world: %.0f m x %.0f m, %zu bodies (populated in %.0f ms), %d agents in squads of %d walking "
      "%.0f m at up to %.1f m/s (%d steps) with a crowd, tile budget %d; %d physics thread(s), %d navmesh "
      "thread(s)\n",
      options.world_size, options.world_size, world.body_count_in_world(), populate_ms, options.agents,
      kSquadSize, options.walk_distance, options.agent_speed, figures.steps, options.tile_budget,
      options.physics_threads, options.navmesh_threads);
  Progress progress("strata bench-navmesh --open-world", "steps");
  if (Status walked = WalkAgents(options, world, **service, **crowd, agents, progress, figures); !walked)
    return Fail(walked.message());
  (void)(*service)->WaitUntilIdle(std::chrono::seconds(60));
  const navmesh::NavMeshServiceStats stats = (*service)->stats();
  figures.most_held = std::max(figures.most_held, stats.tiles_holding_data);
  PrintWalk(options, figures, stats);
  if (!options.json.empty()) {
    nlohmann::json report = WalkReport(options, world, figures, stats);
    if (*profile_cost) report["profile_cost"] = (*profile_cost)->ToJson();
    if (!crowds->empty()) report["crowd_updates"] = ToJson(*crowds);
    if (const Status written = WriteJsonReport(options.json, report); !written)
      return Fail(written.message());
  }
  std::fflush(stdout);
  progress.Finish(std::to_string(figures.steps) + " steps, " + std::to_string(stats.builds) +
                  " tiles built, " + std::to_string(stats.evictions) + " evicted, " +
                  std::to_string(stats.failures) + " failures");
  if (stats.failures > 0) {
    std::fprintf(stderr, "strata bench-navmesh: %zu tile builds failed: %s\n", stats.failures,
                 (*service)->last_error().c_str());
    return 1;
  }
  return 0;
}

}  // namespace strata::bench
