// `strata demo [LEVEL]`: the main job. Imports a level (the bundled courtyard by default), fills it with
// falling crates and rolling boulders, spawns agents of two kinds (people and machines, each with its own
// navmesh) that request navmesh tiles around themselves and walk to their targets through their crowd, and a
// player character that walks a route (the courtyard's: up the stairs and over the bridge), and steps the
// world while the tiles build in the background. Prints per-tile build figures, each agent's walk, the
// player's walk and the longest foreground stall, and writes the navmesh as OBJ, a top-down PNG, and the
// level, navmesh (coloured by island) and paths as one glTF binary.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <thread>
#include <variant>

#include "assets/import/GltfExporter.h"
#include "navmesh/LevelBake.h"
#include "navmesh/NavMeshQuery.h"
#include "navmesh/NavMeshService.h"
#include "navmesh/Validation.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/world/PhysicsSystem.h"
#include "physics/world/WorldQuery.h"
#include "tools/bench/Progress.h"
#include "tools/cli/Commands.h"
#include "tools/cli/NavMeshOptions.h"
#include "tools/cli/Validators.h"
#include "tools/demo/DemoAgents.h"
#include "tools/demo/ScriptedWalk.h"
#include "tools/demo/TopDownImage.h"
#include "tools/view/Recording.h"
#include "tools/view/ViewerFolder.h"

namespace strata::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct DemoOptions {
  std::string level = DefaultLevelPath();
  LevelLoadOptions level_options;
  navmesh::NavMeshSettings settings;
  int steps = 1500;
  int crates = 300;
  int boulders = 6;
  int agents = 8;
  float request_radius = 16.0f;
  float target_radius = 24.0f;
  std::vector<std::string> profiles = {"person", "machine"};
  bool drop_links = true;
  int physics_threads = 1;
  int navmesh_threads = 1;
  float time_scale = 1.0f;  ///< simulated seconds per wall-clock second; 0: as fast as it goes
  std::string out_dir = "build/demo";
  unsigned seed = 1;
  std::string record;    ///< a recording for `strata view` (empty: none)
  int record_every = 6;  ///< steps between recorded frames
  bool player = true;
  std::vector<float> player_route;  ///< x, z pairs; empty: the courtyard's tour on it, else random floors
  float player_speed = 5.0f;        ///< m/s
};

// Option ranges: beyond them a run would take hours or the world's body table would be enormous.
constexpr int kMaxSteps = 10'000'000;
// Spawned bodies: the world's slots, broad phase and step budgets grow with them; 50,000 crates step in
// about 2 GB.
constexpr int kMaxSpawned = 50'000;
constexpr int kMaxAgents = 10'000;

double Milliseconds(Clock::duration duration) {
  return std::chrono::duration<double, std::milli>(duration).count();
}

/// The highest surface below (x, z) within the level, found by a ray cast from above it.
std::optional<Vec3> GroundAt(const PhysicsSystem& world, const AABB& level, float x, float z) {
  const Vec3 origin(x, level.max.y() + 1.0f, z);
  const auto hit = world.query().CastRay(origin, Vec3(0.0f, level.min.y() - level.max.y() - 2.0f, 0.0f),
                                         QueryFilter::OnlyLayer(layers::kNonMoving));
  if (!hit.ok() || !hit->has_value()) return std::nullopt;
  return (*hit)->position;
}

/// Random points on the level's walkable-looking surfaces (facing up within 45 degrees), by area: agents and
/// boulders land on the level however little of its bounds it covers (a floor and one far triangle).
class FloorSampler {
 public:
  FloorSampler(PhysicsSystem& world, const LoadedLevel& level) {
    std::vector<Triangle> triangles;
    for (const BodyID id : level.bodies) {
      const Result<ShapeRef> shape = world.bodies().GetShape(id);
      const Result<Vec3> position = world.bodies().GetPosition(id);
      const Result<Quat> rotation = world.bodies().GetRotation(id);
      if (!shape || !position || !rotation) continue;
      triangles.clear();
      (*shape)->GetTrianglesInBox(level.bounds.Expanded(1.0f), Pose{*position, *rotation}, triangles);
      for (const Triangle& triangle : triangles) Add(triangle);
    }
  }

  bool empty() const { return floors_.empty(); }
  /// The x-z of a random point on the floors (call only when not empty).
  Vec3 Sample(std::mt19937& random) const {
    std::uniform_real_distribution<double> area(0.0, cumulative_area_.back());
    const double pick = area(random);
    const auto found = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), pick);
    const Triangle& floor = floors_[std::min<std::size_t>(
        static_cast<std::size_t>(found - cumulative_area_.begin()), floors_.size() - 1)];
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    float u = unit(random), v = unit(random);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    return floor.vertices[0] + u * (floor.vertices[1] - floor.vertices[0]) +
           v * (floor.vertices[2] - floor.vertices[0]);
  }

 private:
  void Add(const Triangle& triangle) {
    const Vec3 normal =
        (triangle.vertices[1] - triangle.vertices[0]).cross(triangle.vertices[2] - triangle.vertices[0]);
    const float twice_area = normal.norm();
    if (!(twice_area > 1e-6f) || normal.y() < 0.7071f * twice_area) return;
    floors_.push_back(triangle);
    cumulative_area_.push_back((cumulative_area_.empty() ? 0.0 : cumulative_area_.back()) + 0.5 * twice_area);
  }

  std::vector<Triangle> floors_;
  std::vector<double> cumulative_area_;
};

/// The top surface at a random floor point, if a ray from above finds one there.
std::optional<Vec3> RandomGround(const PhysicsSystem& world, const AABB& level, const FloorSampler& floors,
                                 std::mt19937& random) {
  if (floors.empty()) return std::nullopt;
  const Vec3 point = floors.Sample(random);
  return GroundAt(world, level, point.x(), point.z());
}

Status SpawnDynamicBodies(PhysicsSystem& world, const AABB& level, const FloorSampler& floors,
                          const DemoOptions& options, std::mt19937& random) {
  std::uniform_real_distribution<float> x(level.min.x() + 2.0f, level.max.x() - 2.0f);
  std::uniform_real_distribution<float> z(level.min.z() + 2.0f, level.max.z() - 2.0f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const ShapeRef crate = *BoxShape::Create(Vec3(0.4f, 0.4f, 0.4f));
  for (int i = 0; i < options.crates; ++i) {
    BodyCreationSettings settings;
    settings.shape = crate;
    settings.position = Vec3(x(random), level.max.y() + 2.0f + 10.0f * unit(random), z(random));
    settings.rotation =
        Quat(Eigen::AngleAxisf(6.0f * unit(random), Vec3(unit(random), 1.0f, unit(random)).normalized()));
    if (Result<BodyID> added = world.bodies().CreateAndAddBody(settings); !added) return added.error();
  }
  const ShapeRef boulder = *SphereShape::Create(1.0f);  // 2 m across: large enough to count for the navmesh
  for (int i = 0; i < options.boulders; ++i) {
    const auto ground = RandomGround(world, level, floors, random);
    if (!ground) continue;
    BodyCreationSettings settings;
    settings.shape = boulder;
    settings.position = *ground + Vec3(0.0f, 1.05f, 0.0f);
    const float angle = 6.2832f * unit(random);
    settings.linear_velocity = Vec3(4.0f * std::cos(angle), 0.0f, 4.0f * std::sin(angle));
    settings.friction = 0.8f;
    if (Result<BodyID> added = world.bodies().CreateAndAddBody(settings); !added) return added.error();
  }
  return Status::Ok();
}

/// `count` agents at random floor points, and on the bundled courtyard the two of the first profile that
/// start on the crate stack and need a drop link. Every fourth agent is of another profile than the first
/// (taking them in turn): large machines are fewer than people, and a courtyard full of them jams.
std::vector<demo::DemoAgentPlan> PlanAgents(const PhysicsSystem& world, const DemoOptions& options,
                                            const AABB& level, const FloorSampler& floors, int profile_count,
                                            std::mt19937& random) {
  std::vector<demo::DemoAgentPlan> plans;
  for (int attempt = 0; attempt < 50 * options.agents && static_cast<int>(plans.size()) < options.agents;
       ++attempt) {
    const auto start = RandomGround(world, level, floors, random);
    if (!start) continue;
    const int index = static_cast<int>(plans.size());
    const int profile = profile_count > 1 && index % 4 == 3 ? 1 + (index / 4) % (profile_count - 1) : 0;
    plans.push_back({*start, profile, std::nullopt, false});
  }
  if (std::filesystem::path(options.level).stem() == "courtyard")
    for (const demo::DemoAgentPlan& plan : demo::CourtyardDropDownAgents(0)) plans.push_back(plan);
  return plans;
}

/// The player's route: the one asked for, the tour of the bundled courtyard, or four random floor points.
std::vector<Vec3> PlayerRoute(const DemoOptions& options, const FloorSampler& floors, std::mt19937& random) {
  std::vector<Vec3> route;
  for (std::size_t i = 0; i + 1 < options.player_route.size(); i += 2)
    route.emplace_back(options.player_route[i], 0.0f, options.player_route[i + 1]);
  if (!route.empty()) return route;
  if (std::filesystem::path(options.level).stem() == "courtyard") return demo::CourtyardRoute();
  for (int i = 0; i < 4 && !floors.empty(); ++i) route.push_back(floors.Sample(random));
  return route;
}

/// The player, or none (null) when the demo runs without one or a made-up route found no floors to walk;
/// fails (saying why) when a route asked for cannot be walked.
Result<std::unique_ptr<demo::ScriptedWalk>> MakePlayer(PhysicsSystem& world, navmesh::NavMeshService& service,
                                                       const DemoOptions& options, const AABB& level,
                                                       const FloorSampler& floors, std::mt19937& random) {
  if (!options.player) return std::unique_ptr<demo::ScriptedWalk>();
  auto walk = demo::ScriptedWalk::Create(world, service, PlayerRoute(options, floors, random),
                                         level.max.y() + 1.0f, level.min.y() - 1.0f, options.player_speed);
  if (walk) return walk;
  std::cerr << "strata demo: " << (options.player_route.empty() ? "warning: no player: " : "")
            << "the player's route: " << walk.error().message << "\n";
  if (!options.player_route.empty()) return walk.error();
  return std::unique_ptr<demo::ScriptedWalk>();
}

void PrintWalk(const demo::ScriptedWalk& walk) {
  const demo::WalkReport report = walk.report();
  const Vec3& feet = walk.character().feet();
  std::printf("\nplayer: reached %zu of %zu waypoints", report.reached, report.waypoints);
  if (report.finished_at >= 0.0f) std::printf(" (the last at %.1f s)", report.finished_at);
  std::printf(
      ", ended at (%.1f, %.1f, %.1f) after %.1f m, up to %.1f m above its start, on walkable ground after "
      "%.0f%% "
      "of its updates, walked around what blocked it %d times; Character::Update %.1f us mean, %.1f us max\n",
      feet.x(), feet.y(), feet.z(), report.distance, report.highest, 100.0f * report.grounded,
      report.sidesteps, report.mean_update_us, report.max_update_us);
}

void PrintTileTable(const navmesh::NavMeshService& service) {
  std::map<navmesh::TileCoord, std::vector<navmesh::TileBuildRecord>> by_tile;
  for (const auto& record : service.build_log()) by_tile[record.coord].push_back(record);
  std::printf("\n%-9s %6s %6s %9s %8s %10s %10s %10s %12s\n", "tile", "builds", "bodies", "triangles",
              "polygons", "gather ms", "recast ms", "publish ms", "request->ready ms");
  for (const auto& [coord, records] : by_tile) {
    const auto& last = records.back();
    char name[32];
    std::snprintf(name, sizeof(name), "(%d,%d)", coord.x, coord.z);
    std::printf("%-9s %6zu %6zu %9zu %8d %10.2f %10.2f %10.3f %12.1f\n", name, records.size(), last.bodies,
                last.triangles, last.polygons, last.gather_ms, last.recast_ms, last.publish_ms,
                records.front().request_to_ready_ms);
  }
}

/// The level's triangles (every level body's, world space).
std::vector<Triangle> LevelTriangles(PhysicsSystem& world, const LoadedLevel& level) {
  std::vector<Triangle> triangles;
  for (const BodyID id : level.bodies) {
    const auto shape = world.bodies().GetShape(id);
    if (shape.ok()) (*shape)->GetTrianglesInBox(level.bounds.Expanded(1.0f), Pose{}, triangles);
  }
  return triangles;
}

Status DrawPicture(PhysicsSystem& world, const LoadedLevel& level, const navmesh::NavMeshService& service,
                   const std::vector<demo::DemoAgent>& agents, const std::vector<Vec3>& player_trail,
                   const std::filesystem::path& path) {
  demo::TopDownImage image(level.bounds.Expanded(Vec3(2.0f, 0.0f, 2.0f)), 8.0f);
  // Level: grey by height, lower surfaces first.
  struct Face {
    Triangle triangle;
    float top;
  };
  std::vector<Face> faces;
  for (const Triangle& t : LevelTriangles(world, level))
    faces.push_back({t, std::max({t.vertices[0].y(), t.vertices[1].y(), t.vertices[2].y()})});
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.top < b.top; });
  const float low = level.bounds.min.y(), range = std::max(0.1f, level.bounds.Size().y());
  for (const Face& face : faces) {
    const auto grey = static_cast<std::uint8_t>(70.0f + 150.0f * (face.top - low) / range);
    image.FillTriangle(face.triangle.vertices[0], face.triangle.vertices[1], face.triangle.vertices[2],
                       {grey, grey, grey});
  }
  // Navmesh: translucent blue detail triangles.
  service.navmesh().Read([&](const dtNavMesh& mesh) {
    for (int t = 0; t < mesh.getMaxTiles(); ++t) {
      const dtMeshTile* tile = mesh.getTile(t);
      if (!tile || !tile->header) continue;
      for (int p = 0; p < tile->header->polyCount; ++p) {
        const dtPoly& poly = tile->polys[p];
        for (int i = 2; i < poly.vertCount; ++i) {
          const auto vertex = [&](int k) {
            const float* v = &tile->verts[poly.verts[k] * 3];
            return service.navmesh().ToWorld(Vec3(v[0], v[1], v[2]));
          };
          image.FillTriangle(vertex(0), vertex(i - 1), vertex(i), {40, 110, 230}, 0.45f);
        }
      }
    }
    return 0;
  });
  // Tile borders of every tile the service knows.
  const navmesh::TileGrid& grid = service.grid();
  for (const navmesh::TileCoord tile : grid.TilesInBox(level.bounds)) {
    if (service.GetTileState(tile) == navmesh::TileState::kMissing) continue;
    const AABB b = grid.Bounds(tile);
    const Vec3 c00(b.min.x(), 0, b.min.z()), c10(b.max.x(), 0, b.min.z()), c11(b.max.x(), 0, b.max.z()),
        c01(b.min.x(), 0, b.max.z());
    for (const auto& [a, c] : {std::pair{c00, c10}, {c10, c11}, {c11, c01}, {c01, c00}})
      image.DrawLine(a, c, {20, 60, 20});
  }
  for (const BodyID id : world.BodiesInWorld()) {
    const auto motion = world.bodies().GetMotionType(id);
    if (motion.ok() && *motion == MotionType::kDynamic)
      image.DrawDot(*world.bodies().GetPosition(id), 2, {150, 90, 30});
  }
  for (const demo::DemoAgent& agent : agents) {
    for (std::size_t k = 1; k < agent.planned_path.size(); ++k)
      image.DrawLine(agent.planned_path[k - 1], agent.planned_path[k], {220, 30, 30});
    image.DrawDot(agent.plan.start, 4, {20, 170, 40});
    if (agent.crowd_id >= 0) image.DrawDot(agent.target, 3, {200, 30, 200});
  }
  for (std::size_t k = 1; k < player_trail.size(); ++k)
    image.DrawLine(player_trail[k - 1], player_trail[k], {40, 210, 230});
  return image.SavePng(path);
}

/// The level, the navmesh by island and the agents' paths, as the viewer's scene.glb shows them.
Status WriteGltf(PhysicsSystem& world, const LoadedLevel& level, const navmesh::NavMesh& navmesh,
                 const std::vector<demo::DemoAgent>& agents, const std::filesystem::path& path) {
  view::SceneGeometry geometry;
  for (const Triangle& t : LevelTriangles(world, level))
    geometry.level.insert(geometry.level.end(), std::begin(t.vertices), std::end(t.vertices));
  navmesh::NavMeshTriangles surface = navmesh::TrianglesByIsland(navmesh);
  geometry.navmesh = std::move(surface.vertices);
  geometry.island = std::move(surface.island);
  for (const demo::DemoAgent& agent : agents)
    if (agent.plan.profile == 0) geometry.paths.push_back(agent.planned_path);
  return ExportGltf(view::SceneLayers(geometry), path);
}

// A demo that could not run: what to print and the exit code (2: bad options or input, 1: the run failed).
struct DemoFailure {
  int exit_code;
  std::string message;
};

// Everything the game loop runs on, built before it starts.
struct DemoWorld {
  std::unique_ptr<PhysicsSystem> world;
  LoadedLevel level;
  std::unique_ptr<navmesh::NavMeshService> service;
  std::unique_ptr<demo::DemoAgents> walkers;
  std::unique_ptr<demo::ScriptedWalk> player;  // null with --no-player
  std::optional<view::Recorder> recorder;      // with --record
};

// What the foreground saw while the navmesh built in the background.
struct LoopFigures {
  double longest_frame_ms = 0.0;
  double longest_step_ms = 0.0;
  double step_ms_total = 0.0;
  int steps_with_jobs = 0;
  double agents_ms_total = 0.0;  ///< DemoAgents::Update: joining, drawing targets, the crowds
  double longest_agents_ms = 0.0;
};

std::optional<DemoFailure> CheckOptions(const DemoOptions& options,
                                        const navmesh::NavMeshServiceConfig& config) {
  if (Status status = config.Validate(); !status.ok()) return DemoFailure{2, status.message()};
  if (options.player_route.size() % 2 != 0)
    return DemoFailure{2, "--player-route takes x,z pairs (got " +
                              std::to_string(options.player_route.size()) + " numbers)"};
  // Before the run, not after it: a minute of simulation must not end in "cannot write".
  std::error_code error;
  std::filesystem::create_directories(options.out_dir, error);
  if (error || !std::filesystem::is_directory(options.out_dir, error))
    return DemoFailure{2, "--out-dir " + options.out_dir + ": cannot create the directory" +
                              (error ? " (" + error.message() + ")" : std::string())};
  if (options.record.empty()) return std::nullopt;
  const std::filesystem::path record_folder = std::filesystem::path(options.record).parent_path();
  if (!record_folder.empty() && !std::filesystem::is_directory(record_folder, error))
    return DemoFailure{2, "--record " + options.record + ": no such directory"};
  return std::nullopt;
}

std::optional<DemoFailure> StartRecording(const DemoOptions& options, DemoWorld& demo) {
  if (options.record.empty()) return std::nullopt;
  demo.recorder.emplace(*demo.world, "demo",
                        "strata demo: " + std::filesystem::path(options.level).filename().string());
  demo.recorder->TrackTiles(*demo.service, demo.level.bounds);
  if (demo.player) demo.recorder->TrackCharacter(demo.player->character(), "player", demo.player->route());
  const demo::DemoAgents& walkers = *demo.walkers;
  demo.recorder->TrackAgents(walkers.agents().size(), [&walkers] {
    std::vector<Vec3> positions;
    for (const demo::DemoAgent& agent : walkers.agents()) positions.push_back(agent.position);
    return positions;
  });
  const auto frames = static_cast<std::uint64_t>(options.steps / options.record_every) + 2;
  if (Status fits = demo.recorder->CheckFrameBudget(frames); !fits)
    return DemoFailure{2, "--record: " + fits.message()};
  demo.recorder->Capture(0, 0.0f);
  return std::nullopt;
}

// The world, the level, the bodies, the agents, the navmesh service, the player and the recorder.
std::variant<DemoWorld, DemoFailure> SetUpDemo(const DemoOptions& options,
                                               const navmesh::NavMeshServiceConfig& config) {
  DemoWorld demo;
  PhysicsSystemConfig world_config;
  // Room for every crate and boulder asked for besides the level's chunks: none is dropped silently.
  world_config.max_bodies = static_cast<std::uint32_t>(16384 + options.crates + options.boulders);
  world_config.thread_count = options.physics_threads;
  auto created = PhysicsSystem::Create(world_config);
  if (!created) return DemoFailure{2, created.error().message};
  demo.world = std::move(*created);
  const Clock::time_point load_start = Clock::now();
  Result<LoadedLevel> level = LoadLevel(*demo.world, options.level, options.level_options);
  if (!level) return DemoFailure{2, level.error().message};
  demo.level = std::move(*level);
  for (const std::string& warning : demo.level.warnings)
    std::cerr << "strata demo: warning: " << warning << "\n";
  std::printf("level %s: %zu triangles in %zu chunks, loaded in %.1f ms\n", options.level.c_str(),
              demo.level.triangles, demo.level.chunks, Milliseconds(Clock::now() - load_start));
  std::mt19937 random(options.seed);
  const FloorSampler floors(*demo.world, demo.level);
  if (Status spawned = SpawnDynamicBodies(*demo.world, demo.level.bounds, floors, options, random); !spawned)
    return DemoFailure{2, "cannot add the crates and boulders: " + spawned.message()};
  std::vector<demo::DemoAgentPlan> plans = PlanAgents(*demo.world, options, demo.level.bounds, floors,
                                                      static_cast<int>(config.profiles.size()), random);
  const Result<navmesh::NavMeshServiceConfig> level_config =
      navmesh::ConfigForLevel(config, demo.level.bounds);
  if (!level_config) return DemoFailure{2, options.level + ": " + level_config.error().message};
  auto service = navmesh::NavMeshService::Create(*demo.world, *level_config);
  if (!service) return DemoFailure{2, service.error().message};
  demo.service = std::move(*service);
  demo::DemoAgentsConfig agents_config;
  agents_config.request_radius = options.request_radius;
  agents_config.target_radius = options.target_radius;
  agents_config.snap_distance = std::max(options.request_radius, 1.0f);  // onto any ground it waited for
  agents_config.seed = options.seed;
  auto walkers = demo::DemoAgents::Create(*demo.service, std::move(plans), agents_config);
  if (!walkers) return DemoFailure{2, walkers.error().message};
  demo.walkers = std::move(*walkers);
  auto player = MakePlayer(*demo.world, *demo.service, options, demo.level.bounds, floors, random);
  if (!player) return DemoFailure{2, std::string()};  // MakePlayer said why
  demo.player = std::move(*player);
  if (auto failed = StartRecording(options, demo)) return *failed;
  return demo;
}

// The game loop at 60 Hz: the world steps, the player and the agents walk (the agents' crowds ask for the
// tiles around and ahead of them).
std::variant<LoopFigures, DemoFailure> RunGameLoop(const DemoOptions& options, DemoWorld& demo) {
  LoopFigures figures;
  bench::Progress progress("strata demo", "steps");
  // A game's frames come at their pace, and the background builds in the time between; a loop that ran
  // ahead would see tiles arrive later in simulated time than any game would.
  const Clock::time_point loop_start = Clock::now();
  const auto frame_due = [&](int step) {
    const double seconds = static_cast<double>(step) / (60.0 * static_cast<double>(options.time_scale));
    return loop_start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  };
  for (int step = 0; step < options.steps; ++step) {
    if (options.time_scale > 0.0f) std::this_thread::sleep_until(frame_due(step));
    progress.Update(static_cast<std::size_t>(step), static_cast<std::size_t>(options.steps));
    const Clock::time_point frame_start = Clock::now();
    const navmesh::NavMeshServiceStats before = demo.service->stats();
    const Clock::time_point step_start = Clock::now();
    if (Status status = demo.world->Step(1.0f / 60.0f); !status.ok()) return DemoFailure{1, status.message()};
    const double step_ms = Milliseconds(Clock::now() - step_start);
    figures.step_ms_total += step_ms;
    if (demo.player) {
      if (Status walked = demo.player->Update(1.0f / 60.0f, static_cast<float>(step + 1) / 60.0f); !walked)
        return DemoFailure{1, "the player: " + walked.message()};
    }
    const Clock::time_point agents_start = Clock::now();
    if (Status walked = demo.walkers->Update(1.0f / 60.0f, static_cast<float>(step + 1) / 60.0f); !walked)
      return DemoFailure{1, "the agents: " + walked.message()};
    const double agents_ms = Milliseconds(Clock::now() - agents_start);
    figures.agents_ms_total += agents_ms;
    figures.longest_agents_ms = std::max(figures.longest_agents_ms, agents_ms);
    figures.longest_step_ms = std::max(figures.longest_step_ms, step_ms);
    figures.steps_with_jobs += before.building > 0 || before.queued > 0;
    figures.longest_frame_ms = std::max(figures.longest_frame_ms, Milliseconds(Clock::now() - frame_start));
    if (demo.recorder && ((step + 1) % options.record_every == 0 || step + 1 == options.steps))
      demo.recorder->Capture(step + 1, static_cast<float>(step + 1) / 60.0f);
  }
  const bool idle = demo.service->WaitUntilIdle(std::chrono::seconds(60));
  const navmesh::NavMeshServiceStats stats = demo.service->stats();
  progress.Finish(std::to_string(options.steps) + " steps, " + std::to_string(stats.builds) +
                  " tile builds, " + std::to_string(stats.failures) + " failures");
  PrintTileTable(*demo.service);
  std::printf("\n%zu builds (%zu rebuilds of stale tiles), %zu failures; %zu tiles ready%s\n", stats.builds,
              stats.rebuilds, stats.failures, stats.ready, idle ? "" : " (service still busy after 60 s)");
  return figures;
}

std::string PointText(const Vec3& point) {
  char text[64];
  std::snprintf(text, sizeof(text), "(%.1f, %.1f, %.1f)", point.x(), point.y(), point.z());
  return text;
}

// What became of an agent beyond its figures: why it never set off, or for one placed to need a drop link,
// whether a walker that never drops could have got there.
std::string AgentNote(const demo::DemoAgents& walkers, std::size_t index) {
  const demo::DemoAgent& agent = walkers.agents()[index];
  if (!agent.problem.empty()) return agent.problem;
  if (!agent.joined) return "its ground was not built in time";
  if (!agent.plan.drop_down)
    return agent.new_targets == 0 ? ""
                                  : "drew " + std::to_string(agent.new_targets) +
                                        " new target(s): the world cut its way or its target off";
  const Result<bool> without = walkers.ReachesWithoutLinks(index);
  if (!without) return "drop-down agent: " + without.error().message;
  return *without ? "drop-down agent, but a way without links exists too"
                  : "drop-down agent: no way without a drop link";
}

// Each agent's walk through its crowd, as a table.
void PrintAgents(const DemoWorld& demo) {
  const demo::DemoAgents& walkers = *demo.walkers;
  std::printf("\n%-5s %-8s %-20s %-20s %7s %8s %8s %7s  %s\n", "agent", "profile", "from", "to", "set off",
              "arrived", "walked m", "reached", "note");
  for (std::size_t i = 0; i < walkers.agents().size(); ++i) {
    const demo::DemoAgent& agent = walkers.agents()[i];
    char set_off[16] = "-", arrived[16] = "-";
    if (agent.crowd_id >= 0) std::snprintf(set_off, sizeof(set_off), "%.1f s", agent.joined_at);
    if (agent.arrived_at >= 0.0f) std::snprintf(arrived, sizeof(arrived), "%.1f s", agent.arrived_at);
    std::printf("%-5zu %-8s %-20s %-20s %7s %8s %8.1f %7s  %s\n", i,
                demo.service->profile(agent.plan.profile).name.c_str(), PointText(agent.plan.start).c_str(),
                agent.crowd_id >= 0 ? PointText(agent.target).c_str() : "-", set_off, arrived, agent.walked,
                agent.arrived_at >= 0.0f ? "yes" : "no", AgentNote(walkers, i).c_str());
  }
  std::printf("agents: %zu of %zu reached their targets walking", walkers.arrived(), walkers.agents().size());
  for (int p = 0; p < demo.service->profile_count(); ++p) {
    const navmesh::Crowd* crowd = walkers.crowd(p);
    if (!crowd) continue;
    const navmesh::CrowdStats& stats = crowd->stats();
    std::printf("; %s crowd: %zu replans, %.1f agent-s waiting for tiles, %zu stuck",
                demo.service->profile(p).name.c_str(), stats.replans, stats.waiting_seconds,
                stats.stuck_agents);
  }
  std::printf("\n");
}

void PrintSummary(const DemoOptions& options, const DemoWorld& demo, const LoopFigures& figures) {
  if (demo.player) PrintWalk(*demo.player);
  const navmesh::NavMesh& navmesh = demo.service->navmesh();
  std::printf("\nnavmesh: %d tiles, %d polygons, %.1f m^2 walkable, %d islands\n", navmesh.tile_count(),
              navmesh.polygon_count(), navmesh.WalkableArea(), navmesh::CountIslands(navmesh));
  std::printf(
      "foreground: longest frame %.2f ms (step, player, agents); step %.2f ms mean, %.2f ms max; agents "
      "(crowds "
      "and their tile requests) %.3f ms mean, %.3f ms max; jobs were running during %d of %d steps "
      "(bench-navmesh compares steps with and without jobs)\n",
      figures.longest_frame_ms, figures.step_ms_total / std::max(1, options.steps), figures.longest_step_ms,
      figures.agents_ms_total / std::max(1, options.steps), figures.longest_agents_ms,
      figures.steps_with_jobs, options.steps);
}

// navmesh.obj, navmesh.png, scene.glb and the recording.
std::optional<DemoFailure> WriteOutputs(const DemoOptions& options, DemoWorld& demo) {
  const navmesh::NavMesh& navmesh = demo.service->navmesh();
  const std::filesystem::path folder(options.out_dir);
  const std::filesystem::path obj = folder / "navmesh.obj", png = folder / "navmesh.png",
                              glb = folder / "scene.glb";
  const std::vector<Vec3> trail = demo.player ? demo.player->trail() : std::vector<Vec3>{};
  for (const Status& written :
       {navmesh.WriteObj(obj),
        DrawPicture(*demo.world, demo.level, *demo.service, demo.walkers->agents(), trail, png),
        WriteGltf(*demo.world, demo.level, navmesh, demo.walkers->agents(), glb)})
    if (!written) return DemoFailure{2, written.message()};
  std::printf("wrote %s, %s and %s\n", obj.string().c_str(), png.string().c_str(), glb.string().c_str());
  if (!demo.recorder) return std::nullopt;
  std::vector<view::RecordedAgent> recorded;
  for (const demo::DemoAgent& agent : demo.walkers->agents()) {
    const navmesh::NavMeshSettings& walker = demo.service->profile_settings(agent.plan.profile);
    recorded.push_back({agent.plan.start, agent.crowd_id >= 0 ? agent.target : agent.plan.start,
                        agent.planned_path, agent.plan.profile, walker.agent_radius, walker.agent_height,
                        agent.arrived_at >= 0.0f});
  }
  demo.recorder->Finish(demo.service.get(), recorded);
  if (Status written = demo.recorder->Write(options.record); !written)
    return DemoFailure{2, written.message()};
  std::printf("recorded %zu frames to %s (strata view %s --out DIR)\n", demo.recorder->frame_count(),
              options.record.c_str(), options.record.c_str());
  return std::nullopt;
}

int Fail(const DemoFailure& failure) {
  if (!failure.message.empty()) std::cerr << "strata demo: " << failure.message << "\n";
  return failure.exit_code;
}

int RunDemo(const DemoOptions& options, const CLI::App& command) {
  navmesh::NavMeshServiceConfig config;
  config.settings = options.settings;
  config.worker_threads = options.navmesh_threads;
  Result<std::vector<navmesh::AgentProfile>> profiles =
      ChosenProfiles(command, options.profiles, options.settings);
  if (!profiles) return Fail({2, profiles.error().message});
  config.profiles = std::move(*profiles);
  if (!options.drop_links)
    for (navmesh::AgentProfile& profile : config.profiles) profile.max_drop = 0.0f;
  if (auto failed = CheckOptions(options, config)) return Fail(*failed);
  auto set_up = SetUpDemo(options, config);
  if (auto* failed = std::get_if<DemoFailure>(&set_up)) return Fail(*failed);
  DemoWorld& demo = std::get<DemoWorld>(set_up);
  std::printf("%zu bodies, %zu agents (", demo.world->body_count_in_world(), demo.walkers->agents().size());
  for (int p = 0; p < demo.service->profile_count(); ++p) {
    const navmesh::AgentProfile& profile = demo.service->profile(p);
    std::printf("%s%s %.2g m x %.2g m, drops %.2g m", p > 0 ? "; " : "", profile.name.c_str(), profile.radius,
                profile.height, profile.max_drop);
  }
  std::printf("); %d physics thread(s), %d navmesh thread(s)\n", options.physics_threads,
              options.navmesh_threads);
  auto loop = RunGameLoop(options, demo);
  if (auto* failed = std::get_if<DemoFailure>(&loop)) return Fail(*failed);
  PrintAgents(demo);
  PrintSummary(options, demo, std::get<LoopFigures>(loop));
  if (auto failed = WriteOutputs(options, demo)) return Fail(*failed);
  // A demo whose agents got no navmesh did not do its job, whatever the reason: say so in the exit code.
  const navmesh::NavMeshServiceStats stats = demo.service->stats();
  if (stats.failures > 0 || demo.service->navmesh().polygon_count() == 0)
    return Fail(
        {1, "the navmesh could not be built" + (stats.failures > 0 ? ": " + demo.service->last_error()
                                                                   : std::string(" (no walkable polygon)"))});
  return 0;
}

}  // namespace

std::function<int()> AddDemoCommand(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  CLI::App* demo =
      app.add_subcommand("demo", "the main job: a moving world with agents and background navmesh");
  demo->add_option("level", options->level, "level mesh file")->capture_default_str();
  demo->add_option("--steps", options->steps, "physics steps at 60 Hz")
      ->check(CLI::Range(1, kMaxSteps))
      ->capture_default_str();
  demo->add_option("--crates", options->crates, "falling crates (debris: not in the navmesh)")
      ->check(CLI::Range(0, kMaxSpawned))
      ->capture_default_str();
  demo->add_option("--boulders", options->boulders, "rolling boulders (2 m: they count)")
      ->check(CLI::Range(0, kMaxSpawned))
      ->capture_default_str();
  demo->add_option(
          "--agents", options->agents,
          "agents walking to random targets, every fourth of the second profile (on the courtyard two "
          "more start on the crate stack, where only a drop leads off)")
      ->check(CLI::Range(0, kMaxAgents))
      ->capture_default_str();
  demo->add_option("--profiles", options->profiles,
                   "the kinds of walker, each with its own navmesh: person, machine, critter (instead of the "
                   "agent options)")
      ->delimiter(',')
      ->check(CLI::IsMember({"person", "machine", "critter"}))
      ->capture_default_str();
  demo->add_flag("!--no-drop-links", options->drop_links, "build no drop-down links (every max drop 0)");
  demo->add_option("--request-radius", options->request_radius,
                   "tiles an agent waits for around its spawn before it sets off (m)")
      ->check(FiniteIn(0.0, 1.0e4))
      ->capture_default_str();
  demo->add_option("--target-radius", options->target_radius, "how far (about) an agent's target lies (m)")
      ->check(FiniteIn(0.5, 1.0e4))
      ->capture_default_str();
  demo->add_option("--threads", options->physics_threads, "physics threads")
      ->check(CountIn(1, kMaxThreads, "--threads"))
      ->capture_default_str();
  demo->add_option("--navmesh-threads", options->navmesh_threads, "background navmesh threads")
      ->check(CountIn(1, kMaxNavMeshThreads, "--navmesh-threads"))
      ->capture_default_str();
  demo->add_option("--time-scale", options->time_scale,
                   "simulated seconds per second: 1 runs at a game's pace (60 steps a second), 0 as fast as "
                   "it goes (the background then falls behind in simulated time)")
      ->check(FiniteIn(0.0, 1000.0))
      ->capture_default_str();
  demo->add_option("--out-dir", options->out_dir, "where navmesh.obj, navmesh.png and scene.glb go")
      ->capture_default_str();
  demo->add_option("--seed", options->seed, "spawn seed")->capture_default_str();
  demo->add_option("--record", options->record, "also write a recording of the run for `strata view`");
  demo->add_option("--record-every", options->record_every, "steps between recorded frames")
      ->check(CLI::Range(1, kMaxSteps))
      ->capture_default_str();
  demo->add_flag("!--no-player", options->player, "leave out the player character");
  demo->add_option(
          "--player-route", options->player_route,
          "the player's start and waypoints as x,z pairs, two or more (default: the courtyard's tour on it, "
          "else random floors)")
      ->delimiter(',')
      ->check(FiniteIn(-1.0e7, 1.0e7));
  demo->add_option("--player-speed", options->player_speed, "the player's walking speed (m/s)")
      ->check(FiniteIn(0.1, 50.0))
      ->capture_default_str();
  AddNavMeshSettingsOptions(*demo, options->settings);
  AddLevelOptions(*demo, options->level_options);
  return [options, demo] { return RunDemo(*options, *demo); };
}

}  // namespace strata::cli
