// `strata bench-navmesh [LEVEL]`: per-tile gather and Recast cost, gather overhead, request-to-ready time
// and the physics step with and without navmesh jobs (see tools/bench/NavMeshBench.h).
#include "tools/bench/NavMeshBench.h"
#include "tools/cli/Commands.h"
#include "tools/cli/NavMeshOptions.h"

namespace strata::cli {

std::function<int()> AddNavMeshBenchCommand(CLI::App& app) {
  auto options = std::make_shared<bench::NavMeshBenchOptions>();
  options->level = DefaultLevelPath();
  CLI::App* command = app.add_subcommand("bench-navmesh", "background navmesh cost against the physics step");
  command->add_option("level", options->level, "level mesh file")->capture_default_str();
  command->add_option("--crates", options->crates, "dynamic bodies stepping")->capture_default_str();
  command->add_option("--repeats", options->repeats, "builds per tile")->capture_default_str();
  command->add_option("--blocks", options->step_blocks, "alternating step blocks")->capture_default_str();
  command->add_option("--steps", options->steps_per_block, "steps per block")->capture_default_str();
  command->add_option("--threads", options->physics_threads, "physics threads")->capture_default_str();
  command->add_option("--navmesh-threads", options->navmesh_threads, "navmesh threads")
      ->capture_default_str();
  AddNavMeshSettingsOptions(*command, options->settings);
  return [options] { return bench::RunNavMeshBench(*options); };
}

}  // namespace strata::cli
