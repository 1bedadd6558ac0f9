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

}  // namespace strata::cli
