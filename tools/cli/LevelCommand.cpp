// `strata level generate --out DIR`: writes the bundled sample levels (courtyard as Y-up OBJ and as a Z-up
// OBJ copy, arena as binary glTF) from tools/levelgen.
// `strata level field --size M --seed N --out FILE`: a generated open field of any size (farm bakes, tests).
#include <cstdint>
#include <filesystem>
#include <iostream>

#include "assets/import/MeshExporter.h"
#include "tools/cli/Commands.h"
#include "tools/cli/Validators.h"
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

struct FieldOptions {
  float size = 1000.0f;
  std::uint32_t seed = 1;
  std::string out;
};

int RunField(const FieldOptions& options) {
  const std::filesystem::path path(options.out);
  const std::string extension = path.extension().string();
  const std::string format = extension == ".obj" ? "objnomtl" : extension == ".glb" ? "glb2" : "";
  if (format.empty()) {
    std::cerr << "strata level field: --out must end in .obj or .glb, got '" << options.out << "'\n";
    return 2;
  }
  const levelgen::GeneratedLevel field = levelgen::Field(options.size, options.seed);
  if (Status status = ExportMesh(field.mesh, path, format); !status.ok()) {
    std::cerr << "strata level field: " << status.message() << "\n";
    return 2;
  }
  std::cout << "wrote " << path.string() << " (" << options.size << " m square, seed " << options.seed << ", "
            << field.mesh.triangles.size() << " triangles)\n";
  return 0;
}

}  // namespace

std::function<int()> AddLevelCommand(CLI::App& app) {
  CLI::App* level =
      app.add_subcommand("level", "generate the bundled sample levels, or an open field of any size");
  level->require_subcommand(1);
  CLI::App* generate = level->add_subcommand("generate", "write courtyard and arena level files");
  auto out = std::make_shared<std::string>(STRATA_LEVELS_DIR);
  generate->add_option("--out", *out, "output folder")->capture_default_str();
  auto field = std::make_shared<FieldOptions>();
  CLI::App* field_command =
      level->add_subcommand("field", "write a generated open field of any size (.obj or .glb)");
  field_command->add_option("--size", field->size, "side of the square (m), from the origin")
      ->check(FiniteIn(25.6, 16000.0))
      ->capture_default_str();
  field_command->add_option("--seed", field->seed, "places the features")->capture_default_str();
  field_command->add_option("--out", field->out, "the level file")->required();
  // Both subcommands share the level command's callback; the one that was parsed runs.
  return [out, field, generate, field_command] {
    if (field_command->parsed()) return RunField(*field);
    (void)generate;
    return RunGenerate(*out);
  };
}

}  // namespace strata::cli
