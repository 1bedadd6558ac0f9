// strata: the main job (demo), scenes, navmesh bakes and path queries, level generation, benchmarks and the
// browser viewer.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "tools/cli/Commands.h"

namespace {

// Whether everything printed reached standard output: a full disk or a closed pipe there is a failed run,
// not a silent short report.
bool StandardOutputWritten() {
  std::cout.flush();
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  if (flushed && !std::ferror(stdout) && std::cout.good()) return true;
  std::fprintf(stderr, "strata: cannot write to standard output%s%s\n", errno ? ": " : "",
               errno ? std::strerror(errno) : "");
  return false;
}

int Run(const std::function<int()>& command) {
  const int status = command();
  if (!StandardOutputWritten()) return status == 0 ? 1 : status;
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Strata: multithreaded rigid-body physics with a background navmesh service"};
  app.require_subcommand(1);
  const auto simulate = strata::cli::AddSimulateCommand(app);
  const auto bench = strata::cli::AddBenchCommand(app);
  const auto bench_broadphase = strata::cli::AddBroadPhaseBenchCommand(app);
  const auto bench_navmesh = strata::cli::AddNavMeshBenchCommand(app);
  const auto bench_gameplay = strata::cli::AddGameplayBenchCommand(app);
  const auto demo = strata::cli::AddDemoCommand(app);
  const auto navmesh = strata::cli::AddNavMeshCommand(app);
  const auto level = strata::cli::AddLevelCommand(app);
  const auto accuracy = strata::cli::AddAccuracyCommand(app);
  const auto view = strata::cli::AddViewCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? 0 : 2;
  }
  if (app.got_subcommand("simulate")) return Run(simulate);
  if (app.got_subcommand("bench")) return Run(bench);
  if (app.got_subcommand("bench-broadphase")) return Run(bench_broadphase);
  if (app.got_subcommand("bench-navmesh")) return Run(bench_navmesh);
  if (app.got_subcommand("bench-gameplay")) return Run(bench_gameplay);
  if (app.got_subcommand("demo")) return Run(demo);
  if (app.got_subcommand("navmesh")) return Run(navmesh);
  if (app.got_subcommand("level")) return Run(level);
  if (app.got_subcommand("accuracy")) return Run(accuracy);
  if (app.got_subcommand("view")) return Run(view);
  return 2;
}
