// MeshImporter: reads a level or prop mesh file through assimp (glTF/GLB, FBX, STL, DAE, ...; OBJ and PLY
// through ObjReader and PlyReader) into one welded, triangulated triangle list with the scene graph's
// transforms applied. Every file an import opens, the named one and those it refers to, passes the input
// policy (InputFile), and an import that runs past a minute is abandoned. Stateless; safe to call from any
// thread (each call owns its assimp importer).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "physics/core/Result.h"
#include "physics/shapes/TriangleMeshShape.h"

namespace strata {

/// Triangles of an imported file in the file's units, Y up.
struct ImportedMesh {
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
};

/// How to bring a file into Strata's frame.
struct MeshImportOptions {
  float scale = 1.0f;  ///< multiplies every coordinate (e.g. 0.01 for centimetre files)
  bool z_up = false;   ///< the file is Z-up; rotate it to Y-up
};

/// Mesh files larger than this are refused before assimp reads them.
constexpr std::uint64_t kMaxMeshFileBytes = std::uint64_t{1} << 30;

/// Loads every mesh of `path`. Fails (naming the file and why) for a missing, unsupported or corrupt file,
/// anything but a regular file (it or a file it refers to), files over kMaxMeshFileBytes together, counts
/// declared beyond what the file holds, a file with no triangles, or non-finite vertices.
Result<ImportedMesh> ImportMesh(const std::filesystem::path& path, const MeshImportOptions& options = {});

}  // namespace strata
