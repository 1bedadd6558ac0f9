#include "tools/view/ViewerFolder.h"

#include <cmath>
#include <cstdio>
#include <set>
#include <system_error>

#include "assets/import/GltfExporter.h"
#include "physics/core/InputFile.h"
#include "physics/core/OutputFile.h"
#include "tools/view/ViewerAssets.h"

namespace strata::view {

namespace {

constexpr float kNavmeshLift = 0.02f;  // above the level it lies on, so it is not hidden in it
constexpr float kPathLift = 0.1f;

/// The vertex's position relative to `origin`, subtracted in double: a browser draws in float, which a level
/// kilometres from the world origin would otherwise turn into a jumble (float steps of 0.5 m at 5,000 km).
Vec3 PointAt(const nlohmann::json& numbers, std::size_t vertex, const Vec3d& origin) {
  return {static_cast<float>(numbers[3 * vertex].get<double>() - origin.x()),
          static_cast<float>(numbers[3 * vertex + 1].get<double>() - origin.y()),
          static_cast<float>(numbers[3 * vertex + 2].get<double>() - origin.z())};
}

/// Where the page's coordinates start: the middle of the static geometry (or of the bodies' first poses, or
/// the agents), in whole tiles on x and z when there are tiles, so a tile's colour and border need no offset
/// of their own, and whole metres on y.
Vec3d PageOrigin(const nlohmann::json& recording) {
  double low[3] = {1e300, 1e300, 1e300}, high[3] = {-1e300, -1e300, -1e300};
  const auto take = [&](const nlohmann::json& numbers, std::size_t stride) {
    for (std::size_t i = 0; i + 3 <= numbers.size(); i += stride)
      for (std::size_t k = 0; k < 3; ++k) {
        low[k] = std::min(low[k], numbers[i + k].get<double>());
        high[k] = std::max(high[k], numbers[i + k].get<double>());
      }
  };
  take(recording["static"]["positions"], 3);
  if (low[0] > high[0] && !recording["frames"].empty()) take(recording["frames"][0]["poses"], 7);
  if (low[0] > high[0])
    for (const nlohmann::json& agent : recording["agents"]) take(agent["position"], 3);
  if (low[0] > high[0]) return Vec3d::Zero();
  Vec3d centre;
  for (int k = 0; k < 3; ++k) centre[k] = std::round(0.5 * (low[k] + high[k]));
  if (recording.contains("tiles")) {
    const double size = recording["tiles"]["size"].get<double>();
    centre.x() = std::floor(centre.x() / size) * size;
    centre.z() = std::floor(centre.z() / size) * size;
  }
  return centre;
}

std::string HexColour(const Vec4& colour) {
  char text[8];
  const auto byte = [](float value) {
    return static_cast<int>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
  };
  std::snprintf(text, sizeof(text), "#%02x%02x%02x", byte(colour.x()), byte(colour.y()), byte(colour.z()));
  return text;
}

std::string Base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t left = bytes.size() - i;
    std::uint32_t chunk = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (left > 1) chunk |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
    if (left > 2) chunk |= static_cast<std::uint8_t>(bytes[i + 2]);
    out.push_back(kAlphabet[(chunk >> 18) & 63]);
    out.push_back(kAlphabet[(chunk >> 12) & 63]);
    out.push_back(left > 1 ? kAlphabet[(chunk >> 6) & 63] : '=');
    out.push_back(left > 2 ? kAlphabet[chunk & 63] : '=');
  }
  return out;
}

/// Profile `profile`'s navmesh (when recorded) and the paths of its agents, moved to `origin`.
SceneGeometry ProfileGeometry(const nlohmann::json& recording, std::size_t profile, const Vec3d& origin) {
  SceneGeometry geometry;
  const nlohmann::json& navmeshes =
      recording.contains("navmeshes") ? recording["navmeshes"] : nlohmann::json();
  if (profile < navmeshes.size()) {
    const nlohmann::json& surface = navmeshes[profile];
    for (std::size_t v = 0; v < surface["positions"].size() / 3; ++v)
      geometry.navmesh.push_back(PointAt(surface["positions"], v, origin));
    for (const nlohmann::json& island : surface["island"]) geometry.island.push_back(island.get<int>());
  }
  for (const nlohmann::json& agent : recording["agents"]) {
    if (agent.value("profile", std::size_t{0}) != profile) continue;
    std::vector<Vec3>& path = geometry.paths.emplace_back();
    for (const nlohmann::json& point : agent["path"]) path.push_back(PointAt(point, 0, origin));
  }
  return geometry;
}

/// scene.glb's layers from the recording, moved to `origin`: the level, then each profile's navmesh and
/// paths ("navmesh" and "paths" for the first profile, "navmesh_1", "paths_1" for the second, ...).
std::vector<GltfLayer> RecordedSceneLayers(const nlohmann::json& recording, const Vec3d& origin,
                                           ViewerFolderSummary& summary) {
  SceneGeometry geometry = ProfileGeometry(recording, 0, origin);
  const nlohmann::json& static_mesh = recording["static"];
  for (const nlohmann::json& index : static_mesh["indices"])
    geometry.level.push_back(PointAt(static_mesh["positions"], index.get<std::size_t>(), origin));
  summary.level_triangles = geometry.level.size() / 3;
  summary.navmesh_triangles = geometry.island.size();
  for (const int island : std::set<int>(geometry.island.begin(), geometry.island.end()))
    summary.navmesh_colours.push_back(HexColour(IslandColor(island)));
  std::vector<GltfLayer> layers = SceneLayers(geometry);
  const std::size_t profiles = std::max<std::size_t>(
      1, recording.contains("profiles") ? recording["profiles"].size() : std::size_t{0});
  for (std::size_t profile = 1; profile < profiles; ++profile) {
    const std::string suffix = std::to_string(profile);
    std::vector<GltfLayer> more = SceneLayers(ProfileGeometry(recording, profile, origin));
    for (GltfLayer& layer : more) {
      if (layer.name == "level") continue;
      layer.name.append(1, '_').append(suffix);
      layers.push_back(std::move(layer));
    }
  }
  return layers;
}

/// The page's data: what it animates (the file's static layers are in scene.glb), relative to `origin`.
nlohmann::json PageData(const nlohmann::json& recording, const Vec3d& origin,
                        const ViewerFolderSummary& summary) {
  const auto shifted = [&](const nlohmann::json& point) {
    return nlohmann::json{point[0].get<double>() - origin.x(), point[1].get<double>() - origin.y(),
                          point[2].get<double>() - origin.z()};
  };
  nlohmann::json frames = recording["frames"];
  for (nlohmann::json& frame : frames) {
    for (std::size_t i = 0; i + 7 <= frame["poses"].size(); i += 7)
      for (std::size_t k = 0; k < 3; ++k)
        frame["poses"][i + k] = frame["poses"][i + k].get<double>() - origin[static_cast<Eigen::Index>(k)];
    for (const char* points : {"characters", "agents"}) {
      if (!frame.contains(points)) continue;
      for (std::size_t i = 0; i < frame[points].size(); ++i)
        frame[points][i] = frame[points][i].get<double>() - origin[static_cast<Eigen::Index>(i % 3)];
    }
  }
  nlohmann::json characters = nlohmann::json::array();
  if (recording.contains("characters"))
    for (const nlohmann::json& character : recording["characters"]) {
      nlohmann::json route = nlohmann::json::array();
      if (character.contains("route"))
        for (const nlohmann::json& point : character["route"]) route.push_back(shifted(point));
      characters.push_back({{"name", character["name"]},
                            {"radius", character["radius"]},
                            {"height", character["height"]},
                            {"route", std::move(route)}});
    }
  nlohmann::json agents = nlohmann::json::array();
  for (const nlohmann::json& agent : recording["agents"])
    agents.push_back({{"position", shifted(agent["position"])},
                      {"target", shifted(agent["target"])},
                      {"profile", agent.value("profile", 0)},
                      {"radius", agent.value("radius", 0.6)},
                      {"height", agent.value("height", 2.0)},
                      {"reached", agent.value("reached", false)}});
  nlohmann::json data = {
      {"title", recording["title"]},         {"origin", {origin.x(), origin.y(), origin.z()}},
      {"shapes", recording["shapes"]},       {"bodies", recording["bodies"]},
      {"frames", std::move(frames)},         {"agents", std::move(agents)},
      {"characters", std::move(characters)}, {"navmesh_colours", summary.navmesh_colours}};
  if (recording.contains("tiles")) data["tiles"] = recording["tiles"];
  data["profiles"] = recording.contains("profiles") ? recording["profiles"] : nlohmann::json::array();
  return data;
}

}  // namespace

std::vector<GltfLayer> SceneLayers(const SceneGeometry& geometry) {
  GltfLayer level{"level", {}, {}, {}, false};
  for (const Vec3& vertex : geometry.level) {
    level.indices.push_back(static_cast<std::uint32_t>(level.vertices.size()));
    level.vertices.push_back(vertex);
    level.colors.emplace_back(0.55f, 0.55f, 0.55f, 1.0f);
  }
  GltfLayer navmesh{"navmesh", {}, {}, {}, false};
  for (std::size_t v = 0; v < geometry.navmesh.size(); ++v) {
    navmesh.indices.push_back(static_cast<std::uint32_t>(v));
    navmesh.vertices.push_back(geometry.navmesh[v] + Vec3(0.0f, kNavmeshLift, 0.0f));
    navmesh.colors.push_back(IslandColor(geometry.island[v / 3]));
  }
  GltfLayer paths{"paths", {}, {}, {}, true};
  for (const std::vector<Vec3>& path : geometry.paths)
    for (std::size_t k = 1; k < path.size(); ++k)
      for (const Vec3& point : {path[k - 1], path[k]}) {
        paths.indices.push_back(static_cast<std::uint32_t>(paths.vertices.size()));
        paths.vertices.push_back(point + Vec3(0.0f, kPathLift, 0.0f));
        paths.colors.emplace_back(1.0f, 1.0f, 1.0f, 1.0f);  // white: no island's colour is
      }
  return {level, navmesh, paths};
}

Vec4 IslandColor(int island) {
  const float hue = std::fmod(0.61803f * static_cast<float>(island), 1.0f) * 6.0f;
  const float x = 1.0f - std::abs(std::fmod(hue, 2.0f) - 1.0f);
  const int sector = static_cast<int>(hue);
  const Vec3 rgb = sector == 0   ? Vec3(1, x, 0)
                   : sector == 1 ? Vec3(x, 1, 0)
                   : sector == 2 ? Vec3(0, 1, x)
                   : sector == 3 ? Vec3(0, x, 1)
                   : sector == 4 ? Vec3(x, 0, 1)
                                 : Vec3(1, 0, x);
  return {0.2f + 0.7f * rgb.x(), 0.2f + 0.7f * rgb.y(), 0.2f + 0.7f * rgb.z(), 1.0f};
}

Result<ViewerFolderSummary> WriteViewerFolder(const nlohmann::json& recording,
                                              const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (!std::filesystem::is_directory(folder, error))
    return MakeError(ErrorCode::kInvalidArgument, folder.string() + ": cannot create the folder");
  ViewerFolderSummary summary;
  summary.bodies = recording["bodies"].size();
  summary.agents = recording["agents"].size();
  summary.frames = recording["frames"].size();
  summary.tiles = recording.contains("tiles") ? recording["tiles"]["coords"].size() : 0;

  // scene.glb first: it is written through the exporter, then read back for data.js.
  const Vec3d origin = PageOrigin(recording);
  const std::vector<GltfLayer> layers = RecordedSceneLayers(recording, origin, summary);
  const std::filesystem::path glb = folder / "scene.glb";
  std::string glb_bytes;
  const bool any_layer = std::any_of(layers.begin(), layers.end(),
                                     [](const GltfLayer& layer) { return !layer.indices.empty(); });
  if (any_layer) {
    if (Status written = ExportGltf(layers, glb); !written) return written.error();
    Result<std::string> bytes = ReadInputFile(glb, std::uint64_t{4} << 30);
    if (!bytes) return bytes.error();
    glb_bytes = std::move(*bytes);
  }
  std::string data = "window.STRATA_VIEW = " + PageData(recording, origin, summary).dump() + ";\n";
  if (!glb_bytes.empty()) data += "window.STRATA_GLB = \"" + Base64(glb_bytes) + "\";\n";
  for (const auto& [name, text] : {std::pair<const char*, std::string>{"data.js", data},
                                   {"viewer.js", ViewerScript()},
                                   {"index.html", ViewerPage()}})
    if (Status written = WriteOutputFile(folder / name, text); !written) return written.error();
  return summary;
}

}  // namespace strata::view
