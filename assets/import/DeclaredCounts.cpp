#include "assets/import/DeclaredCounts.h"

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "assets/json/StrictJson.h"
#include "physics/core/InputFile.h"

namespace strata {

namespace {

constexpr std::uint32_t kGlbJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kGlbBin = 0x004E4942;   // "BIN\0"
// Accessors without a buffer view are zeros assimp allocates: allowed up to this many bytes.
constexpr std::uint64_t kMaxUnbackedAccessorBytes = std::uint64_t{64} << 20;

Error CountError(const std::filesystem::path& path, const std::string& why) {
  return {ErrorCode::kParseError, path.string() + ": " + why};
}

// A non-negative integer field of `object`, or `fallback` when absent; nullopt-like -1 when invalid.
std::int64_t Field(const nlohmann::json& object, const char* key, std::int64_t fallback) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  const nlohmann::json& value = object[key];
  if (!value.is_number_unsigned()) return -1;
  const auto number = value.get<std::uint64_t>();
  return number > (std::uint64_t{1} << 62) ? -1 : static_cast<std::int64_t>(number);
}

std::int64_t ComponentBytes(std::int64_t type) {
  switch (type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

std::int64_t Components(const nlohmann::json& type) {
  if (!type.is_string()) return 0;
  const std::string name = type.get<std::string>();
  if (name == "SCALAR") return 1;
  if (name == "VEC2") return 2;
  if (name == "VEC3") return 3;
  if (name == "VEC4" || name == "MAT2") return 4;
  if (name == "MAT3") return 9;
  if (name == "MAT4") return 16;
  return 0;
}

// The bytes a buffer really has: the GLB's binary chunk, a data URI's decoded length, or a file's size.
std::int64_t AvailableBytes(const nlohmann::json& buffer, const std::filesystem::path& directory,
                            std::int64_t binary_chunk) {
  if (!buffer.is_object() || !buffer.contains("uri")) return binary_chunk;
  if (!buffer["uri"].is_string()) return 0;
  const std::string uri = buffer["uri"].get<std::string>();
  if (uri.rfind("data:", 0) == 0) {
    const std::size_t comma = uri.find(',');
    return comma == std::string::npos ? 0 : static_cast<std::int64_t>((uri.size() - comma - 1) / 4 * 3 + 3);
  }
  const Result<std::uint64_t> size = CheckInputFile(directory / uri, std::uint64_t{1} << 40);
  return size ? static_cast<std::int64_t>(*size) : -1;  // a missing file is assimp's error to report
}

Status CheckGltfJson(const std::filesystem::path& path, const std::string& text, std::int64_t binary_chunk) {
  // Strictly, and refused here when it is not: assimp's own JSON reader recurses, and a deeply nested
  // file would exhaust its stack.
  const Result<nlohmann::json> parsed = ParseStrictJson(text, path.string() + " (glTF JSON)");
  if (!parsed) return parsed.error();
  const nlohmann::json& document = *parsed;
  if (!document.is_object()) return CountError(path, "glTF JSON must be an object");
  const auto list = [&](const char* key) {
    return document.contains(key) && document[key].is_array() ? document[key] : nlohmann::json::array();
  };
  const nlohmann::json buffers = list("buffers"), views = list("bufferViews"), accessors = list("accessors");
  std::vector<std::int64_t> buffer_bytes;
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const std::int64_t declared = Field(buffers[b], "byteLength", -1);
    const std::int64_t available = AvailableBytes(buffers[b], path.parent_path(), binary_chunk);
    if (declared < 0)
      return CountError(path, "glTF buffer " + std::to_string(b) + " has no valid byteLength");
    if (available >= 0 && declared > available)
      return CountError(path, "glTF buffer " + std::to_string(b) + " declares " + std::to_string(declared) +
                                  " bytes but has " + std::to_string(available));
    buffer_bytes.push_back(declared);
  }
  std::vector<std::int64_t> view_bytes;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::int64_t buffer = Field(views[v], "buffer", -1), offset = Field(views[v], "byteOffset", 0),
                       length = Field(views[v], "byteLength", -1);
    if (buffer < 0 || static_cast<std::size_t>(buffer) >= buffer_bytes.size() || offset < 0 || length < 0 ||
        offset + length > buffer_bytes[static_cast<std::size_t>(buffer)])
      return CountError(path, "glTF buffer view " + std::to_string(v) + " lies outside its buffer");
    view_bytes.push_back(length);
  }
  for (std::size_t a = 0; a < accessors.size(); ++a) {
    const std::int64_t count = Field(accessors[a], "count", -1),
                       offset = Field(accessors[a], "byteOffset", 0);
    const std::int64_t element =
        ComponentBytes(Field(accessors[a], "componentType", -1)) *
        Components(accessors[a].is_object() && accessors[a].contains("type") ? accessors[a]["type"]
                                                                             : nullptr);
    const std::int64_t view = Field(accessors[a], "bufferView", -1);
    const std::string which = "glTF accessor " + std::to_string(a);
    if (count < 0 || offset < 0 || element <= 0)
      return CountError(path, which + " has no valid count or type");
    if (count > (std::int64_t{1} << 40) / element)
      return CountError(path, which + " declares too many elements");
    const std::int64_t needed = offset + count * element;
    if (view >= 0 && static_cast<std::size_t>(view) < view_bytes.size()
            ? needed > view_bytes[static_cast<std::size_t>(view)] + element  // a stride may pad the last one
            : static_cast<std::uint64_t>(needed) > kMaxUnbackedAccessorBytes)
      return CountError(
          path, which + " declares " + std::to_string(count) + " elements, more than its buffer view holds");
  }
  return Status::Ok();
}

// GLB: a 12-byte header whose length is the file's, then chunks that must fit in it; the first is JSON.
Status CheckGlb(const std::filesystem::path& path, const std::string& bytes) {
  const auto word = [&](std::size_t at) {
    std::uint32_t value = 0;
    std::memcpy(&value, bytes.data() + at, sizeof(value));
    return value;
  };
  if (bytes.size() < 12 || word(4) != 2) return Status::Ok();  // glTF 1 binaries are assimp's to judge
  if (word(8) != bytes.size())
    return CountError(path, "GLB header says " + std::to_string(word(8)) + " bytes; the file has " +
                                std::to_string(bytes.size()));
  std::string json;
  std::int64_t binary = 0;
  for (std::size_t offset = 12; offset < bytes.size();) {
    if (bytes.size() - offset < 8) return CountError(path, "GLB chunk header cut short");
    const std::uint64_t length = word(offset), type = word(offset + 4);
    if (length > bytes.size() - offset - 8)
      return CountError(path, "GLB chunk at byte " + std::to_string(offset) + " claims " +
                                  std::to_string(length) + " bytes, past the end of the file");
    if (type == kGlbJson && json.empty()) json = bytes.substr(offset + 8, length);
    if (type == kGlbBin && binary == 0) binary = static_cast<std::int64_t>(length);
    offset += 8 + length;
  }
  return CheckGltfJson(path, json, binary);
}

}  // namespace

Status CheckDeclaredCounts(const std::filesystem::path& path, std::uint64_t file_size) {
  char magic[4] = {};
  std::ifstream(path, std::ios::binary).read(magic, sizeof(magic));
  const bool glb = std::memcmp(magic, "glTF", 4) == 0;
  if (!glb && path.extension() != ".gltf") return Status::Ok();
  const Result<std::string> bytes = ReadInputFile(path, file_size);
  if (!bytes) return bytes.error();
  return glb ? CheckGlb(path, *bytes) : CheckGltfJson(path, *bytes, 0);
}

}  // namespace strata
