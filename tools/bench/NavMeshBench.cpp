#include "tools/bench/NavMeshBench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <random>
#include <thread>

#include "assets/level/LevelLoader.h"
#include "navmesh/LevelBake.h"
#include "navmesh/NavMeshService.h"
#include "navmesh/TileBuilder.h"
#include "physics/body/BodyManager.h"
#include "physics/shapes/BoxShape.h"
#include "physics/world/PhysicsSystem.h"
#include "tools/bench/JsonReport.h"
#include "tools/bench/Progress.h"

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;

double Milliseconds(Clock::duration duration) {
  return std::chrono::duration<double, std::milli>(duration).count();
}

double Max(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

struct BenchWorld {
  std::unique_ptr<PhysicsSystem> world;
  LoadedLevel level;
};

Result<BenchWorld> MakeWorld(const NavMeshBenchOptions& options) {
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(options.crates) + 4096;
  config.thread_count = options.physics_threads;
  auto world = PhysicsSystem::Create(config);
  if (!world) return world.error();
  Result<LoadedLevel> level = LoadLevel(**world, options.level);
  if (!level) return level.error();
  std::mt19937 random(11);
  const AABB& bounds = level->bounds;
  std::uniform_real_distribution<float> x(bounds.min.x() + 2.0f, bounds.max.x() - 2.0f);
  std::uniform_real_distribution<float> z(bounds.min.z() + 2.0f, bounds.max.z() - 2.0f);
  std::uniform_real_distribution<float> height(1.0f, 20.0f);
  const ShapeRef crate = *BoxShape::Create(Vec3(0.3f, 0.3f, 0.3f));
  for (int i = 0; i < options.crates; ++i) {
    BodyCreationSettings settings;
    settings.shape = crate;
    settings.position = Vec3(x(random), bounds.max.y() + height(random), z(random));
    settings.allow_sleeping = false;  // keep the step busy: this measures what jobs cost a working step
    (void)(*world)->bodies().CreateAndAddBody(settings);
  }
  return BenchWorld{std::move(*world), std::move(*level)};
}

/// Gather + Recast per tile, against Recast alone on triangles gathered beforehand.
void BenchTiles(const BenchWorld& bench, const NavMeshBenchOptions& options, nlohmann::json& report) {
  const navmesh::TileGrid grid(options.settings.tile_size());
  std::vector<double> gather_ms, recast_ms, precollected_ms;
  double gather_total = 0.0, precollected_total = 0.0, full_total = 0.0;
  std::size_t triangles = 0;
  for (const navmesh::TileCoord tile : grid.TilesInBox(bench.level.bounds)) {
    const AABB box = navmesh::TileGatherBox(options.settings, tile);
    const navmesh::TileGeometry precollected = navmesh::GatherTileGeometry(*bench.world, box, {});
    triangles += precollected.triangle_count();
    std::vector<double> gather, recast, alone;
    for (int r = 0; r < options.repeats; ++r) {
      const Clock::time_point start = Clock::now();
      const navmesh::TileGeometry geometry = navmesh::GatherTileGeometry(*bench.world, box, {});
      const Clock::time_point gathered = Clock::now();
      auto built = navmesh::BuildTile(options.settings, tile, geometry);
      const Clock::time_point done = Clock::now();
      gather.push_back(Milliseconds(gathered - start));
      recast.push_back(Milliseconds(done - gathered));
      const Clock::time_point alone_start = Clock::now();
      auto built_alone = navmesh::BuildTile(options.settings, tile, precollected);
      alone.push_back(Milliseconds(Clock::now() - alone_start));
      (void)built;
      (void)built_alone;
    }
    gather_ms.push_back(Median(gather));
    recast_ms.push_back(Median(recast));
    precollected_ms.push_back(Median(alone));
    gather_total += gather_ms.back();
    full_total += gather_ms.back() + recast_ms.back();
    precollected_total += precollected_ms.back();
  }
  std::printf("per tile (%zu tiles, %zu triangles gathered, median of %d builds each):\n", gather_ms.size(),
              triangles, options.repeats);
  std::printf("  gather        %7.3f ms median, %7.3f ms max\n", Median(gather_ms), Max(gather_ms));
  std::printf("  recast        %7.3f ms median, %7.3f ms max\n", Median(recast_ms), Max(recast_ms));
  std::printf("  pre-collected %7.3f ms median (Recast on triangles gathered beforehand)\n",
              Median(precollected_ms));
  std::printf(
      "  gather overhead: %.1f%% (all tiles: gather + build %.1f ms vs build from pre-collected %.1f ms; "
      "target <= 10%%)\n",
      100.0 * (full_total - precollected_total) / precollected_total, full_total, precollected_total);
  report["tiles"] = {
      {"count", gather_ms.size()},
      {"triangles", triangles},
      {"gather_ms", {{"median", Median(gather_ms)}, {"max", Max(gather_ms)}}},
      {"recast_ms", {{"median", Median(recast_ms)}, {"max", Max(recast_ms)}}},
      {"precollected_ms", {{"median", Median(precollected_ms)}}},
      {"gather_overhead_percent", 100.0 * (full_total - precollected_total) / precollected_total}};
  (void)gather_total;
}

/// A service sized for the bench level; the reason on standard error when it cannot be made.
std::unique_ptr<navmesh::NavMeshService> MakeLevelService(const BenchWorld& bench,
                                                          const navmesh::NavMeshServiceConfig& config) {
  Result<navmesh::NavMeshServiceConfig> level_config = navmesh::ConfigForLevel(config, bench.level.bounds);
  if (!level_config) {
    std::fprintf(stderr, "strata bench-navmesh: %s\n", level_config.error().message.c_str());
    return nullptr;
  }
  auto service = navmesh::NavMeshService::Create(*bench.world, *level_config);
  if (!service) {
    std::fprintf(stderr, "strata bench-navmesh: %s\n", service.error().message.c_str());
    return nullptr;
  }
  return std::move(*service);
}

/// One agent asks for the tiles around it; how long until each is published.
void BenchRequestToReady(const BenchWorld& bench, const NavMeshBenchOptions& options,
                         nlohmann::json& report) {
  navmesh::NavMeshServiceConfig config;
  config.settings = options.settings;
  config.worker_threads = options.navmesh_threads;
  auto service = MakeLevelService(bench, config);
  if (!service) return;
  const Vec3 agent = bench.level.bounds.Center();
  const Clock::time_point start = Clock::now();
  (void)service->RequestAround(agent, 20.0f);
  service->WaitUntilIdle(std::chrono::seconds(120));
  const double all_ms = Milliseconds(Clock::now() - start);
  std::vector<double> ready_ms;
  double longest_publish_ms = 0.0;
  for (const auto& record : service->build_log()) {
    ready_ms.push_back(record.request_to_ready_ms);
    longest_publish_ms = std::max(longest_publish_ms, record.publish_ms);
  }
  std::printf(
      "RequestAround(level centre, 20 m) with %d navmesh thread(s): %zu tiles; first ready %.2f ms, "
      "median %.2f ms, all %.2f ms\n",
      options.navmesh_threads, ready_ms.size(),
      ready_ms.empty() ? 0.0 : *std::min_element(ready_ms.begin(), ready_ms.end()), Median(ready_ms), all_ms);
  std::printf("  publishing a tile held the navmesh from path queries for at most %.3f ms\n",
              longest_publish_ms);
  report["request_to_ready"] = {
      {"tiles", ready_ms.size()},
      {"first_ms", ready_ms.empty() ? 0.0 : *std::min_element(ready_ms.begin(), ready_ms.end())},
      {"median_ms", Median(ready_ms)},
      {"all_ms", all_ms},
      {"longest_publish_ms", longest_publish_ms}};
}

struct StepFigures {
  std::vector<double> step_ms;
  double lock_wait_ms = 0.0;
  double max_step_lock_wait_ms = 0.0;  ///< the most one step waited for body locks
};

/// Steps with and without navmesh jobs in alternating blocks (so drift hits both alike).
void BenchStepWithJobs(BenchWorld& bench, const NavMeshBenchOptions& options, nlohmann::json& report,
                       Progress& progress) {
  navmesh::NavMeshServiceConfig config;
  config.settings = options.settings;
  config.worker_threads = options.navmesh_threads;
  config.rebuild_delay = std::chrono::milliseconds(0);
  auto service = MakeLevelService(bench, config);
  if (!service) return;
  (void)service->RequestBox(bench.level.bounds);
  service->WaitUntilIdle(std::chrono::seconds(120));
  for (int i = 0; i < 120; ++i) (void)bench.world->Step(1.0f / 60.0f);  // let the crates land first

  StepFigures with_jobs, without_jobs;
  std::size_t builds_during = 0;
  for (int block = 0; block < options.step_blocks; ++block) {
    const bool jobs = block % 2 == 0;
    StepFigures& figures = jobs ? with_jobs : without_jobs;
    const std::size_t builds_before = service->stats().builds;
    for (int i = 0; i < options.steps_per_block; ++i) {
      progress.Update(static_cast<std::size_t>(block * options.steps_per_block + i),
                      static_cast<std::size_t>(options.step_blocks * options.steps_per_block));
      // Keep the workers busy: whenever they run dry, every tile goes stale again.
      if (jobs && service->stats().queued == 0) (void)service->Invalidate(bench.level.bounds);
      const std::uint64_t wait_before = ThreadBodyLockWaitNanoseconds();
      const Clock::time_point start = Clock::now();
      (void)bench.world->Step(1.0f / 60.0f);
      figures.step_ms.push_back(Milliseconds(Clock::now() - start));
      const double waited_ms = static_cast<double>(ThreadBodyLockWaitNanoseconds() - wait_before) * 1e-6;
      figures.lock_wait_ms += waited_ms;
      figures.max_step_lock_wait_ms = std::max(figures.max_step_lock_wait_ms, waited_ms);
    }
    if (jobs) {
      builds_during += service->stats().builds - builds_before;
    } else {
      service->WaitUntilIdle(std::chrono::seconds(120));
    }
    if (jobs) service->WaitUntilIdle(std::chrono::seconds(120));
  }
  progress.Hide();
  const auto print = [](const char* name, const StepFigures& figures) {
    double sum = 0.0;
    for (const double ms : figures.step_ms) sum += ms;
    std::printf(
        "  %-18s mean %7.3f ms, median %7.3f ms, max %7.3f ms; step blocked on body locks %.3f ms in all, "
        "at most %.3f ms in one step\n",
        name, sum / static_cast<double>(figures.step_ms.size()), Median(figures.step_ms),
        Max(figures.step_ms), figures.lock_wait_ms, figures.max_step_lock_wait_ms);
    return sum / static_cast<double>(figures.step_ms.size());
  };
  std::printf(
      "physics step, %zu bodies, %d physics thread(s), %d navmesh thread(s), %u cores (%d steps each):\n",
      bench.world->body_count_in_world(), options.physics_threads, options.navmesh_threads,
      std::thread::hardware_concurrency(), options.step_blocks / 2 * options.steps_per_block);
  const double busy = print("with navmesh jobs", with_jobs);
  const double idle = print("without", without_jobs);
  // Nothing but the navmesh jobs runs beside the step here, so its waits in the first row are theirs.
  std::printf("  step blocked by navmesh jobs: %.3f us in %zu steps (target 0)\n",
              with_jobs.lock_wait_ms * 1e3, with_jobs.step_ms.size());
  std::printf(
      "  %zu tiles built while stepping; step %+.1f%% with jobs (target <= 3%% when a core is free)\n",
      builds_during, 100.0 * (busy - idle) / idle);
  const auto figures_json = [](const StepFigures& figures, double mean) {
    return nlohmann::json{{"mean_ms", mean},
                          {"median_ms", Median(figures.step_ms)},
                          {"max_ms", Max(figures.step_ms)},
                          {"lock_wait_ms", figures.lock_wait_ms},
                          {"max_step_lock_wait_ms", figures.max_step_lock_wait_ms}};
  };
  report["step"] = {{"bodies", bench.world->body_count_in_world()},
                    {"physics_threads", options.physics_threads},
                    {"navmesh_threads", options.navmesh_threads},
                    {"steps_each", with_jobs.step_ms.size()},
                    {"with_jobs", figures_json(with_jobs, busy)},
                    {"without_jobs", figures_json(without_jobs, idle)},
                    {"blocked_by_navmesh_jobs_us", with_jobs.lock_wait_ms * 1e3},
                    {"tiles_built_while_stepping", builds_during},
                    {"step_change_with_jobs_percent", 100.0 * (busy - idle) / idle}};
}

}  // namespace

int RunNavMeshBench(const NavMeshBenchOptions& options) {
  if (Status status = options.settings.Validate(); !status.ok()) {
    std::cerr << "strata bench-navmesh: " << status.message() << "\n";
    return 2;
  }
  if (!options.json.empty() && !JsonDestinationExists(options.json)) {
    std::cerr << "strata bench-navmesh: --json " << options.json << ": no such directory\n";
    return 2;
  }
  Result<BenchWorld> bench = MakeWorld(options);
  if (!bench) {
    std::cerr << "strata bench-navmesh: " << bench.error().message << "\n";
    return 2;
  }
  std::printf("level %s: %zu triangles, %d crates\n", options.level.c_str(), bench->level.triangles,
              options.crates);
  Progress progress("strata bench-navmesh", "steps");
  nlohmann::json report = {{"level", options.level},
                           {"level_triangles", bench->level.triangles},
                           {"crates", options.crates},
                           {"hardware_threads", std::thread::hardware_concurrency()}};
  BenchTiles(*bench, options, report);
  BenchRequestToReady(*bench, options, report);
  BenchStepWithJobs(*bench, options, report, progress);
  if (!options.json.empty()) {
    if (const Status written = WriteJsonReport(options.json, report); !written) {
      std::cerr << "strata bench-navmesh: " << written.message() << "\n";
      return 2;
    }
  }
  std::fflush(stdout);
  progress.Finish(std::to_string(options.step_blocks * options.steps_per_block) +
                  " steps with and without navmesh jobs");
  return 0;
}

}  // namespace strata::bench
