// The subcommands of the `strata` CLI; each registers its options on a CLI11 app and returns an exit code.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace strata::cli {

/// Adds `simulate` to `app`; the returned function runs it once parsing has succeeded.
std::function<int()> AddSimulateCommand(CLI::App& app);
/// Adds `bench` to `app`.
std::function<int()> AddBenchCommand(CLI::App& app);
/// Adds `bench-broadphase` to `app`.
std::function<int()> AddBroadPhaseBenchCommand(CLI::App& app);
/// Adds `bench-navmesh` to `app`.
std::function<int()> AddNavMeshBenchCommand(CLI::App& app);
/// Adds `bench-gameplay` (shape casts, contact events' cost, the character's update) to `app`.
std::function<int()> AddGameplayBenchCommand(CLI::App& app);
/// Adds `demo` (the main job) to `app`.
std::function<int()> AddDemoCommand(CLI::App& app);
/// Adds `navmesh bake` and `navmesh path` to `app`.
std::function<int()> AddNavMeshCommand(CLI::App& app);
/// Adds `accuracy` (analytic cases against run time, beside Bullet) to `app`.
std::function<int()> AddAccuracyCommand(CLI::App& app);
/// Adds `level generate` and `level field` to `app`.
std::function<int()> AddLevelCommand(CLI::App& app);
/// Adds `view` (a recorded run as a browser page, optionally served on localhost) to `app`.
std::function<int()> AddViewCommand(CLI::App& app);

}  // namespace strata::cli
