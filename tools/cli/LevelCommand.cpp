// `strata level generate --out DIR`: writes the bundled sample levels (courtyard as Y-up OBJ and as a Z-up
// OBJ copy, arena as binary glTF) from tools/levelgen.
#include <filesystem>
#include <iostream>

#include "assets/import/MeshExporter.h"
#include "tools/cli/Commands.h"
#include "tools/levelgen/LevelGenerator.h"

namespace strata::cli {

namespace {

int RunGenerate(const std::string& out) {
  std::error_code error;
  std::filesystem::create_directories(out, error);
  const levelgen::GeneratedLevel courtyard = levelgen::Courtyard();
  const levelgen::GeneratedLevel arena = levelgen::Arena();
  struct Output {
    const levelgen::GeneratedLevel& level;
    std::string file;
    std::string format;
    bool z_up;
  };
  const Output outputs[] = {{courtyard, "courtyard.obj", "objnomtl", false},
                            {courtyard, "courtyard_zup.obj", "objnomtl", true},
                            {arena, "arena.glb", "glb2", false}};
  for (const Output& output : outputs) {
    const std::filesystem::path path = std::filesystem::path(out) / output.file;
    if (Status status = ExportMesh(output.level.mesh, path, output.format, output.z_up); !status.ok()) {
      std::cerr << "strata level generate: " << status.message() << "\n";
      return 1;
    }
    std::cout << "wrote " << path.string() << " (" << output.level.mesh.triangles.size() << " triangles"
              << (output.z_up ? ", Z-up" : "") << ")\n";
  }
  return 0;
}

}  // namespace

std::function<int()> AddLevelCommand(CLI::App& app) {
  CLI::App* level = app.add_subcommand("level", "generate the bundled sample levels");
  level->require_subcommand(1);
  CLI::App* generate = level->add_subcommand("generate", "write courtyard and arena level files");
  auto out = std::make_shared<std::string>(STRATA_LEVELS_DIR);
  generate->add_option("--out", *out, "output folder")->capture_default_str();
  return [out] { return RunGenerate(*out); };
}

}  // namespace strata::cli
