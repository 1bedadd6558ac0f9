// InputFile: how every loader reads a file it was given (scenes, meshes, navmeshes). One policy for all of
// them: regular files only (a directory, device, pipe or socket is refused before anything is read, so
// /dev/zero or a FIFO cannot hang a tool), a size limit per kind of file, and errors that name the file.
// Pure functions; any thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "physics/core/Result.h"

namespace strata {

/// Checks that `path` is a regular file of at most `max_bytes` and returns its size.
Result<std::uint64_t> CheckInputFile(const std::filesystem::path& path, std::uint64_t max_bytes);

/// The whole of `path` (checked as CheckInputFile does, on the opened file itself, so a file swapped for a
/// pipe after the check is still refused). Errors are kParseError and start with the path.
Result<std::string> ReadInputFile(const std::filesystem::path& path, std::uint64_t max_bytes);

}  // namespace strata
