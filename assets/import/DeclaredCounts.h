// DeclaredCounts: checks the counts and lengths a mesh file declares against what the file holds, before
// assimp allocates for them (a 227-byte PLY declaring a billion vertices, a 3 KB GLB whose header claims a
// 3.9 GB JSON chunk). Formats without such declarations pass. Pure functions; any thread.
#pragma once

#include <cstdint>
#include <filesystem>

#include "physics/core/Result.h"

namespace strata {

/// Fails, naming the file and the count, when `path` (of `file_size` bytes) is a PLY, GLB or glTF file that
/// declares more than it holds.
Status CheckDeclaredCounts(const std::filesystem::path& path, std::uint64_t file_size);

}  // namespace strata
