// `strata bench-gameplay`: what game code costs (tools/bench/GameplayBench.h): shape casts on the 20,000-body
// open world beside Bullet's convex sweep, both against the exact first touch, the pyramid stepped with and
// without contact events, and the character's update in the courtyard.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "tools/bench/GameplayBench.h"
#include "tools/bench/JsonReport.h"
#include "tools/cli/Commands.h"
#include "tools/cli/NavMeshOptions.h"
#include "tools/cli/Validators.h"

namespace strata::cli {

namespace {

struct GameplayBenchOptions {
  int bodies = 20000;
  int tiles = 28;
  int casts = 20000;
  int repeats = 3;
  std::vector<int> event_threads = {1};
  int event_steps = 200;
  int event_rounds = 3;
  int walkers = 64;
  int frames = 600;
  std::string level = DefaultLevelPath();
  bool bullet = true;
  std::string json;
};

void PrintAccuracy(const char* shape, const char* engine, const bench::CastRun& run,
                   const bench::CastAccuracy& accuracy, const char* speed) {
  char missed[32];
  std::snprintf(missed, sizeof(missed), "%d (%d inside)", accuracy.missed, accuracy.missed_inside);
  std::printf("  %-20s %-7s %10.0f %7s %6d %11d %9.2f %9.2f %10.3f %8.3f %8.2f %16s %6d\n", shape, engine,
              run.casts_per_second, speed, run.hits, accuracy.within_1mm, accuracy.earliest_mm,
              accuracy.latest_mm, accuracy.mean_abs_mm, accuracy.widest_gap_mm, accuracy.deepest_overlap_mm,
              missed, accuracy.false_hits);
}

nlohmann::json AccuracyJson(const char* engine, const bench::CastRun& run,
                            const bench::CastAccuracy& accuracy) {
  return {{"engine", engine},
          {"casts_per_second", run.casts_per_second},
          {"hits", run.hits},
          {"within_1mm", accuracy.within_1mm},
          {"earliest_mm", accuracy.earliest_mm},
          {"latest_mm", accuracy.latest_mm},
          {"mean_abs_mm", accuracy.mean_abs_mm},
          {"widest_gap_mm", accuracy.widest_gap_mm},
          {"deepest_overlap_mm", accuracy.deepest_overlap_mm},
          {"missed", accuracy.missed},
          {"missed_inside", accuracy.missed_inside},
          {"false_hits", accuracy.false_hits}};
}

nlohmann::json Casts(const GameplayBenchOptions& options, const bench::OpenWorld& world,
                     const bench::QuerySet& queries) {
  constexpr float kCastLength = 10.0f;
  std::printf(
      "shape casts: %d casts of 10 m through %d boxes (bench-broadphase's open world), closest hit, one "
      "thread, best of %d\n  against the exact first touch: error along the cast (mm, - early), the widest "
      "gap and deepest "
      "overlap at a hit (mm), exact hits missed, hits where there is none\n",
      options.casts, options.bodies, options.repeats);
  std::printf("  %-20s %-7s %10s %7s %6s %11s %9s %9s %10s %8s %8s %16s %6s\n", "shape", "engine", "casts/s",
              "speed", "hits", "within 1 mm", "earliest", "latest", "mean |err|", "gap", "overlap", "missed",
              "false");
  nlohmann::json rows = nlohmann::json::array();
  for (const bench::CastShapeKind kind : {bench::CastShapeKind::kSphere, bench::CastShapeKind::kCapsule}) {
    const std::vector<float> exact = bench::ExactCastFractions(world, queries, kind);
    const bench::CastRun strata = bench::MeasureStrataCasts(world, queries, kind, options.repeats);
    const bench::CastAccuracy strata_accuracy = bench::MeasureCastAccuracy(
        strata, exact, bench::ExactGapsAt(world, queries, kind, strata.fractions), kCastLength);
    nlohmann::json row = {{"shape", bench::ToString(kind)},
                          {"exact_hits", strata_accuracy.exact_hits},
                          {"exact_starts_inside", strata_accuracy.starts_inside},
                          {"engines", {AccuracyJson("strata", strata, strata_accuracy)}}};
    bench::CastRun bullet;
#ifdef STRATA_HAVE_BULLET
    if (options.bullet) bullet = bench::MeasureBulletCasts(world, queries, kind, options.repeats);
#endif
    char speed[16] = "-";
    if (bullet.casts_per_second > 0.0)
      std::snprintf(speed, sizeof(speed), "%.2fx", strata.casts_per_second / bullet.casts_per_second);
    PrintAccuracy(bench::ToString(kind), "strata", strata, strata_accuracy, speed);
    if (bullet.casts_per_second > 0.0) {
      // Bullet reports a hit once the shapes overlap by up to its allowed penetration and passes shapes that
      // start inside a box, so its hits come late or not at all there.
      const bench::CastAccuracy bullet_accuracy = bench::MeasureCastAccuracy(
          bullet, exact, bench::ExactGapsAt(world, queries, kind, bullet.fractions), kCastLength);
      PrintAccuracy("", "bullet", bullet, bullet_accuracy, "1.00x");
      row["engines"].push_back(AccuracyJson("bullet", bullet, bullet_accuracy));
    }
    std::printf("  %-20s exact   %10s %9s %6d (%d start inside a box)\n", "", "", "",
                strata_accuracy.exact_hits, strata_accuracy.starts_inside);
    rows.push_back(std::move(row));
  }
  return rows;
}

nlohmann::json Events(const GameplayBenchOptions& options) {
  std::printf(
      "\ncontact events: the pyramid (1,240 boxes), %d steps, every box reporting its contacts against none "
      "(each run's median step; the median of %d alternated runs)\n",
      options.event_steps, options.event_rounds);
  std::printf("  %-8s %14s %16s %10s %14s\n", "threads", "quiet ms/step", "reporting ms/step", "cost",
              "events/step");
  nlohmann::json rows = nlohmann::json::array();
  for (const int threads : options.event_threads) {
    const bench::EventFigures figures =
        bench::MeasureEventCost(threads, options.event_steps, options.event_rounds);
    const double cost =
        figures.quiet_step_ms > 0.0 ? figures.reporting_step_ms / figures.quiet_step_ms - 1.0 : 0.0;
    std::printf("  %-8d %14.3f %16.3f %9.1f%% %14.0f\n", figures.threads, figures.quiet_step_ms,
                figures.reporting_step_ms, 100.0 * cost, figures.events_per_step);
    rows.push_back({{"threads", figures.threads},
                    {"quiet_step_ms", figures.quiet_step_ms},
                    {"reporting_step_ms", figures.reporting_step_ms},
                    {"events_per_step", figures.events_per_step}});
  }
  return rows;
}

Result<nlohmann::json> CharacterUpdates(const GameplayBenchOptions& options) {
  const Result<bench::CharacterFigures> measured =
      bench::MeasureCharacterUpdates(options.level, options.walkers, options.frames);
  if (!measured) return measured.error();
  const bench::CharacterFigures& figures = *measured;
  std::printf(
      "\ncharacter: %d walkers x %d frames on %s: %d updates, Character::Update %.1f us mean, %.1f us "
      "median, %.1f us 99th percentile, %.1f us max\n",
      options.walkers, options.frames, options.level.c_str(), figures.updates, figures.mean_us,
      figures.median_us, figures.p99_us, figures.max_us);
  return nlohmann::json{{"updates", figures.updates},
                        {"mean_us", figures.mean_us},
                        {"median_us", figures.median_us},
                        {"p99_us", figures.p99_us},
                        {"max_us", figures.max_us}};
}

int Run(const GameplayBenchOptions& options) {
  if (!options.json.empty() && !bench::JsonDestinationExists(options.json)) {
    std::cerr << "strata bench-gameplay: --json " << options.json << ": no such directory\n";
    return 2;
  }
  // The character first: a level that does not load stops the run before the long parts.
  Result<nlohmann::json> character = CharacterUpdates(options);
  if (!character) {
    // The loader's message names the file.
    std::cerr << "strata bench-gameplay: --level " << character.error().message << "\n";
    return 2;
  }
  const bench::OpenWorld world = bench::MakeOpenWorld(options.bodies, options.tiles, 7);
  const bench::QuerySet queries = bench::MakeQuerySet(world, options.casts, 11);
  const nlohmann::json report = {
      {"casts", Casts(options, world, queries)}, {"events", Events(options)}, {"character", *character}};
  if (options.json.empty()) return 0;
  if (Status written = bench::WriteJsonReport(options.json, report); !written) {
    std::cerr << "strata bench-gameplay: " << written.message() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace

std::function<int()> AddGameplayBenchCommand(CLI::App& app) {
  auto options = std::make_shared<GameplayBenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench-gameplay",
      "Shape casts beside Bullet, contact events' cost on the pyramid, the character's update");
  command->add_option("--bodies", options->bodies, "Bodies of the open world")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command->add_option("--tiles", options->tiles, "Its 256 m tiles")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command->add_option("--casts", options->casts, "Shape casts per shape")
      ->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  command->add_option("--repeats", options->repeats, "Passes over the casts (the best counts)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command->add_option("--event-threads", options->event_threads, "Thread counts for the events' cost")
      ->delimiter(',')
      ->check(CountIn(1, kMaxThreads, "--event-threads"));
  command->add_option("--event-steps", options->event_steps, "Pyramid steps a run")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  command->add_option("--event-rounds", options->event_rounds, "Alternated runs of each")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command->add_option("--walkers", options->walkers, "Characters walking the level")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  command->add_option("--frames", options->frames, "Updates of each")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command->add_option("--level", options->level, "Level the characters walk")->capture_default_str();
  command->add_flag("!--no-bullet", options->bullet, "Leave out Bullet");
  command->add_option("--json", options->json, "Also write the figures here");
  return [options] { return Run(*options); };
}

}  // namespace strata::cli
