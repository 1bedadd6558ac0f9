// `strata bench [--scene pyramid|convex_vs_mesh|all] [--steps N] [--threads T]`: runs the benchmark scenes
// in Strata and, when built with Bullet, in Bullet in the same run, each engine in its own child process.
#include <cstdio>
#include <iostream>

#include "tools/bench/BenchRunner.h"
#include "tools/cli/Commands.h"

namespace strata::cli {

namespace {

struct BenchOptions {
  std::string scene = "all";
  int steps = 0;  // 0 = the scene's own count
  int threads = 0;
  bool bullet = true;
};

void Print(const char* engine, const bench::BenchScene& scene, const bench::EngineResult& r) {
  if (!r.ok) {
    std::printf("  %-8s failed\n", engine);
    return;
  }
  std::printf(
      "  %-8s %5d bodies  %7.1f steps/s  %7.2f ms/step median  %7.2f ms max  %7.1f MiB peak  "
      "%5d %s  hash %016llx\n",
      engine, r.bodies, r.StepsPerSecond(), r.median_step_ms, r.max_step_ms, r.peak_memory_kb / 1024.0,
      r.bodies_in_footprint, scene.name == "pyramid" ? "in footprint" : "above y=0",
      static_cast<unsigned long long>(r.state_hash));
}

int RunBench(const BenchOptions& options) {
  std::vector<std::string> names;
  if (options.scene == "all")
    names = {"pyramid", "convex_vs_mesh"};
  else
    names = {options.scene};
  for (const std::string& name : names) {
    bench::BenchScene scene = bench::MakeBenchScene(name);
    if (scene.bodies.empty()) {
      std::cerr << "strata bench: unknown scene '" << name << "' (pyramid, convex_vs_mesh, all)\n";
      return 2;
    }
    if (options.steps > 0) scene.steps = options.steps;
    std::printf(
        "%s: %zu bodies, %d steps of %.4f s, %d velocity / %d position iterations, sleeping %s, "
        "threads %s\n",
        name.c_str(), scene.bodies.size(), scene.steps, scene.dt, scene.velocity_iterations,
        scene.position_iterations, scene.sleeping ? "on" : "off",
        options.threads == 0 ? "all" : std::to_string(options.threads).c_str());
    const bench::EngineResult strata =
        bench::RunIsolated([&] { return bench::RunStrata(scene, options.threads); });
    Print("strata", scene, strata);
#ifdef STRATA_HAVE_BULLET
    if (options.bullet) {
      const bench::EngineResult bullet = bench::RunIsolated([&] { return bench::RunBullet(scene); });
      Print("bullet", scene, bullet);
      if (strata.ok && bullet.ok)
        std::printf("  strata/bullet: %.2fx steps/s, %.2fx peak memory\n",
                    strata.StepsPerSecond() / bullet.StepsPerSecond(),
                    static_cast<double>(strata.peak_memory_kb) / static_cast<double>(bullet.peak_memory_kb));
    }
#else
    if (options.bullet) std::printf("  bullet   not built (install libbullet-dev and reconfigure)\n");
#endif
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

std::function<int()> AddBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command =
      app.add_subcommand("bench", "Run the pyramid and convex_vs_mesh benchmarks (Bullet side by side)");
  command->add_option("--scene", options->scene, "pyramid, convex_vs_mesh or all");
  command->add_option("--steps", options->steps, "Steps per scene (default: the scene's 500)")
      ->check(CLI::PositiveNumber);
  command->add_option("--threads", options->threads, "Strata worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("!--no-bullet", options->bullet, "Skip the Bullet peer");
  return [options] { return RunBench(*options); };
}

}  // namespace strata::cli
