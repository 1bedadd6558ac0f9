// HeightMapImporter: terrain heights from files, for HeightFieldShape: grey PNG pictures (8 or 16 bits, black
// to white spread over a height range, one sample a pixel, picture rows along +z) and raw grids of
// little-endian 32-bit floats (NaN for a hole). Stateless; safe to call from any thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "physics/core/Result.h"

namespace strata {

/// A grid of heights, row after row (`columns` per row).
struct HeightMap {
  std::uint32_t columns = 0;
  std::uint32_t rows = 0;
  std::vector<float> heights;
};

/// How a height-map picture becomes terrain.
struct HeightMapImportOptions {
  float cell_size = 1.0f;  ///< metres between samples
  float low = 0.0f;        ///< height of black (m)
  float high = 1.0f;       ///< height of white (m)
  Status Validate() const;
};

/// Whether `path` names a height-map picture (a .png file) rather than a mesh.
bool IsHeightMapPicture(const std::filesystem::path& path);

/// The grey levels of a PNG picture spread from `low` (black) to `high` (white). Fails, naming the file, for
/// a missing or non-regular file, one that is not a PNG, or a picture outside 2 x 2 to
/// HeightFieldShape::kMaxSamples pixels (checked from its header, before it is decoded).
Result<HeightMap> ImportHeightMapPicture(const std::filesystem::path& path, float low, float high);

/// `columns` x `rows` raw floats. Fails, naming the file, when its size is not exactly that many floats.
Result<HeightMap> ImportRawHeights(const std::filesystem::path& path, std::uint32_t columns,
                                   std::uint32_t rows);

}  // namespace strata
