// `strata bench-navmesh [LEVEL]`: per-tile gather and Recast cost, gather overhead, request-to-ready time
// and the physics step with and without navmesh jobs (see tools/bench/NavMeshBench.h).
// `strata bench-navmesh --open-world`: agents walking across a generated world larger than the tile budget
// (see tools/bench/OpenWorldBench.h).
#include "navmesh/NavMeshService.h"
#include "tools/bench/NavMeshBench.h"
#include "tools/bench/OpenWorldBench.h"
#include "tools/cli/Commands.h"
#include "tools/cli/NavMeshOptions.h"
#include "tools/cli/Validators.h"

namespace strata::cli {

std::function<int()> AddNavMeshBenchCommand(CLI::App& app) {
  auto options = std::make_shared<bench::NavMeshBenchOptions>();
  options->level = DefaultLevelPath();
  CLI::App* command = app.add_subcommand("bench-navmesh", "background navmesh cost against the physics step");
  command->add_option("level", options->level, "level mesh file")->capture_default_str();
  command->add_option("--crates", options->crates, "dynamic bodies stepping")
      ->check(CountIn(0, 50000, "--crates"))
      ->capture_default_str();
  command->add_option("--repeats", options->repeats, "builds per tile")
      ->check(CountIn(1, 1000, "--repeats"))
      ->capture_default_str();
  command->add_option("--blocks", options->step_blocks, "alternating step blocks")
      ->check(CountIn(2, 1000, "--blocks"))
      ->capture_default_str();
  command->add_option("--steps", options->steps_per_block, "steps per block")
      ->check(CountIn(1, 100000, "--steps"))
      ->capture_default_str();
  command->add_option("--threads", options->physics_threads, "physics threads")
      ->check(CountIn(1, kMaxThreads, "--threads"))
      ->capture_default_str();
  command->add_option("--navmesh-threads", options->navmesh_threads, "navmesh threads")
      ->check(CountIn(1, kMaxNavMeshThreads, "--navmesh-threads"))
      ->capture_default_str();
  command->add_option("--json", options->json, "Also write the figures to this JSON file");
  AddNavMeshSettingsOptions(*command, options->settings);

  auto open_world = std::make_shared<bench::OpenWorldOptions>();
  auto open_world_on = std::make_shared<bool>(false);
  command->add_flag("--open-world", *open_world_on,
                    "walk agents across a generated world instead (the options below; --threads and "
                    "--navmesh-threads apply)");
  command->add_option("--world-size", open_world->world_size, "open world: side (m)")
      ->check(CLI::Range(100.0f, 100000.0f))
      ->capture_default_str();
  command->add_option("--bodies", open_world->bodies, "open world: bodies, the ground included")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command->add_option("--agents", open_world->agents, "open world: agents (squads of 8)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  command->add_option("--walk", open_world->walk_distance, "open world: each agent's walk (m)")
      ->check(CLI::Range(1.0f, 1.0e6f))
      ->capture_default_str();
  command->add_option("--agent-speed", open_world->agent_speed, "open world: m/s")
      ->check(CLI::Range(0.1f, 1000.0f))
      ->capture_default_str();
  command->add_option("--tile-budget", open_world->tile_budget, "open world: the service's max_tiles")
      ->check(CLI::Range(1, navmesh::NavMeshService::kMaxTiles))
      ->capture_default_str();
  command
      ->add_option(
          "--profile-cost-tiles", open_world->profile_cost_tiles,
          "open world: tiles a side of the block built for three profiles from one gather and with a "
          "service each (0: skip)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  command
      ->add_option("--profile-cost-runs", open_world->profile_cost_runs, "open world: alternated runs of it")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  command
      ->add_option("--crowd-agents", open_world->crowd_agents,
                   "open world: crowd sizes whose update is timed on a built block (0: none)")
      ->check(CLI::Range(0, 65536))
      ->capture_default_str();
  return [options, open_world, open_world_on] {
    std::erase(open_world->crowd_agents, 0);
    if (!*open_world_on) return bench::RunNavMeshBench(*options);
    open_world->physics_threads = options->physics_threads;
    open_world->navmesh_threads = options->navmesh_threads;
    open_world->settings = options->settings;
    open_world->json = options->json;
    return bench::RunOpenWorldBench(*open_world);
  };
}

}  // namespace strata::cli
