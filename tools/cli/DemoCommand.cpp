// `strata demo [LEVEL]`: the main job. Imports a level (the bundled courtyard by default), fills it with
// falling crates and rolling boulders, spawns agents that request navmesh tiles around themselves and a
// player character that walks a route (the courtyard's: up the stairs and over the bridge), and steps the
// world while the tiles build in the background. Prints per-tile build figures, the agents' paths, the
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
  int physics_threads = 1;
  int navmesh_threads = 1;
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

struct Agent {
  Vec3 position;
  Vec3 target;
};

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

std::vector<Agent> SpawnAgents(const PhysicsSystem& world, const AABB& level, const FloorSampler& floors,
                               int count, std::mt19937& random) {
  std::vector<Agent> agents;
  for (int attempt = 0; attempt < 50 * count && static_cast<int>(agents.size()) < count; ++attempt) {
    const auto start = RandomGround(world, level, floors, random);
    const auto target = RandomGround(world, level, floors, random);
    if (start && target) agents.push_back({*start, *target});
  }
  return agents;
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
                   const std::vector<Agent>& agents, const std::vector<navmesh::PathResult>& paths,
                   const std::vector<Vec3>& player_trail, const std::filesystem::path& path) {
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
  for (std::size_t i = 0; i < agents.size(); ++i) {
    for (std::size_t k = 1; k < paths[i].points.size(); ++k)
      image.DrawLine(paths[i].points[k - 1], paths[i].points[k], {220, 30, 30});
    image.DrawDot(agents[i].position, 4, {20, 170, 40});
    image.DrawDot(agents[i].target, 3, {200, 30, 200});
  }
  for (std::size_t k = 1; k < player_trail.size(); ++k)
    image.DrawLine(player_trail[k - 1], player_trail[k], {40, 210, 230});
  return image.SavePng(path);
}

/// The level, the navmesh by island and the agents' paths, as the viewer's scene.glb shows them.
Status WriteGltf(PhysicsSystem& world, const LoadedLevel& level, const navmesh::NavMesh& navmesh,
                 const std::vector<navmesh::PathResult>& paths, const std::filesystem::path& path) {
  view::SceneGeometry geometry;
  for (const Triangle& t : LevelTriangles(world, level))
    geometry.level.insert(geometry.level.end(), std::begin(t.vertices), std::end(t.vertices));
  navmesh::NavMeshTriangles surface = navmesh::TrianglesByIsland(navmesh);
  geometry.navmesh = std::move(surface.vertices);
  geometry.island = std::move(surface.island);
  for (const navmesh::PathResult& agent_path : paths) geometry.paths.push_back(agent_path.points);
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
  std::vector<Agent> agents;
  std::unique_ptr<navmesh::NavMeshService> service;
  std::unique_ptr<demo::ScriptedWalk> player;  // null with --no-player
  std::optional<view::Recorder> recorder;      // with --record
};

// What the foreground saw while the navmesh built in the background.
struct LoopFigures {
  double longest_frame_ms = 0.0;
  double longest_request_ms = 0.0;
  double longest_step_ms = 0.0;
  double step_ms_total = 0.0;
  int steps_with_jobs = 0;
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
  demo.agents = SpawnAgents(*demo.world, demo.level.bounds, floors, options.agents, random);
  const Result<navmesh::NavMeshServiceConfig> level_config =
      navmesh::ConfigForLevel(config, demo.level.bounds);
  if (!level_config) return DemoFailure{2, options.level + ": " + level_config.error().message};
  auto service = navmesh::NavMeshService::Create(*demo.world, *level_config);
  if (!service) return DemoFailure{2, service.error().message};
  demo.service = std::move(*service);
  auto player = MakePlayer(*demo.world, *demo.service, options, demo.level.bounds, floors, random);
  if (!player) return DemoFailure{2, std::string()};  // MakePlayer said why
  demo.player = std::move(*player);
  if (auto failed = StartRecording(options, demo)) return *failed;
  return demo;
}

// The game loop: agents (re)request tiles around them every second; the world steps at 60 Hz.
std::variant<LoopFigures, DemoFailure> RunGameLoop(const DemoOptions& options, DemoWorld& demo) {
  LoopFigures figures;
  bench::Progress progress("strata demo", "steps");
  for (int step = 0; step < options.steps; ++step) {
    progress.Update(static_cast<std::size_t>(step), static_cast<std::size_t>(options.steps));
    const Clock::time_point frame_start = Clock::now();
    if (step % 60 == 0) {
      // Around where each agent stands and where it wants to go (nearer tiles first).
      for (const Agent& agent : demo.agents) {
        for (const Vec3& point : {agent.position, agent.target}) {
          const Clock::time_point request_start = Clock::now();
          (void)demo.service->RequestAround(point, options.request_radius);
          figures.longest_request_ms =
              std::max(figures.longest_request_ms, Milliseconds(Clock::now() - request_start));
        }
      }
    }
    const navmesh::NavMeshServiceStats before = demo.service->stats();
    const Clock::time_point step_start = Clock::now();
    if (Status status = demo.world->Step(1.0f / 60.0f); !status.ok()) return DemoFailure{1, status.message()};
    const double step_ms = Milliseconds(Clock::now() - step_start);
    figures.step_ms_total += step_ms;
    if (demo.player) {
      if (Status walked = demo.player->Update(1.0f / 60.0f, static_cast<float>(step + 1) / 60.0f); !walked)
        return DemoFailure{1, "the player: " + walked.message()};
    }
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

// Each agent's path to its target on the finished navmesh, printed as a table.
std::vector<navmesh::PathResult> FindAgentPaths(const DemoWorld& demo) {
  auto query = navmesh::NavMeshQuery::Create(demo.service->navmesh());
  std::vector<navmesh::PathResult> paths;
  std::printf("\n%-5s %-24s %-24s %6s %8s %9s %7s\n", "agent", "from", "to", "found", "reached", "length m",
              "corners");
  for (std::size_t i = 0; i < demo.agents.size(); ++i) {
    const Agent& agent = demo.agents[i];
    auto path = (*query)->FindPath(agent.position, agent.target);
    paths.push_back(path.ok() ? *path : navmesh::PathResult{});
    const navmesh::PathResult& p = paths.back();
    char from[64], to[64];
    std::snprintf(from, sizeof(from), "(%.1f, %.1f, %.1f)", agent.position.x(), agent.position.y(),
                  agent.position.z());
    std::snprintf(to, sizeof(to), "(%.1f, %.1f, %.1f)", agent.target.x(), agent.target.y(), agent.target.z());
    std::printf("%-5zu %-24s %-24s %6s %8s %9.2f %7zu%s\n", i, from, to, p.found ? "yes" : "no",
                p.reached_end ? "yes" : "no", p.length, p.points.size(),
                path.ok() ? "" : "  (no navmesh at start)");
  }
  return paths;
}

void PrintSummary(const DemoOptions& options, const DemoWorld& demo, const LoopFigures& figures) {
  if (demo.player) PrintWalk(*demo.player);
  const navmesh::NavMesh& navmesh = demo.service->navmesh();
  std::printf("\nnavmesh: %d tiles, %d polygons, %.1f m^2 walkable, %d islands\n", navmesh.tile_count(),
              navmesh.polygon_count(), navmesh.WalkableArea(), navmesh::CountIslands(navmesh));
  std::printf(
      "foreground: longest frame %.2f ms (step + requests), longest RequestAround %.3f ms; step %.2f ms "
      "mean, %.2f ms max; jobs were running during %d of %d steps (bench-navmesh compares steps with "
      "and without jobs)\n",
      figures.longest_frame_ms, figures.longest_request_ms,
      figures.step_ms_total / std::max(1, options.steps), figures.longest_step_ms, figures.steps_with_jobs,
      options.steps);
}

// navmesh.obj, navmesh.png, scene.glb and the recording.
std::optional<DemoFailure> WriteOutputs(const DemoOptions& options, DemoWorld& demo,
                                        const std::vector<navmesh::PathResult>& paths) {
  const navmesh::NavMesh& navmesh = demo.service->navmesh();
  const std::filesystem::path folder(options.out_dir);
  const std::filesystem::path obj = folder / "navmesh.obj", png = folder / "navmesh.png",
                              glb = folder / "scene.glb";
  const std::vector<Vec3> trail = demo.player ? demo.player->trail() : std::vector<Vec3>{};
  for (const Status& written :
       {navmesh.WriteObj(obj),
        DrawPicture(*demo.world, demo.level, *demo.service, demo.agents, paths, trail, png),
        WriteGltf(*demo.world, demo.level, navmesh, paths, glb)})
    if (!written) return DemoFailure{2, written.message()};
  std::printf("wrote %s, %s and %s\n", obj.string().c_str(), png.string().c_str(), glb.string().c_str());
  if (!demo.recorder) return std::nullopt;
  std::vector<view::RecordedAgent> recorded;
  for (std::size_t i = 0; i < demo.agents.size(); ++i)
    recorded.push_back({demo.agents[i].position, demo.agents[i].target, paths[i].points});
  demo.recorder->Finish(&navmesh, recorded);
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

int RunDemo(const DemoOptions& options) {
  navmesh::NavMeshServiceConfig config;
  config.settings = options.settings;
  config.worker_threads = options.navmesh_threads;
  if (auto failed = CheckOptions(options, config)) return Fail(*failed);
  auto set_up = SetUpDemo(options, config);
  if (auto* failed = std::get_if<DemoFailure>(&set_up)) return Fail(*failed);
  DemoWorld& demo = std::get<DemoWorld>(set_up);
  std::printf("%zu bodies, %zu agents; %d physics thread(s), %d navmesh thread(s)\n",
              demo.world->body_count_in_world(), demo.agents.size(), options.physics_threads,
              options.navmesh_threads);
  auto loop = RunGameLoop(options, demo);
  if (auto* failed = std::get_if<DemoFailure>(&loop)) return Fail(*failed);
  const std::vector<navmesh::PathResult> paths = FindAgentPaths(demo);
  PrintSummary(options, demo, std::get<LoopFigures>(loop));
  if (auto failed = WriteOutputs(options, demo, paths)) return Fail(*failed);
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
  demo->add_option("--agents", options->agents, "agents requesting tiles")
      ->check(CLI::Range(0, kMaxAgents))
      ->capture_default_str();
  demo->add_option("--request-radius", options->request_radius, "radius of each agent's request (m)")
      ->check(FiniteIn(0.0, 1.0e4))
      ->capture_default_str();
  demo->add_option("--threads", options->physics_threads, "physics threads")
      ->check(CountIn(1, kMaxThreads, "--threads"))
      ->capture_default_str();
  demo->add_option("--navmesh-threads", options->navmesh_threads, "background navmesh threads")
      ->check(CountIn(1, kMaxNavMeshThreads, "--navmesh-threads"))
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
  return [options] { return RunDemo(*options); };
}

}  // namespace strata::cli
