// `strata accuracy`: runs the analytic cases over the settings grid on Strata and Bullet and writes
// accuracy.json, accuracy.md and accuracy.png into --out-dir.
#include <cstdio>
#include <iostream>
#include <set>

#include "tools/accuracy/AccuracyReport.h"
#include "tools/bench/Progress.h"
#include "tools/cli/Commands.h"

namespace strata::cli {

namespace {

struct AccuracyOptions {
  std::string out_dir = ".";
  std::vector<std::string> cases;     // empty = all
  std::vector<std::string> settings;  // empty = the whole grid
  bool quick = false;
  bool no_bullet = false;
  int timing_runs = 5;
};

// Keeps the items named in `wanted` (all of them when it is empty). False, with a message listing every name,
// when a name matches nothing.
template <class Item>
bool KeepNamed(std::vector<Item>& items, const std::vector<std::string>& wanted, const char* option) {
  if (wanted.empty()) return true;
  const std::set<std::string> names(wanted.begin(), wanted.end());
  std::vector<Item> chosen;
  for (const Item& item : items)
    if (names.count(item.name)) chosen.push_back(item);
  if (chosen.size() == names.size()) {
    items = std::move(chosen);
    return true;
  }
  std::cerr << "strata accuracy: unknown name in " << option << "; the names are:";
  for (const Item& item : items) std::cerr << " \"" << item.name << "\"";
  std::cerr << "\n";
  return false;
}

int RunAccuracy(const AccuracyOptions& options) {
  using namespace accuracy;
  std::vector<AccuracyCase> cases = AccuracyCases();
  std::vector<AccuracySetting> settings = AccuracySettings();
  if (!KeepNamed(cases, options.cases, "--case") || !KeepNamed(settings, options.settings, "--setting"))
    return 2;
  if (options.quick) settings = {DefaultAccuracySetting()};
  std::vector<std::string> engines = {"strata"};
  if (!options.no_bullet && MakeBulletEngine()) engines.push_back("bullet");
  std::error_code error;
  std::filesystem::create_directories(options.out_dir, error);
  if (!std::filesystem::is_directory(options.out_dir)) {
    std::cerr << "strata accuracy: cannot use output directory " << options.out_dir << "\n";
    return 2;
  }
  bench::Progress progress("strata accuracy", "runs");
  Result<std::vector<AccuracyRecord>> records =
      RunAccuracySuite(cases, settings, engines, options.timing_runs, progress.Callback());
  progress.Hide();
  if (!records) {
    std::cerr << "strata accuracy: " << records.error().message << "\n";
    return 1;
  }
  const std::filesystem::path out(options.out_dir);
  for (const Status& written : {WriteAccuracyJson(*records, cases, out / "accuracy.json"),
                                WriteAccuracyMarkdown(*records, cases, out / "accuracy.md"),
                                WriteAccuracyPlot(*records, cases, out / "accuracy.png")})
    if (!written) {
      std::cerr << "strata accuracy: " << written.message() << "\n";
      return 1;
    }
  int failed_defaults = 0;
  std::printf("%-24s %-10s %12s %10s %5s\n", "case (default setting)", "engine", "error", "ms", "pass");
  for (const AccuracyRecord& r : *records) {
    if (!r.is_default) continue;
    std::printf("%-24s %-10s %12.3e %10.2f %5s\n", r.case_name.c_str(), r.engine.c_str(), r.error, r.wall_ms,
                r.passed ? "yes" : "NO");
    if (r.engine == "strata" && !r.passed) ++failed_defaults;
  }
  int compared = 0, at_or_below = 0, only_failing = 0;
  for (const AccuracyCase& c : cases) {
    if (ParetoFront(*records, c.name, "bullet").empty()) continue;
    ++compared;
    const std::vector<FrontGap> gaps = FrontGaps(*records, c.name, c.tolerance * 0.1);
    if (gaps.empty()) ++at_or_below;
    if (OnlyFailingRunsUncovered(gaps)) ++only_failing;
  }
  if (compared > 0)
    std::printf(
        "Strata's Pareto front is at or below Bullet's on %d of %d cases (accuracy.md says where not); on %d "
        "of "
        "the other %d, every Bullet run it does not cover fails the case's tolerance\n",
        at_or_below, compared, only_failing, compared - at_or_below);
  std::printf("wrote %s, %s, %s (%zu runs); %d case(s) fail at Strata's default setting\n",
              (out / "accuracy.json").c_str(), (out / "accuracy.md").c_str(), (out / "accuracy.png").c_str(),
              records->size(), failed_defaults);
  std::fflush(stdout);
  progress.Finish(std::to_string(records->size()) + " runs, " + std::to_string(failed_defaults) +
                  " failing at the default setting");
  return 0;
}

}  // namespace

std::function<int()> AddAccuracyCommand(CLI::App& app) {
  auto options = std::make_shared<AccuracyOptions>();
  CLI::App* command = app.add_subcommand(
      "accuracy", "Analytic cases (error against run time) at a grid of settings, beside Bullet");
  command->add_option("--out-dir", options->out_dir, "Where accuracy.json, accuracy.md and accuracy.png go");
  command->add_option("--case", options->cases, "Run only these cases (repeatable)");
  command->add_option("--setting", options->settings,
                      "Run only these settings of the grid, by name as accuracy.md writes them (repeatable)");
  command->add_flag("--quick", options->quick, "Only the default setting");
  command->add_flag("--no-bullet", options->no_bullet, "Strata only");
  command
      ->add_option("--timing-runs", options->timing_runs,
                   "Passes over the grid; each run's time is the least of its passes")
      ->check(CLI::Range(1, 20));
  return [options] { return RunAccuracy(*options); };
}

}  // namespace strata::cli
