// libFuzzer target: scene JSON. Any input must give a scene or an error, never a crash, hang or sanitizer
// report; a scene small enough to step is built and stepped, so valid but extreme scenes reach the engine.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "assets/scene/SceneLoader.h"
#include "physics/core/JobSystem.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // Mesh files are looked up in an empty directory: the loader's file errors, not the disk, are fuzzed.
  const strata::Result<strata::Scene> scene =
      strata::ParseScene(text, "fuzz.json", std::filesystem::temp_directory_path() / "strata_fuzz_no_files");
  if (!scene || scene->description.bodies.size() > 64) return 0;
  strata::PhysicsSystemConfig config;
  config.job_system = std::make_shared<strata::SerialJobSystem>();
  strata::Result<strata::SceneWorld> world = strata::BuildSceneWorld(*scene, config);
  if (!world) return 0;
  for (int step = 0; step < 3; ++step)
    if (!world->system->Step(scene->description.dt)) break;
  return 0;
}
