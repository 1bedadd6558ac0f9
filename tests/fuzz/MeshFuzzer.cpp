// libFuzzer target: level and prop meshes through assimp. The input is a whole file; its format is told from
// its first bytes (as a user's file would be named), so the bundled levels seed it as they are. Any input
// must give a mesh or an error, never a crash, hang, unbounded allocation or sanitizer report.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "FuzzInput.h"
#include "assets/import/MeshImporter.h"

namespace {

std::string ExtensionFor(const std::uint8_t* data, std::size_t size) {
  const auto starts = [&](const char* magic) {
    const std::size_t length = std::strlen(magic);
    return size >= length && std::memcmp(data, magic, length) == 0;
  };
  if (starts("glTF")) return ".glb";
  if (starts("ply")) return ".ply";
  if (starts("solid")) return ".stl";
  if (size >= 84) {  // binary STL: an 80-byte header, then a triangle count that the size agrees with
    std::uint32_t triangles = 0;
    std::memcpy(&triangles, data + 80, sizeof(triangles));
    if (84 + 50 * static_cast<std::uint64_t>(triangles) == size) return ".stl";
  }
  if (starts("<?xml") || starts("<COLLADA")) return ".dae";
  if (starts("Kaydara FBX")) return ".fbx";
  if (starts("{")) return ".gltf";
  return ".obj";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = strata::fuzz::WriteInput(data, size, "strata_fuzz_mesh", ExtensionFor(data, size));
  (void)strata::ImportMesh(path);
  return 0;
}
