// `strata bench [--scene pyramid|convex_vs_mesh|all] [--steps N] [--threads 1,2,4,8,16] [--json FILE]
// [--solver strata|jolt|both] [--job-system default|pool] [--pair-cache-mm MM] [--pair-cache-degrees DEG]
// [--runs N] [--no-bullet] [--in-process]`: runs the benchmark scenes in Strata at each thread count and,
// when built with Bullet, in Bullet (one thread) in the same run, each run in its own child process (or, with
// --in-process, in this one: for profilers that do not follow a fork), at Strata's default
// solver passes and at Jolt's. With --runs N the engines take turns N times and each row is its engine's
// median run: on a noisy machine a ratio is only as good as the runs it compares. Prints one table per scene
// and solver budget with a speedup column, then where a step's time goes, stage by stage.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "physics/core/OutputFile.h"
#include "tools/bench/BenchRunner.h"
#include "tools/bench/InstructionSet.h"
#include "tools/bench/JsonReport.h"
#include "tools/bench/Progress.h"
#include "tools/cli/Commands.h"
#include "tools/cli/Validators.h"

namespace strata::cli {

namespace {

struct BenchOptions {
  std::string scene = "all";
  int steps = 0;  // 0 = the scene's own count
  std::vector<int> threads;
  std::string json;
  std::string job_system = "default";
  std::string solver = "both";
  bool bullet = true;
  int runs = 1;                                 // alternated runs of every engine per scene
  bool isolate = true;                          // each run in a child process (its own peak memory)
  std::optional<float> pair_cache_distance_mm;  // unset: the scene's own
  std::optional<float> pair_cache_angle;
};

// 1, 2, 4, ... up to the machine's cores, and the core count itself.
std::vector<int> DefaultThreadCounts() {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<int> counts;
  for (int t = 1; t < cores; t *= 2) counts.push_back(t);
  counts.push_back(cores);
  return counts;
}

void PrintRow(const char* engine, const bench::BenchScene& scene, const bench::EngineResult& r,
              double speedup) {
  if (!r.ok) {
    std::printf("  %-7s %7s  failed\n", engine, "");
    return;
  }
  std::printf("  %-7s %7d %9.1f %10.2f %9.2f %9.1f %8.2fx %6d %-12s %016llx\n", engine, r.threads,
              r.StepsPerSecond(), r.median_step_ms, r.max_step_ms, r.peak_memory_kb / 1024.0, speedup,
              r.bodies_in_footprint, scene.name == "pyramid" ? "in footprint" : "above y=0",
              static_cast<unsigned long long>(r.state_hash));
  if (!scene.joints.empty())
    std::printf(
        "  %-7s %7s joints' anchors apart after the last step: max %.3f mm, mean %.4f mm; widest over "
        "the run (every %d steps): %.3f mm\n",
        "", "", r.max_joint_gap_mm, r.mean_joint_gap_mm, bench::kJointGapSampleSteps, r.widest_joint_gap_mm);
}

// Stage by stage: time per step at each thread count, jobs, and the share of a one-thread step a stage
// takes; stages that run as one job are the serial part that bounds the speedup.
void PrintStages(const std::vector<bench::EngineResult>& runs) {
  if (runs.empty() || !runs.front().ok || runs.front().stage_count == 0) return;
  const bench::EngineResult& first = runs.front();
  std::printf("  where a step goes (ms per step, wall clock of each stage; busy = summed over its jobs):\n");
  std::printf("  %-20s %5s", "stage", "jobs");
  for (const bench::EngineResult& run : runs) std::printf("  %2dT wall %2dT busy", run.threads, run.threads);
  std::printf("  share@%dT  kind\n", first.threads);
  double serial = 0.0, total = 0.0;
  for (int s = 0; s < first.stage_count; ++s) total += first.stages[s].wall_ms;
  for (int s = 0; s < first.stage_count; ++s) {
    const bench::EngineResult& widest = runs.back();
    const std::uint32_t jobs = s < widest.stage_count ? widest.stages[s].jobs : first.stages[s].jobs;
    std::printf("  %-20s %5u", first.stages[s].name, jobs);
    for (const bench::EngineResult& run : runs)
      std::printf("  %8.3f %8.3f", s < run.stage_count ? run.stages[s].wall_ms : 0.0,
                  s < run.stage_count ? run.stages[s].busy_ms : 0.0);
    const bool parallel = first.stages[s].parallel;
    if (!parallel) serial += first.stages[s].wall_ms;
    std::printf("  %7.1f%%  %s\n", total > 0.0 ? 100.0 * first.stages[s].wall_ms / total : 0.0,
                parallel ? "parallel" : "serial");
  }
  std::printf("  %-20s %5s", "step (mean)", "");
  for (const bench::EngineResult& run : runs) std::printf("  %8.3f %8s", run.mean_step_ms, "");
  std::printf(
      "\n  serial stages: %.1f%% of a %d-thread step (Amdahl's limit %.1fx); pairs replayed from the "
      "body-pair cache: %.1f%%, held apart by last step's separating axis: %.1f%%\n",
      total > 0.0 ? 100.0 * serial / total : 0.0, first.threads, serial > 0.0 ? total / serial : 0.0,
      100.0 * first.replayed_pair_share, 100.0 * first.kept_apart_pair_share);
}

nlohmann::json ToJson(const bench::EngineResult& r, double speedup) {
  nlohmann::json run = {{"ok", r.ok},
                        {"threads", r.threads},
                        {"steps", r.steps},
                        {"steps_per_second", r.StepsPerSecond()},
                        {"mean_step_ms", r.mean_step_ms},
                        {"median_step_ms", r.median_step_ms},
                        {"max_step_ms", r.max_step_ms},
                        {"peak_memory_mib", r.peak_memory_kb / 1024.0},
                        {"bodies_in_footprint", r.bodies_in_footprint},
                        {"state_hash", r.state_hash},
                        {"max_joint_gap_mm", r.max_joint_gap_mm},
                        {"mean_joint_gap_mm", r.mean_joint_gap_mm},
                        {"widest_joint_gap_mm", r.widest_joint_gap_mm},
                        {"speedup", speedup}};
  if (r.stage_count > 0) {
    run["replayed_pair_share"] = r.replayed_pair_share;
    run["kept_apart_pair_share"] = r.kept_apart_pair_share;
    nlohmann::json stages = nlohmann::json::array();
    for (int s = 0; s < r.stage_count; ++s)
      stages.push_back({{"name", r.stages[s].name},
                        {"wall_ms", r.stages[s].wall_ms},
                        {"busy_ms", r.stages[s].busy_ms},
                        {"jobs", r.stages[s].jobs}});
    run["stages"] = stages;
  }
  return run;
}

// Counts the runs and keeps the progress bar on the one in progress (the rows print as runs end).
class RunProgress {
 public:
  RunProgress(std::size_t total, bool isolate)
      : progress_("strata bench", "runs"), total_(total), isolate_(isolate) {}
  template <class Run>
  bench::EngineResult operator()(Run&& run) {
    progress_.Update(done_, total_);
    bench::EngineResult result = isolate_ ? bench::RunIsolated(std::forward<Run>(run)) : run();
    progress_.Hide();
    ++done_;
    return result;
  }
  void Finish(std::size_t scenes) {
    progress_.Finish(std::to_string(done_) + " runs of " + std::to_string(scenes) + " scene run(s)");
  }

 private:
  bench::Progress progress_;
  std::size_t total_;
  bool isolate_;
  std::size_t done_ = 0;
};

// "jolt: 1 substep x (10 velocity + 2 relax passes), 1 restitution pass"
std::string SolverText(const bench::BenchScene& scene, bench::SolverBudget budget) {
  char text[160];
  std::snprintf(
      text, sizeof(text), "%s: %d substep%s x (%d velocity + %d relax passes), %d restitution pass%s",
      bench::ToString(budget), scene.substeps, scene.substeps == 1 ? "" : "s", scene.velocity_iterations,
      scene.relax_iterations, scene.restitution_iterations, scene.restitution_iterations == 1 ? "" : "es");
  return text;
}

void PrintSceneHeader(const bench::BenchScene& scene, const std::string& solver, int runs) {
  std::printf("%s: %zu bodies, %d steps of %.4f s, solver %s, sleeping %s, pair cache %.2f mm / %.1f deg",
              scene.name.c_str(), scene.bodies.size(), scene.steps, scene.dt, solver.c_str(),
              scene.sleeping ? "on" : "off", scene.pair_cache_max_distance * 1000.0f,
              scene.pair_cache_max_angle);
  if (runs > 1) std::printf("; each row the median of %d runs, the engines taking turns", runs);
  std::printf("\n");
  std::printf("  %-7s %7s %9s %10s %9s %9s %9s %6s %-12s %s\n", "engine", "threads", "steps/s", "ms median",
              "ms max", "MiB peak", "speedup", "bodies", "", "state hash");
}

// The run whose steps/s is the median of `runs` (the lower middle one of an even count).
bench::EngineResult MedianRun(std::vector<bench::EngineResult> runs) {
  std::sort(runs.begin(), runs.end(), [](const bench::EngineResult& a, const bench::EngineResult& b) {
    return a.StepsPerSecond() < b.StepsPerSecond();
  });
  return runs[(runs.size() - 1) / 2];
}

// The median over the alternated runs of Strata's steps/s over Bullet's in the same turn.
double MedianRatio(const std::vector<bench::EngineResult>& strata,
                   const std::vector<bench::EngineResult>& bullet) {
  std::vector<double> ratios;
  for (std::size_t r = 0; r < strata.size() && r < bullet.size(); ++r)
    if (strata[r].ok && bullet[r].ok)
      ratios.push_back(strata[r].StepsPerSecond() / bullet[r].StepsPerSecond());
  if (ratios.empty()) return 0.0;
  std::sort(ratios.begin(), ratios.end());
  return ratios[(ratios.size() - 1) / 2];
}

// Bullet's median run beside Strata's, with the ratios (when Bullet ran).
void PrintBulletBeside(const bench::BenchScene& scene,
                       const std::vector<std::vector<bench::EngineResult>>& strata,
                       const std::vector<bench::EngineResult>& bullet, nlohmann::json& scene_json) {
  if (bullet.empty()) return;
  const bench::EngineResult result = MedianRun(bullet);
  PrintRow("bullet", scene, result, 1.0);
  scene_json["bullet"] = ToJson(result, 1.0);
  if (!result.ok) return;
  nlohmann::json ratios = nlohmann::json::array();
  for (const std::vector<bench::EngineResult>& turns : strata) {
    const bench::EngineResult median = MedianRun(turns);
    if (!median.ok) continue;
    const double ratio = MedianRatio(turns, bullet);
    ratios.push_back({{"threads", median.threads}, {"steps_per_second", ratio}});
    std::printf("  strata/bullet at %d thread%s: %.2fx steps/s%s, %.2fx peak memory\n", median.threads,
                median.threads == 1 ? "" : "s", ratio,
                bullet.size() > 1 ? " (median of the turns' ratios)" : "",
                static_cast<double>(median.peak_memory_kb) / static_cast<double>(result.peak_memory_kb));
  }
  scene_json["strata_over_bullet"] = ratios;
}

// One scene at every thread count (and Bullet beside it), `options.runs` times in turn; false if a run
// failed.
bool RunScene(const bench::BenchScene& scene, const std::string& solver, const BenchOptions& options,
              bench::JobSystemKind job_system, bool with_bullet, RunProgress& run, nlohmann::json& document) {
  PrintSceneHeader(scene, solver, options.runs);
  nlohmann::json scene_json = {{"name", scene.name},
                               {"solver", solver},
                               {"bodies", scene.bodies.size()},
                               {"steps", scene.steps},
                               {"runs", options.runs},
                               {"pair_cache_mm", scene.pair_cache_max_distance * 1000.0f},
                               {"pair_cache_degrees", scene.pair_cache_max_angle}};
  std::vector<std::vector<bench::EngineResult>> strata(options.threads.size());
  std::vector<bench::EngineResult> bullet;
  for (int turn = 0; turn < options.runs; ++turn) {
    for (std::size_t t = 0; t < options.threads.size(); ++t)
      strata[t].push_back(run([&] { return bench::RunStrata(scene, options.threads[t], job_system); }));
#ifdef STRATA_HAVE_BULLET
    if (with_bullet) bullet.push_back(run([&] { return bench::RunBullet(scene); }));
#endif
  }
  std::vector<bench::EngineResult> runs;
  nlohmann::json strata_json = nlohmann::json::array();
  for (const std::vector<bench::EngineResult>& turns : strata) {
    runs.push_back(MedianRun(turns));
    const double base = runs.front().StepsPerSecond();
    const double speedup = base > 0.0 ? runs.back().StepsPerSecond() / base : 0.0;
    PrintRow("strata", scene, runs.back(), speedup);
    strata_json.push_back(ToJson(runs.back(), speedup));
  }
  scene_json["strata"] = strata_json;
  PrintBulletBeside(scene, strata, bullet, scene_json);
#ifndef STRATA_HAVE_BULLET
  (void)with_bullet;
  if (options.bullet) std::printf("  bullet   not built (install libbullet-dev and reconfigure)\n");
#endif
  PrintStages(runs);
  document["scenes"].push_back(scene_json);
  std::fflush(stdout);
  const auto all_ok = [](const std::vector<bench::EngineResult>& turns) {
    return std::all_of(turns.begin(), turns.end(), [](const bench::EngineResult& r) { return r.ok; });
  };
  return std::all_of(strata.begin(), strata.end(), all_ok);
}

int RunBench(BenchOptions options) {
  const std::vector<std::string> names =
      options.scene == "all" ? std::vector<std::string>{"pyramid", "convex_vs_mesh", "ragdolls", "chains"}
                             : std::vector<std::string>{options.scene};
  if (options.job_system != "default" && options.job_system != "pool") {
    std::cerr << "strata bench: --job-system must be 'default' or 'pool'\n";
    return 2;
  }
  std::vector<bench::SolverBudget> budgets;
  if (options.solver == "strata" || options.solver == "both") budgets.push_back(bench::SolverBudget::kStrata);
  if (options.solver == "jolt" || options.solver == "both") budgets.push_back(bench::SolverBudget::kJolt);
  if (budgets.empty()) {
    std::cerr << "strata bench: --solver must be 'strata', 'jolt' or 'both'\n";
    return 2;
  }
  if (!options.json.empty() && !bench::JsonDestinationExists(options.json)) {
    std::cerr << "strata bench: --json " << options.json << ": no such directory\n";
    return 2;
  }
  if (options.threads.empty()) options.threads = DefaultThreadCounts();
  const bench::JobSystemKind job_system =
      options.job_system == "pool" ? bench::JobSystemKind::kThreadPool : bench::JobSystemKind::kDefault;
  nlohmann::json document = {{"hardware_threads", std::thread::hardware_concurrency()},
                             {"instruction_set", bench::InstructionSet()},
                             {"job_system", options.job_system},
                             {"scenes", nlohmann::json::array()}};
  bool with_bullet = false;
#ifdef STRATA_HAVE_BULLET
  with_bullet = options.bullet;
#endif
  std::printf("strata bench: built for %s\n", bench::InstructionSet().c_str());
  RunProgress run(names.size() * budgets.size() * static_cast<std::size_t>(options.runs) *
                      (options.threads.size() + (with_bullet ? 1 : 0)),
                  options.isolate);
  for (const std::string& name : names) {
    bench::BenchScene scene = bench::MakeBenchScene(name);
    if (scene.bodies.empty()) {
      std::cerr << "strata bench: unknown scene '" << name
                << "' (pyramid, convex_vs_mesh, ragdolls, chains, all)\n";
      return 2;
    }
    if (options.steps > 0) scene.steps = options.steps;
    if (options.pair_cache_distance_mm)
      scene.pair_cache_max_distance = *options.pair_cache_distance_mm / 1000.0f;
    if (options.pair_cache_angle) scene.pair_cache_max_angle = *options.pair_cache_angle;
    for (const bench::SolverBudget budget : budgets) {
      const bench::BenchScene budgeted = bench::WithSolverBudget(scene, budget);
      if (!RunScene(budgeted, SolverText(budgeted, budget), options, job_system, with_bullet, run, document))
        return 1;
    }
  }
  if (!options.json.empty() && !bench::WriteJsonReport(options.json, document).ok()) {
    std::cerr << "strata bench: cannot write " << options.json << "\n";
    return 1;
  }
  run.Finish(names.size() * budgets.size());
  return 0;
}

}  // namespace

std::function<int()> AddBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Run the pyramid and convex_vs_mesh benchmarks at several thread counts (Bullet side by side)");
  command->add_option("--scene", options->scene, "pyramid, convex_vs_mesh, ragdolls, chains or all");
  command->add_option("--steps", options->steps, "Steps per scene (default: the scene's 500)")
      ->check(CountIn(1, 1000000, "--steps"));
  command
      ->add_option("--threads", options->threads,
                   "Thread counts to run Strata at, comma separated (default: 1, 2, 4, ... up to all cores)")
      ->delimiter(',')
      ->check(CountIn(1, kMaxThreads, "--threads"));
  command->add_option("--json", options->json, "Also write the figures to this JSON file");
  command->add_option(
      "--solver", options->solver,
      "strata (Strata's default passes), jolt (Jolt's passes for the scene) or both (default)");
  command->add_option("--job-system", options->job_system,
                      "default (oneTBB when built with it) or pool (Strata's std::thread pool)");
  command
      ->add_option("--pair-cache-mm", options->pair_cache_distance_mm,
                   "Body-pair cache: reuse a pair's contacts while it moved less than this (mm; 0 = off; "
                   "default 1, as Jolt)")
      ->check(CLI::Range(0.0f, 1000.0f));
  command
      ->add_option("--pair-cache-degrees", options->pair_cache_angle,
                   "Body-pair cache: ...and turned less than this (degrees; default 2, as Jolt)")
      ->check(CLI::Range(0.0f, 180.0f));
  command
      ->add_option("--runs", options->runs,
                   "Runs per scene, the engines taking turns; each row is its engine's median run and the "
                   "ratio the median of the turns' ratios (default 1)")
      ->check(CountIn(1, 101, "--runs"));
  command->add_flag("!--no-bullet", options->bullet, "Skip the Bullet peer");
  command->add_flag("!--in-process", options->isolate,
                    "Run every engine in this process, not each run in a child: for profilers that do not "
                    "follow a fork (valgrind --tool=callgrind); peak memory then includes the runs before");
  return [options] { return RunBench(*options); };
}

}  // namespace strata::cli
