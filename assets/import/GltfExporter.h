// GltfExporter: writes named layers of coloured triangles and lines (a level, its navmesh by island, agents'
// paths) as one binary glTF 2 file (.glb) through assimp's exporter, which engines, viewers and assimp's
// importer load. The file is written whole or not at all (WriteOutputFile). Stateless; safe from any thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata {

/// One mesh of the file: triangles (3 indices each) or line segments (2 each), Y-up metres.
struct GltfLayer {
  std::string name;  ///< the mesh's and its node's name in the file
  std::vector<Vec3> vertices;
  std::vector<Vec4> colors;  ///< RGBA 0..1 per vertex, or empty for none
  std::vector<std::uint32_t> indices;
  bool lines = false;
};

/// Writes `layers` (those with no index are left out) to `path` as glTF 2 binary. Errors for a non-finite
/// vertex, an index past the vertices, an index count that is not whole triangles or segments, colours that
/// are not one per vertex, nothing to write, or a failed write.
Status ExportGltf(const std::vector<GltfLayer>& layers, const std::filesystem::path& path);

}  // namespace strata
