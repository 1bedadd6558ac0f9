// ObjReader: Wavefront OBJ geometry read by Strata itself, not assimp, whose OBJ reader (Debian's 5.2)
// crashed on faces naming vertices the file never gives. Only what a level's collision needs is read:
// vertices (`v`) and faces (`f`, any of the i, i/t, i//n, i/t/n forms, negative indices counting back),
// fanned into triangles; materials, groups, normals, texture coordinates, lines and points are skipped, so a
// `mtllib` is never opened. One pass; every index checked. Pure function; any thread.
#pragma once

#include <filesystem>
#include <string_view>

#include "assets/import/MeshImporter.h"

namespace strata {

/// The vertices (as the file has them) and triangles of the OBJ file `bytes`. Fails, naming `path` and the
/// line, for a vertex without three numbers, a face index of 0 or past the vertices, or a face of fewer than
/// three vertices.
Result<ImportedMesh> ReadObj(std::string_view bytes, const std::filesystem::path& path);

}  // namespace strata
