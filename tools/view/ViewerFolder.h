// ViewerFolder: turns a recording (Recording.h) into the folder `strata view` writes: index.html, viewer.js
// (three.js and the viewer), scene.glb (the level, the navmesh coloured by island, the agents' paths) and
// data.js (the recording's frames, bodies, tiles and agents, and scene.glb again as base64, so the page works
// opened from disk). Positions in the page are relative to an origin in the middle of the level (data.js
// names it), so a level far from the world origin draws as well as one at it. Every file is written whole
// or not at all. Safe from any thread.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "assets/import/GltfExporter.h"
#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata::view {

/// A colour per navmesh island that neighbours in number tell apart (RGBA 0..1): hues a golden-ratio turn
/// apart. The demo's scene.glb and the viewer use the same.
Vec4 IslandColor(int island);

/// What scene.glb shows: the level as triangles (3 points each), the navmesh's triangles with one island
/// each, and the agents' paths.
struct SceneGeometry {
  std::vector<Vec3> level;
  std::vector<Vec3> navmesh;
  std::vector<int> island;  ///< per navmesh triangle
  std::vector<std::vector<Vec3>> paths;
};

/// The layers of scene.glb (the viewer's, and the demo's own): the level grey, the navmesh by island (2 cm
/// above the level it lies on), the paths as white lines.
std::vector<GltfLayer> SceneLayers(const SceneGeometry& geometry);

/// What the folder holds.
struct ViewerFolderSummary {
  std::size_t level_triangles = 0;
  std::size_t navmesh_triangles = 0;
  std::size_t bodies = 0;
  std::size_t agents = 0;
  std::size_t frames = 0;
  std::size_t tiles = 0;
  /// The islands' colours as the page draws them ("#rrggbb").
  std::vector<std::string> navmesh_colours;
};

/// Writes the viewer for `recording` (checked by ReadRecording) into `folder`, creating it.
Result<ViewerFolderSummary> WriteViewerFolder(const nlohmann::json& recording,
                                              const std::filesystem::path& folder);

}  // namespace strata::view
