// DeclaredCounts: checks the counts and lengths a glTF file declares against what the file holds, before
// assimp allocates for them (a 3 KB GLB whose header claims a 3.9 GB JSON chunk, an accessor of a billion
// elements). Other formats pass (PlyReader checks PLY counts itself). Pure functions; any thread.
#pragma once

#include <cstdint>
#include <filesystem>

#include "physics/core/Result.h"

namespace strata {

/// Fails, naming the file and the count, when `path` (of `file_size` bytes) is a GLB or glTF file that
/// declares more than it holds, or whose JSON StrictJson refuses.
Status CheckDeclaredCounts(const std::filesystem::path& path, std::uint64_t file_size);

}  // namespace strata
