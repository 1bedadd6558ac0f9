// Command-line options shared by the commands that build navmeshes (navmesh bake, demo, bench-navmesh):
// the Recast settings, level import options and small parsing helpers. Used on the CLI's main thread.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "assets/level/LevelLoader.h"
#include "navmesh/AgentProfile.h"
#include "navmesh/NavMeshSettings.h"

namespace strata::cli {

/// Registers --cell-size, --agent-radius, ... on `command`, writing into `settings`.
void AddNavMeshSettingsOptions(CLI::App& command, navmesh::NavMeshSettings& settings);
/// Registers --profile on `command` (writing the name into `profile`).
void AddProfileOption(CLI::App& command, std::string& profile, const std::string& what);
/// The agent profile called `name` with `settings`' agent fields left out, or the agent fields of `settings`
/// when `name` is empty. Fails for an unknown name, or a name given with --agent-height, --agent-radius,
/// --max-climb, --max-slope or --max-drop on `command` (one agent, said once).
Result<std::optional<navmesh::AgentProfile>> ChosenProfile(const CLI::App& command, const std::string& name);
/// The profiles a command with several walkers builds for: those named in `names` (--profiles on `command`),
/// or one made of `settings`' agent fields when --profiles was not given but an agent option was. Fails for
/// an unknown or repeated name, or --profiles given with an agent option.
Result<std::vector<navmesh::AgentProfile>> ChosenProfiles(const CLI::App& command,
                                                          const std::vector<std::string>& names,
                                                          const navmesh::NavMeshSettings& settings);
/// Registers --scale, --z-up and --world-tile on `command`.
void AddLevelOptions(CLI::App& command, LevelLoadOptions& options);
/// Parses "x,y,z"; nullopt for anything else.
std::optional<Vec3> ParsePoint(const std::string& text);
/// Median and maximum of `values` (0, 0 when empty).
std::pair<double, double> MedianAndMax(std::vector<double> values);
/// The default level the main job and bake use when none is given: courtyard.obj in $STRATA_DATA_DIR/levels,
/// else beside the executable's install prefix (share/strata/levels), else in the source tree it was built
/// from.
std::string DefaultLevelPath();

}  // namespace strata::cli
