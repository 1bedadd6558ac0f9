// `strata simulate SCENE.json --steps N [--out states.jsonl] [--every K]`: runs a scene and writes one JSON
// line per recorded step. A bad scene exits with code 2 before anything is written.
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "assets/scene/SceneLoader.h"
#include "physics/body/BodyInterface.h"
#include "tools/cli/Commands.h"

namespace strata::cli {

namespace {

struct SimulateOptions {
  std::string scene;
  int steps = 600;
  std::string out;
  int every = 1;
  int threads = 0;
};

nlohmann::json StateLine(const Scene& scene, SceneWorld& world, int step, float time) {
  nlohmann::json bodies = nlohmann::json::array();
  BodyInterface& interface = world.system->bodies();
  for (std::size_t i = 0; i < world.ids.size(); ++i) {
    const BodyID id = world.ids[i];
    const Vec3 p = *interface.GetPosition(id);
    const Quat q = *interface.GetRotation(id);
    const Vec3 v = *interface.GetLinearVelocity(id);
    const Vec3 w = *interface.GetAngularVelocity(id);
    const bool active = *interface.IsActive(id);
    bodies.push_back({{"name", scene.bodies[i].name},
                      {"position", {p.x(), p.y(), p.z()}},
                      {"rotation", {q.w(), q.x(), q.y(), q.z()}},
                      {"linear_velocity", {v.x(), v.y(), v.z()}},
                      {"angular_velocity", {w.x(), w.y(), w.z()}},
                      {"sleeping", !active && scene.bodies[i].settings.motion_type != MotionType::kStatic}});
  }
  return {{"step", step}, {"time", time}, {"bodies", bodies}};
}

int RunSimulate(const SimulateOptions& options) {
  Result<Scene> scene = LoadScene(options.scene);
  if (!scene) {
    std::cerr << "strata simulate: " << scene.error().message << "\n";
    return 2;
  }
  PhysicsSystemConfig config;
  config.thread_count = options.threads;
  Result<SceneWorld> world = BuildSceneWorld(*scene, config);
  if (!world) {
    std::cerr << "strata simulate: " << options.scene << ": " << world.error().message << "\n";
    return 2;
  }
  std::ofstream file;
  if (!options.out.empty()) {
    file.open(options.out);
    if (!file) {
      std::cerr << "strata simulate: cannot write " << options.out << "\n";
      return 2;
    }
  }
  std::ostream& out = options.out.empty() ? std::cout : file;
  for (int step = 1; step <= options.steps; ++step) {
    if (Status stepped = world->system->Step(scene->dt); !stepped) {
      std::cerr << "strata simulate: step " << step << ": " << stepped.message() << "\n";
      return 1;
    }
    if (step % options.every == 0 || step == options.steps)
      out << StateLine(*scene, *world, step, static_cast<float>(step) * scene->dt).dump() << "\n";
  }
  return 0;
}

}  // namespace

std::function<int()> AddSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* command = app.add_subcommand("simulate", "Run a JSON scene and write body states as JSON lines");
  command->add_option("scene", options->scene, "Scene file (see assets/scenes/README.md)")->required();
  command->add_option("--steps", options->steps, "Number of steps")->check(CLI::PositiveNumber);
  command->add_option("--out", options->out, "Write JSON lines here instead of standard output");
  command->add_option("--every", options->every, "Record every K-th step (and the last)")->check(CLI::PositiveNumber);
  command->add_option("--threads", options->threads, "Worker threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  return [options] { return RunSimulate(*options); };
}

}  // namespace strata::cli
