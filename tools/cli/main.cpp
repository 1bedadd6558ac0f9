// strata: the main job (demo), scenes, navmesh bakes and path queries, level generation, benchmarks and the
// browser viewer.
#include <iostream>

#include "tools/cli/Commands.h"

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
  if (app.got_subcommand("simulate")) return simulate();
  if (app.got_subcommand("bench")) return bench();
  if (app.got_subcommand("bench-broadphase")) return bench_broadphase();
  if (app.got_subcommand("bench-navmesh")) return bench_navmesh();
  if (app.got_subcommand("bench-gameplay")) return bench_gameplay();
  if (app.got_subcommand("demo")) return demo();
  if (app.got_subcommand("navmesh")) return navmesh();
  if (app.got_subcommand("level")) return level();
  if (app.got_subcommand("accuracy")) return accuracy();
  if (app.got_subcommand("view")) return view();
  return 2;
}
