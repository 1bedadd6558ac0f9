// libFuzzer target: level meshes and height pictures, one family of files per run (STRATA_FUZZ_FAMILY: obj,
// glb, gltf, stl, ply, png). An input is a whole file; for obj and gltf, what follows the line
// "#strata-fuzz-next-file" is the file it refers to (level.mtl, level.bin), so the fuzzer also mutates the
// referenced file and the reference itself (a mutated name may point anywhere: the input policy must hold).
// Any input must give a mesh or an error, never a crash, hang, unbounded allocation or sanitizer report.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "assets/import/HeightMapImporter.h"
#include "assets/import/MeshImporter.h"

namespace {

constexpr std::string_view kNextFile = "\n#strata-fuzz-next-file\n";

struct Family {
  std::string extension;   ///< of the main file
  std::string referenced;  ///< name of the second file, empty: none
};

Family FamilyOf(std::string_view name) {
  if (name == "obj") return {".obj", "level.mtl"};
  if (name == "gltf") return {".gltf", "level.bin"};
  if (name == "glb") return {".glb", ""};
  if (name == "stl") return {".stl", ""};
  if (name == "ply") return {".ply", ""};
  if (name == "png") return {".png", ""};
  return {"", ""};
}

const Family& ThisFamily() {
  static const Family family = [] {
    const char* name = std::getenv("STRATA_FUZZ_FAMILY");
    Family chosen = FamilyOf(name ? name : "");
    if (chosen.extension.empty()) {
      std::fprintf(stderr, "set STRATA_FUZZ_FAMILY to obj, glb, gltf, stl, ply or png\n");
      std::abort();
    }
    return chosen;
  }();
  return family;
}

void Write(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Family& family = ThisFamily();
  static const std::filesystem::path folder = [] {
    const auto made =
        std::filesystem::temp_directory_path() / ("strata_fuzz_mesh_" + std::to_string(::getpid()));
    std::filesystem::create_directories(made);
    return made;
  }();
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::string_view main_file = input, referenced;
  if (const std::size_t split = input.find(kNextFile);
      !family.referenced.empty() && split != std::string_view::npos) {
    main_file = input.substr(0, split);
    referenced = input.substr(split + kNextFile.size());
  }
  const std::filesystem::path path = folder / ("level" + family.extension);
  Write(path, main_file);
  if (!family.referenced.empty()) Write(folder / family.referenced, referenced);
  if (family.extension == ".png") {
    (void)strata::ImportHeightMapPicture(path, 0.0f, 10.0f);
  } else {
    (void)strata::ImportMesh(path);
  }
  return 0;
}
