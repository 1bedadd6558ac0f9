#include "assets/import/HeightMapImporter.h"

#include <stb/stb_image.h>

#include <cmath>
#include <cstring>
#include <string>

#include "physics/core/InputFile.h"
#include "physics/shapes/HeightFieldShape.h"

namespace strata {

namespace {

// Neither form of a height map is larger than the heights it holds as floats.
constexpr std::uint64_t kMaxHeightMapBytes = HeightFieldShape::kMaxSamples * sizeof(float);

Error FileError(const std::filesystem::path& path, const std::string& why) {
  return MakeError(ErrorCode::kParseError, path.string() + ": " + why);
}

}  // namespace

Status HeightMapImportOptions::Validate() const {
  if (!std::isfinite(cell_size) || cell_size <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "height map: cell size must be a positive finite number");
  if (!std::isfinite(low) || !std::isfinite(high))
    return MakeError(ErrorCode::kInvalidArgument, "height map: the height range must be finite");
  return Status::Ok();
}

bool IsHeightMapPicture(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".png";
}

Result<HeightMap> ImportHeightMapPicture(const std::filesystem::path& path, float low, float high) {
  const Result<std::string> bytes = ReadInputFile(path, kMaxHeightMapBytes);
  if (!bytes) return bytes.error();
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes->data());
  const int length = static_cast<int>(bytes->size());
  int width = 0, height = 0, channels = 0;
  // The size first: a small file can declare a picture far larger than a height field may be.
  if (!stbi_info_from_memory(data, length, &width, &height, &channels))
    return FileError(path, std::string("not a PNG picture (") + stbi_failure_reason() + ")");
  if (width < 2 || height < 2 ||
      static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > HeightFieldShape::kMaxSamples)
    return FileError(path, "a " + std::to_string(width) + " x " + std::to_string(height) +
                               " picture is outside 2 x 2 to " +
                               std::to_string(HeightFieldShape::kMaxSamples) + " samples");
  stbi_us* grey = stbi_load_16_from_memory(data, length, &width, &height, &channels, 1);
  if (grey == nullptr) return FileError(path, stbi_failure_reason());
  HeightMap map;
  map.columns = static_cast<std::uint32_t>(width);
  map.rows = static_cast<std::uint32_t>(height);
  map.heights.resize(static_cast<std::size_t>(map.columns) * map.rows);
  for (std::size_t i = 0; i < map.heights.size(); ++i)
    map.heights[i] = low + (high - low) * (static_cast<float>(grey[i]) / 65535.0f);
  stbi_image_free(grey);
  return map;
}

Result<HeightMap> ImportRawHeights(const std::filesystem::path& path, std::uint32_t columns,
                                   std::uint32_t rows) {
  const std::uint64_t expected = static_cast<std::uint64_t>(columns) * rows * sizeof(float);
  if (expected > kMaxHeightMapBytes)
    return FileError(path, std::to_string(columns) + " x " + std::to_string(rows) +
                               " heights are more than " + std::to_string(HeightFieldShape::kMaxSamples));
  const Result<std::string> bytes = ReadInputFile(path, kMaxHeightMapBytes);
  if (!bytes) return bytes.error();
  if (bytes->size() != expected)
    return FileError(path, std::to_string(bytes->size()) + " bytes, but " + std::to_string(columns) + " x " +
                               std::to_string(rows) + " float heights take " + std::to_string(expected));
  HeightMap map{columns, rows, std::vector<float>(static_cast<std::size_t>(columns) * rows)};
  for (std::size_t i = 0; i < map.heights.size(); ++i) {
    // Little-endian whatever the machine's order.
    std::uint32_t bits = 0;
    for (std::size_t b = 4; b-- > 0;) bits = (bits << 8) | static_cast<unsigned char>((*bytes)[4 * i + b]);
    std::memcpy(&map.heights[i], &bits, sizeof(float));
  }
  return map;
}

}  // namespace strata
