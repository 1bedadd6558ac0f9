// MeshExporter: writes a triangle list to a file through assimp (OBJ, glTF/GLB, FBX, PLY, STL, DAE), for
// the level generator and for tests that round-trip every format. Stateless; safe from any thread.
#pragma once

#include <filesystem>
#include <string>

#include "assets/import/MeshImporter.h"

namespace strata {

/// Writes `mesh` (Y-up, metres) to `path` in assimp's export format `format` ("obj", "glb2", "gltf2",
/// "fbx", "ply", "plyb", "stl", "collada", ...). With `z_up`, the file gets Z-up coordinates (what
/// ImportMesh with z_up = true reads back to the same mesh).
Status ExportMesh(const ImportedMesh& mesh, const std::filesystem::path& path, const std::string& format,
                  bool z_up = false);

}  // namespace strata
