#include "tools/cli/NavMeshOptions.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace strata::cli {

void AddProfileOption(CLI::App& command, std::string& profile, const std::string& what) {
  command
      .add_option("--profile", profile, what + ": person, machine or critter (instead of the agent options)")
      ->check(CLI::IsMember({"person", "machine", "critter"}));
}

namespace {

constexpr const char* kAgentOptions[] = {"--agent-height", "--agent-radius", "--max-climb", "--max-slope",
                                         "--max-drop"};

/// The first agent option given on `command`, or null.
const char* GivenAgentOption(const CLI::App& command) {
  for (const char* agent_option : kAgentOptions)
    if (command.count(agent_option) > 0) return agent_option;
  return nullptr;
}

}  // namespace

Result<std::optional<navmesh::AgentProfile>> ChosenProfile(const CLI::App& command, const std::string& name) {
  if (name.empty()) return std::optional<navmesh::AgentProfile>();
  if (const char* agent_option = GivenAgentOption(command))
    return MakeError(ErrorCode::kInvalidArgument,
                     std::string("give --profile or ") + agent_option + ", not both (a profile is an agent)");
  Result<navmesh::AgentProfile> profile = navmesh::AgentProfile::Named(name);
  if (!profile) return profile.error();
  return std::optional<navmesh::AgentProfile>(*profile);
}

Result<std::vector<navmesh::AgentProfile>> ChosenProfiles(const CLI::App& command,
                                                          const std::vector<std::string>& names,
                                                          const navmesh::NavMeshSettings& settings) {
  const char* agent_option = GivenAgentOption(command);
  if (agent_option && command.count("--profiles") > 0)
    return MakeError(ErrorCode::kInvalidArgument, std::string("give --profiles or ") + agent_option +
                                                      ", not both (a profile is an agent)");
  if (agent_option) return std::vector<navmesh::AgentProfile>{navmesh::AgentProfile::FromSettings(settings)};
  if (names.empty()) return MakeError(ErrorCode::kInvalidArgument, "--profiles: name one profile or more");
  std::vector<navmesh::AgentProfile> profiles;
  for (const std::string& name : names) {
    Result<navmesh::AgentProfile> profile = navmesh::AgentProfile::Named(name);
    if (!profile) return profile.error();
    for (const navmesh::AgentProfile& earlier : profiles)
      if (earlier.name == name)
        return MakeError(ErrorCode::kInvalidArgument, "--profiles: '" + name + "' is named twice");
    profiles.push_back(*profile);
  }
  return profiles;
}

void AddNavMeshSettingsOptions(CLI::App& command, navmesh::NavMeshSettings& settings) {
  command.add_option("--cell-size", settings.cell_size, "horizontal voxel size (m)")->capture_default_str();
  command.add_option("--cell-height", settings.cell_height, "vertical voxel size (m)")->capture_default_str();
  command.add_option("--tile-cells", settings.tile_cells, "cells per tile side")->capture_default_str();
  command.add_option("--agent-height", settings.agent_height, "agent height (m)")->capture_default_str();
  command.add_option("--agent-radius", settings.agent_radius, "agent radius (m)")->capture_default_str();
  command.add_option("--max-climb", settings.agent_max_climb, "highest walkable step (m)")
      ->capture_default_str();
  command.add_option("--max-slope", settings.agent_max_slope, "steepest walkable slope (degrees)")
      ->capture_default_str();
  command
      .add_option("--max-drop", settings.agent_max_drop, "deepest ledge dropped down (m; 0: no drop links)")
      ->capture_default_str();
  command.add_option("--region-min", settings.region_min_size, "smallest region kept (cells, squared)")
      ->capture_default_str();
  command
      .add_option("--region-merge", settings.region_merge_size, "regions below this merge (cells, squared)")
      ->capture_default_str();
  command.add_option("--edge-max-len", settings.edge_max_length, "longest contour edge (m)")
      ->capture_default_str();
  command.add_option("--edge-max-error", settings.edge_max_error, "contour simplification error (cells)")
      ->capture_default_str();
  command.add_option("--verts-per-poly", settings.verts_per_poly, "3..6")->capture_default_str();
  command.add_option("--detail-sample-dist", settings.detail_sample_distance, "detail sampling (cells)")
      ->capture_default_str();
  command.add_option("--detail-max-error", settings.detail_sample_max_error, "detail height error (cells)")
      ->capture_default_str();
}

void AddLevelOptions(CLI::App& command, LevelLoadOptions& options) {
  command.add_option("--scale", options.import.scale, "multiplies every coordinate of the level file")
      ->capture_default_str();
  command.add_flag("--z-up", options.import.z_up, "the level file is Z-up");
  command.add_option("--world-tile", options.world_tile_size, "side of the level's physics chunks (m)")
      ->capture_default_str();
  command
      .add_option("--terrain-cell", options.height_map.cell_size,
                  "a .png terrain level: metres between pixels")
      ->capture_default_str();
  command.add_option("--terrain-low", options.height_map.low, "a .png terrain level: height of black (m)")
      ->capture_default_str();
  command.add_option("--terrain-high", options.height_map.high, "a .png terrain level: height of white (m)")
      ->capture_default_str();
}

std::optional<Vec3> ParsePoint(const std::string& text) {
  std::istringstream stream(text);
  Vec3 point;
  char comma1 = 0, comma2 = 0;
  if (!(stream >> point.x() >> comma1 >> point.y() >> comma2 >> point.z()) || comma1 != ',' || comma2 != ',')
    return std::nullopt;
  std::string rest;
  if (stream >> rest || !IsFinite(point)) return std::nullopt;
  return point;
}

std::pair<double, double> MedianAndMax(std::vector<double> values) {
  if (values.empty()) return {0.0, 0.0};
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  const double median = values.size() % 2 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
  return {median, values.back()};
}

namespace {

// <prefix>/share/strata/levels for a binary at <prefix>/bin/strata; empty when the binary cannot be found.
std::filesystem::path InstalledLevels() {
  std::error_code error;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return {};
  return executable.parent_path().parent_path() / "share" / "strata" / "levels";
}

}  // namespace

std::string DefaultLevelPath() {
  const std::filesystem::path installed = InstalledLevels();
  std::vector<std::filesystem::path> folders;
  if (const char* data = std::getenv("STRATA_DATA_DIR"); data != nullptr && *data != '\0')
    folders.push_back(std::filesystem::path(data) / "levels");
  if (!installed.empty()) folders.push_back(installed);
  folders.emplace_back(STRATA_LEVELS_DIR);  // the source tree this binary was built from
  for (const std::filesystem::path& folder : folders) {
    std::error_code error;
    if (std::filesystem::is_regular_file(folder / "courtyard.obj", error))
      return (folder / "courtyard.obj").string();
  }
  // None there: the installed place, so that the loader's error says where the level was expected.
  return ((installed.empty() ? folders.back() : installed) / "courtyard.obj").string();
}

}  // namespace strata::cli
