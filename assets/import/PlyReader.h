// PlyReader: Stanford PLY meshes (ASCII, binary little- and big-endian) read by Strata itself, not assimp,
// whose PLY reader crashed or spun on damaged files (a missing last newline, a binary body one byte short,
// a header without end_header). Every count is checked against the bytes there are before anything is
// allocated for it, and reading is one pass over the file. Pure function; any thread.
#pragma once

#include <filesystem>
#include <string_view>

#include "assets/import/MeshImporter.h"

namespace strata {

/// Whether `bytes` start as a PLY file does ("ply" and a line end).
bool LooksLikePly(std::string_view bytes);

/// The vertices (x, y, z of the "vertex" element, as the file has them) and the faces (the "face" element's
/// vertex_indices or vertex_index list, fanned into triangles) of the PLY file `bytes`. Elements it does not
/// use are skipped. Fails, naming `path`, the element and the byte where it can, for any malformed file.
Result<ImportedMesh> ReadPly(std::string_view bytes, const std::filesystem::path& path);

}  // namespace strata
