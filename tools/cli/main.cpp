// strata: run scenes, benchmarks and (later) navmesh jobs from the command line.
#include <iostream>

#include "tools/cli/Commands.h"

int main(int argc, char** argv) {
  CLI::App app{"Strata: multithreaded rigid-body physics with a background navmesh service"};
  app.require_subcommand(1);
  const auto simulate = strata::cli::AddSimulateCommand(app);
  const auto bench = strata::cli::AddBenchCommand(app);
  const auto bench_broadphase = strata::cli::AddBroadPhaseBenchCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? 0 : 2;
  }
  if (app.got_subcommand("simulate")) return simulate();
  if (app.got_subcommand("bench")) return bench();
  if (app.got_subcommand("bench-broadphase")) return bench_broadphase();
  return 2;
}
