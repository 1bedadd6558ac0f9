// `strata bench-gameplay`: what game code costs (tools/bench/GameplayBench.h): shape casts on the 20,000-body
// open world beside Bullet's convex sweep, the pyramid stepped with and without contact events, and the
// character's update in the courtyard.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "tools/bench/GameplayBench.h"
#include "tools/bench/JsonReport.h"
#include "tools/cli/Commands.h"
#include "tools/cli/NavMeshOptions.h"

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

nlohmann::json Casts(const GameplayBenchOptions& options, const bench::OpenWorld& world,
                     const bench::QuerySet& queries) {
  std::printf(
      "shape casts: %d casts of 10 m through %d boxes (bench-broadphase's open world), closest hit, one "
      "thread, best of %d\n",
      options.casts, options.bodies, options.repeats);
  std::printf("  %-20s %14s %14s %13s %13s %28s %16s\n", "shape", "strata casts/s", "bullet casts/s",
              "strata/bullet", "hits s / b", "same place / strata earlier", "only strata");
  nlohmann::json rows = nlohmann::json::array();
  for (const bench::CastShapeKind kind : {bench::CastShapeKind::kSphere, bench::CastShapeKind::kCapsule}) {
    const bench::CastRun strata = bench::MeasureStrataCasts(world, queries, kind, options.repeats);
    bench::CastRun bullet;
#ifdef STRATA_HAVE_BULLET
    if (options.bullet) bullet = bench::MeasureBulletCasts(world, queries, kind, options.repeats);
#endif
    nlohmann::json row = {{"shape", bench::ToString(kind)},
                          {"strata_casts_per_second", strata.casts_per_second},
                          {"strata_hits", strata.hits}};
    if (bullet.casts_per_second < 0.0) {
      std::printf("  %-20s %14.0f %14s %13s %13d\n", bench::ToString(kind), strata.casts_per_second, "-", "-",
                  strata.hits);
      rows.push_back(std::move(row));
      continue;
    }
    // Within 1 mm of a 10 m cast. Bullet reports a hit once the shapes overlap by up to its allowed
    // penetration (4 cm by default), so its hits come later, and it passes shapes that start inside a box.
    const bench::CastAgreement agreement = bench::CompareCasts(strata, bullet, 1e-4f);
    char hits[32], places[48], only[48];
    std::snprintf(hits, sizeof(hits), "%d / %d", strata.hits, bullet.hits);
    std::snprintf(places, sizeof(places), "%d / %d of %d", agreement.same_place, agreement.a_earlier,
                  agreement.both_hit);
    std::snprintf(only, sizeof(only), "%d (%d at start)", agreement.only_a + agreement.only_a_at_start,
                  agreement.only_a_at_start);
    std::printf("  %-20s %14.0f %14.0f %12.2fx %13s %28s %16s\n", bench::ToString(kind),
                strata.casts_per_second, bullet.casts_per_second,
                strata.casts_per_second / bullet.casts_per_second, hits, places, only);
    if (agreement.b_earlier + agreement.only_b > 0)
      std::printf("  (%d casts Bullet hits earlier, %d only Bullet hits)\n", agreement.b_earlier,
                  agreement.only_b);
    row["bullet_casts_per_second"] = bullet.casts_per_second;
    row["bullet_hits"] = bullet.hits;
    row["both_hit"] = agreement.both_hit;
    row["same_place"] = agreement.same_place;
    row["strata_earlier"] = agreement.a_earlier;
    row["bullet_earlier"] = agreement.b_earlier;
    row["only_strata"] = agreement.only_a + agreement.only_a_at_start;
    row["only_strata_at_start"] = agreement.only_a_at_start;
    row["only_bullet"] = agreement.only_b;
    rows.push_back(std::move(row));
  }
  return rows;
}

nlohmann::json Events(const GameplayBenchOptions& options) {
  std::printf(
      "\ncontact events: the pyramid (1,240 boxes), %d steps, every box reporting its contacts against none "
      "(medians of %d alternated runs)\n",
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

nlohmann::json CharacterUpdates(const GameplayBenchOptions& options) {
  const bench::CharacterFigures figures =
      bench::MeasureCharacterUpdates(options.level, options.walkers, options.frames);
  std::printf(
      "\ncharacter: %d walkers x %d frames on %s: %d updates, Character::Update %.1f us mean, %.1f us "
      "median, %.1f us 99th percentile, %.1f us max\n",
      options.walkers, options.frames, options.level.c_str(), figures.updates, figures.mean_us,
      figures.median_us, figures.p99_us, figures.max_us);
  return {{"updates", figures.updates},
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
  const bench::OpenWorld world = bench::MakeOpenWorld(options.bodies, options.tiles, 7);
  const bench::QuerySet queries = bench::MakeQuerySet(world, options.casts, 11);
  nlohmann::json report = {{"casts", Casts(options, world, queries)},
                           {"events", Events(options)},
                           {"character", CharacterUpdates(options)}};
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
      ->check(CLI::Range(1, 1024));
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
