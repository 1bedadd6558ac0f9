// AccuracyReport: runs the accuracy cases over the settings grid on each engine and writes what came out:
// accuracy.json (every run), a Markdown table (error, wall ms, pass/fail per case and setting) and a PNG
// of error against run time per case with each engine's Pareto front. One thread.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/accuracy/AccuracyCases.h"
#include "tools/bench/Progress.h"

namespace strata::accuracy {

/// One case run at one setting on one engine.
struct AccuracyRecord {
  std::string case_name;
  std::string setting;
  std::string engine;
  double error = 0.0;
  double tolerance = 0.0;
  double wall_ms = 0.0;  ///< stepping time only, the least over the timing runs
  bool finite = true;
  bool passed = false;
  bool is_default = false;  ///< the world's default setting
};

/// Runs every case at every setting on every engine (a fresh engine per run), the whole grid `timing_runs`
/// times; each run's time is its least.
Result<std::vector<AccuracyRecord>> RunAccuracySuite(const std::vector<AccuracyCase>& cases,
                                                     const std::vector<AccuracySetting>& settings,
                                                     const std::vector<std::string>& engines,
                                                     int timing_runs = 1,
                                                     const bench::ProgressCallback& progress = {});

/// Per case and engine: the runs no other run of the same engine beats on both error and time.
std::vector<AccuracyRecord> ParetoFront(const std::vector<AccuracyRecord>& records,
                                        const std::string& case_name, const std::string& engine);
/// Whether Strata's front is at or below Bullet's for a case: for every point of Bullet's front, some
/// Strata run is no slower and no less accurate (errors within `floor` count as equal).
bool FrontAtOrBelow(const std::vector<AccuracyRecord>& strata, const std::vector<AccuracyRecord>& bullet,
                    double floor);

/// A point of Bullet's front that no Strata run covers, and the cheapest Strata run that is at least as
/// accurate (none when no Strata run is).
struct FrontGap {
  AccuracyRecord bullet;
  std::optional<AccuracyRecord> strata;
};
/// Why FrontAtOrBelow is false for a case: every uncovered point of Bullet's front (empty when it is true).
std::vector<FrontGap> FrontGaps(const std::vector<AccuracyRecord>& records, const std::string& case_name,
                                double floor);
/// Whether there are gaps and Bullet's run fails the case's tolerance in every one of them (the uncovered
/// points are cheap but wrong answers), which the report states beside the verdict; it does not change it.
bool OnlyFailingRunsUncovered(const std::vector<FrontGap>& gaps);

Status WriteAccuracyJson(const std::vector<AccuracyRecord>& records, const std::vector<AccuracyCase>& cases,
                         const std::filesystem::path& path);
Status WriteAccuracyMarkdown(const std::vector<AccuracyRecord>& records,
                             const std::vector<AccuracyCase>& cases, const std::filesystem::path& path);
Status WriteAccuracyPlot(const std::vector<AccuracyRecord>& records, const std::vector<AccuracyCase>& cases,
                         const std::filesystem::path& path);

}  // namespace strata::accuracy
