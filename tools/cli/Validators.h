// Validators: CLI11 checks for options that CLI11's own miss (its Range and PositiveNumber let NaN through:
// every comparison with NaN is false), the limits every count option has, and the check that no two of a
// command's files are the same file. Used while the CLI parses and starts a command, on the main thread.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "navmesh/NavMeshService.h"
#include "physics/core/Result.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::cli {

/// The most threads any --threads option takes: far above the machines we run on, far below what makes
/// thread creation fail.
constexpr long kMaxThreads = PhysicsSystemConfig::kMaxThreads;
/// The most background navmesh threads (NavMeshServiceConfig's limit).
constexpr long kMaxNavMeshThreads = navmesh::NavMeshServiceConfig::kMaxWorkerThreads;

/// A finite number in [min, max].
CLI::Validator FiniteIn(double min, double max);
/// A whole number in [min, max]; the message names the limit (`what`: "threads", "crates", ...).
CLI::Validator CountIn(long min, long max, const std::string& what);

/// Fails when two of `files` ((option, path) pairs; empty paths are skipped) name the same file, directly or
/// through links: one output would overwrite the other, or an output its input.
Status DistinctFiles(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace strata::cli
