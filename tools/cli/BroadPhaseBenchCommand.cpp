// `strata bench-broadphase`: the streamed open-world broad-phase benchmark (see
// tools/bench/BroadPhaseBench.h), Bullet's DBVT side by side when built with it, then the game-object update
// with 1 vs 32 body mutexes.
#include <cstdio>
#include <thread>

#include <iostream>
#include <nlohmann/json.hpp>

#include "tools/bench/BroadPhaseBench.h"
#include "tools/bench/JsonReport.h"
#include "tools/bench/Progress.h"
#include "tools/cli/Commands.h"
#include "tools/cli/Validators.h"

namespace strata::cli {

namespace {

struct BroadPhaseBenchOptions {
  int bodies = 20000;
  int tiles = 28;
  int queries = 20000;
  int frames = 60;
  int max_threads = 0;  // 0 = hardware threads
  double object_work_us = 1.0;
  bool bullet = true;
  std::string json;  // also write the figures here
};

void Row(const char* what, double strata, double bullet, const char* unit) {
  if (bullet < 0.0) {
    std::printf("  %-44s %10.3f %-3s\n", what, strata, unit);
    return;
  }
  std::printf("  %-44s %10.3f %-3s  bullet %10.3f %-3s  strata/bullet %.2fx\n", what, strata, unit, bullet,
              unit, strata / bullet);
}

nlohmann::json ToJson(const bench::BroadPhaseFigures& f) {
  return {{"prepare_per_body_us", f.prepare_per_body_us},
          {"finalize_us", f.finalize_us},
          {"finalize_batch_sizes", bench::kBatchSizes},
          {"remove_us", f.remove_us},
          {"move_us", f.move_us},
          {"full_rebuild_ms", f.full_rebuild_ms},
          {"incremental_rebuild_ms", f.incremental_rebuild_ms},
          {"aabb_query_us", f.aabb_query_us},
          {"ray_10m_us", f.ray_10m_us},
          {"ray_100m_us", f.ray_100m_us},
          {"aabb_query_busy_us", f.aabb_query_busy_us},
          {"ray_10m_busy_us", f.ray_10m_busy_us},
          {"ray_100m_busy_us", f.ray_100m_busy_us},
          {"hits_per_block", f.hits_per_block},
          {"hits_per_100m_ray", f.hits_per_100m_ray}};
}

// The broad-phase operations, Strata beside Bullet (-1: Bullet was not run).
void PrintOperations(const bench::BroadPhaseFigures& strata, const bench::BroadPhaseFigures& bullet,
                     bool with_bullet) {
  auto peer = [&](double value) { return with_bullet ? value : -1.0; };
  Row("add: prepare per body (bullet: createProxy)", strata.prepare_per_body_us,
      peer(bullet.prepare_per_body_us), "us");
  for (std::size_t i = 0; i < strata.finalize_us.size(); ++i) {
    char label[64];
    std::snprintf(label, sizeof(label), "add: finalize batch of %d (bullet: n x create)",
                  bench::kBatchSizes[i]);
    Row(label, strata.finalize_us[i], with_bullet ? bullet.finalize_us[i] : -1.0, "us");
  }
  Row("remove one body", strata.remove_us, peer(bullet.remove_us), "us");
  Row("move one body (bullet: setAabb)", strata.move_us, peer(bullet.move_us), "us");
  Row("full rebuild (bullet: optimize)", strata.full_rebuild_ms, peer(bullet.full_rebuild_ms), "ms");
  Row("incremental rebuild after 600 moves", strata.incremental_rebuild_ms, -1.0, "ms");
  Row("AABB query 12.8 x 12.8 x 20 m, idle", strata.aabb_query_us, peer(bullet.aabb_query_us), "us");
  Row("ray cast 10 m, idle", strata.ray_10m_us, peer(bullet.ray_10m_us), "us");
  Row("ray cast 100 m, idle", strata.ray_100m_us, peer(bullet.ray_100m_us), "us");
  Row("AABB query, 2 threads add/remove/move (a)", strata.aabb_query_busy_us, -1.0, "us");
  Row("ray cast 10 m, 2 threads changing (a)", strata.ray_10m_busy_us, -1.0, "us");
  Row("ray cast 100 m, 2 threads changing (a)", strata.ray_100m_busy_us, -1.0, "us");
  std::printf(
      "  (a) per 16 ms frame each thread removes 100 bodies, streams them back in 10 batches and moves\n"
      "      1000; one of them also rebuilds the tree each frame, as the physics step does\n");
  std::printf("  bodies per block: strata %.2f%s; bodies per 100 m ray: strata %.2f%s\n",
              strata.hits_per_block,
              with_bullet ? (" bullet " + std::to_string(bullet.hits_per_block)).c_str() : "",
              strata.hits_per_100m_ray,
              with_bullet ? (" bullet " + std::to_string(bullet.hits_per_100m_ray)).c_str() : "");
}

// Each (logic, threads, mutexes) run of the game-object update, printed and added to `report`.
void RunGameObjectUpdates(const BroadPhaseBenchOptions& options, const bench::OpenWorld& world,
                          int max_threads, bench::Progress& progress, std::size_t& parts_done,
                          std::size_t parts, nlohmann::json& report) {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  std::printf(
      "game-object update: each thread takes a range of the %zu kinematic bodies, reads and sets each\n"
      "one's position and ray casts for every 4th, %d frames; lock wait = time blocked on body mutexes\n"
      "(%d hardware threads); 'logic' = busy work per object outside locks; contended = body mutexes per\n"
      "thread per frame found taken by another thread, of all it took\n",
      static_cast<std::size_t>(std::count(world.layers.begin(), world.layers.end(), layers::kMoving)),
      options.frames, hardware);
  for (const double work_us : {0.0, options.object_work_us}) {
    for (int threads = 1; threads <= max_threads; threads *= 2) {
      for (const std::uint32_t mutexes : {1u, 32u}) {
        progress.Update(parts_done, parts);
        const bench::GameObjectFigures figures =
            bench::MeasureGameObjectUpdate(world, threads, mutexes, options.frames, work_us);
        progress.Hide();
        ++parts_done;
        std::printf(
            "  logic %3.1f us, %2d threads, %2u mutexes: frame %7.3f ms, lock wait per thread per frame: "
            "mean "
            "%9.2f us, median %9.2f us, p99 %9.2f us, worst %9.2f us; contended %6.1f of %6.0f locks\n",
            work_us, threads, mutexes, figures.frame_ms, figures.lock_wait_us_per_thread_frame,
            figures.median_lock_wait_us, figures.p99_lock_wait_us, figures.max_lock_wait_us,
            figures.contended_per_thread_frame, figures.acquisitions_per_thread_frame);
        report["game_object_update"].push_back({{"logic_us", work_us},
                                                {"threads", threads},
                                                {"mutexes", mutexes},
                                                {"frame_ms", figures.frame_ms},
                                                {"lock_wait_us_mean", figures.lock_wait_us_per_thread_frame},
                                                {"lock_wait_us_median", figures.median_lock_wait_us},
                                                {"lock_wait_us_p99", figures.p99_lock_wait_us},
                                                {"lock_wait_us_worst", figures.max_lock_wait_us},
                                                {"contended", figures.contended_per_thread_frame},
                                                {"acquisitions", figures.acquisitions_per_thread_frame}});
      }
    }
    if (options.object_work_us <= 0.0) break;
  }
}

int Run(const BroadPhaseBenchOptions& options) {
  if (!options.json.empty() && !bench::JsonDestinationExists(options.json)) {
    std::cerr << "strata bench-broadphase: --json " << options.json << ": no such directory\n";
    return 2;
  }
  const bench::OpenWorld world = bench::MakeOpenWorld(options.bodies, options.tiles, 42);
  const bench::QuerySet queries = bench::MakeQuerySet(world, options.queries, 7);
  std::printf("broad phase: %d bodies in %d tiles of 256 m (%.0f x %.0f m), %d queries of each kind\n",
              options.bodies, options.tiles, world.extent.Size().x(), world.extent.Size().z(),
              options.queries);
  bench::Progress progress("strata bench-broadphase", "parts");
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  const int max_threads = options.max_threads > 0 ? options.max_threads : hardware;
  int thread_counts = 0;
  for (int threads = 1; threads <= max_threads; threads *= 2) ++thread_counts;
  // Strata's and Bullet's figures, then each (logic, threads, mutexes) run of the game-object update.
  const std::size_t parts =
      2 + static_cast<std::size_t>(thread_counts) * 2 * (options.object_work_us > 0.0 ? 2 : 1);
  std::size_t parts_done = 0;
  progress.Update(parts_done, parts);
  const bench::BroadPhaseFigures strata = bench::MeasureStrata(world, queries);
  progress.Update(++parts_done, parts);
  bench::BroadPhaseFigures bullet;
#ifdef STRATA_HAVE_BULLET
  if (options.bullet) bullet = bench::MeasureBullet(world, queries);
#endif
  progress.Hide();
  ++parts_done;
#ifndef STRATA_HAVE_BULLET
  if (options.bullet) std::printf("  (Bullet not built: install libbullet-dev and reconfigure)\n");
#endif
  const bool with_bullet = bullet.aabb_query_us >= 0.0;
  PrintOperations(strata, bullet, with_bullet);

  nlohmann::json report = {{"bodies", options.bodies},
                           {"tiles", options.tiles},
                           {"queries", options.queries},
                           {"strata", ToJson(strata)},
                           {"game_object_update", nlohmann::json::array()}};
  if (with_bullet) report["bullet"] = ToJson(bullet);
  RunGameObjectUpdates(options, world, max_threads, progress, parts_done, parts, report);
  report["hardware_threads"] = hardware;
  report["frames"] = options.frames;
  if (!options.json.empty()) {
    if (const Status written = bench::WriteJsonReport(options.json, report); !written) {
      std::cerr << "strata bench-broadphase: " << written.message() << "\n";
      return 2;
    }
  }
  std::fflush(stdout);
  progress.Finish(std::to_string(options.bodies) + " bodies, " + std::to_string(parts_done) + " parts");
  return 0;
}

}  // namespace

std::function<int()> AddBroadPhaseBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BroadPhaseBenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench-broadphase",
      "Broad-phase figures on a streamed open world (Bullet DBVT side by side), and body lock waits");
  command->add_option("--bodies", options->bodies, "Bodies in the world")->check(CLI::Range(100, 1000000));
  command->add_option("--tiles", options->tiles, "256 m tiles they are spread over")
      ->check(CLI::Range(1, 1000));
  command->add_option("--queries", options->queries, "Queries of each kind")->check(CLI::Range(1, 10000000));
  command->add_option("--frames", options->frames, "Frames of the game-object update")
      ->check(CLI::Range(1, 100000));
  command
      ->add_option("--max-threads", options->max_threads, "Most game-object threads (0 = hardware threads)")
      ->check(CountIn(0, kMaxThreads, "--max-threads"));
  command->add_option("--object-work-us", options->object_work_us, "Game logic per object in the second run")
      ->check(CLI::Range(0.0, 1000.0));
  command->add_flag("!--no-bullet", options->bullet, "Skip the Bullet peer");
  command->add_option("--json", options->json, "Also write the figures to this JSON file");
  return [options] { return Run(*options); };
}

}  // namespace strata::cli
