// `strata simulate SCENE.json --steps N [--out states.jsonl] [--every K] [--events events.jsonl]`: runs a
// scene and writes one JSON line per recorded step (with --constraint-forces, each joint's force and torque
// too), and with --events one JSON line per contact or sensor event. A bad scene exits with code 2 before
// anything is written.
#include <unistd.h>

#include <sys/resource.h>
#include <chrono>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "assets/scene/SceneLoader.h"
#include "physics/body/BodyInterface.h"
#include "physics/core/OutputFile.h"
#include "tools/bench/Progress.h"
#include "tools/cli/Commands.h"
#include "tools/cli/Validators.h"
#include "tools/view/Recording.h"

namespace strata::cli {

namespace {

// The most this process has held in memory so far (resident set), for the run's summary.
long PeakMemoryMegabytes() {
  rusage usage{};
  return ::getrusage(RUSAGE_SELF, &usage) == 0 ? usage.ru_maxrss / 1024 : 0;
}

struct SimulateOptions {
  std::string scene;
  int steps = 600;
  std::string out;
  int every = 1;
  int threads = 0;
  bool constraint_forces = false;
  std::string record;  ///< a recording for `strata view` (empty: none)
  std::string events;  ///< contact and sensor events as JSON lines (empty: none)
};

nlohmann::json VectorJson(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

// One line per event of the step, bodies by their scene names.
int WriteEvents(const StepEvents& events, const std::vector<std::string>& names, int step, float time,
                std::ostream& out) {
  const auto name = [&](BodyID id) { return id.index < names.size() ? names[id.index] : std::string("?"); };
  int lines = 0;
  const auto contact = [&](const char* kind, const ContactEvent& event) {
    nlohmann::json points = nlohmann::json::array();
    for (int i = 0; i < event.point_count; ++i) points.push_back(VectorJson(event.points[i]));
    out << nlohmann::json{{"step", step},
                          {"time", time},
                          {"event", kind},
                          {"body_a", name(event.body_a)},
                          {"body_b", name(event.body_b)},
                          {"normal", VectorJson(event.normal)},
                          {"points", std::move(points)},
                          {"approach_speed", event.approach_speed},
                          {"normal_impulse", event.normal_impulse}}
               .dump()
        << "\n";
    ++lines;
  };
  for (const ContactEvent& event : events.contact_begin) contact("contact_begin", event);
  for (const ContactEvent& event : events.contact_persist) contact("contact_persist", event);
  for (const ContactEndEvent& event : events.contact_end) {
    out << nlohmann::json{{"step", step},
                          {"time", time},
                          {"event", "contact_end"},
                          {"body_a", name(event.body_a)},
                          {"body_b", name(event.body_b)}}
               .dump()
        << "\n";
    ++lines;
  }
  const auto sensor = [&](const char* kind, const SensorEvent& event) {
    out << nlohmann::json{{"step", step},
                          {"time", time},
                          {"event", kind},
                          {"sensor", name(event.sensor)},
                          {"visitor", name(event.visitor)}}
               .dump()
        << "\n";
    ++lines;
  };
  for (const SensorEvent& event : events.sensor_begin) sensor("sensor_begin", event);
  for (const SensorEvent& event : events.sensor_end) sensor("sensor_end", event);
  return lines;
}

nlohmann::json StateLine(const Scene& scene, SceneWorld& world, int step, float time,
                         bool constraint_forces) {
  nlohmann::json bodies = nlohmann::json::array();
  BodyInterface& interface = world.system->bodies();
  for (std::size_t i = 0; i < world.ids.size(); ++i) {
    const BodyID id = world.ids[i];
    const Vec3d p = *interface.GetPrecisePosition(id);
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
  nlohmann::json line = {{"step", step}, {"time", time}, {"bodies", bodies}};
  if (!constraint_forces) return line;
  // Each joint's force and torque on its body_b over the last step (N, N m, world axes).
  nlohmann::json joints = nlohmann::json::array();
  for (std::size_t i = 0; i < world.constraint_ids.size(); ++i) {
    const ConstraintID id = world.constraint_ids[i];
    const ConstraintForces forces = *world.system->constraints().GetForces(id);
    joints.push_back({{"name", scene.constraints[i].name},
                      {"force", {forces.force.x(), forces.force.y(), forces.force.z()}},
                      {"torque", {forces.torque.x(), forces.torque.y(), forces.torque.z()}},
                      {"broken", *world.system->constraints().IsBroken(id)}});
  }
  line["constraints"] = joints;
  return line;
}

// A person-readable account of the run, printed when the states go to a file.
void PrintSummary(const Scene& scene, SceneWorld& world, const SimulateOptions& options, int lines,
                  double total_ms, double slowest_ms) {
  std::printf(
      "%s: %zu bodies, %d steps of %.4f s (%.2f s simulated) in %.1f ms (%.3f ms/step, slowest %.3f ms)\n",
      options.scene.c_str(), scene.bodies.size(), options.steps, scene.dt, options.steps * scene.dt, total_ms,
      total_ms / options.steps, slowest_ms);
  std::printf("wrote %d state lines to %s\n%-12s %28s %10s %s\n", lines, options.out.c_str(), "body",
              "position (m)", "speed m/s", "state");
  BodyInterface& interface = world.system->bodies();
  for (std::size_t i = 0; i < world.ids.size(); ++i) {
    const Vec3 p = *interface.GetPosition(world.ids[i]);
    const float speed = interface.GetLinearVelocity(world.ids[i])->norm();
    const MotionType motion = scene.bodies[i].settings.motion_type;
    const char* state =
        motion == MotionType::kStatic ? "static" : (*interface.IsActive(world.ids[i]) ? "awake" : "asleep");
    std::printf("%-12s (%8.3f, %8.3f, %8.3f) %10.3f %s\n", scene.bodies[i].name.c_str(), p.x(), p.y(), p.z(),
                speed, state);
  }
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
  // Written beside --out and renamed over it at the end: a failed or killed run leaves the old file whole.
  std::optional<OutputFile> file;
  if (!options.out.empty()) {
    file.emplace(options.out);
    if (!file->status()) {
      std::cerr << "strata simulate: " << file->status().message() << "\n";
      return 2;
    }
  }
  std::optional<OutputFile> events_file;
  std::vector<std::string> names;  // by body index
  if (!options.events.empty()) {
    // One file written twice would end as whichever was renamed over it last.
    const auto same = [](const std::string& a, const std::string& b) {
      return !b.empty() && std::filesystem::absolute(a).lexically_normal() ==
                               std::filesystem::absolute(b).lexically_normal();
    };
    if (same(options.events, options.out) || same(options.events, options.record)) {
      std::cerr << "strata simulate: --events names the same file as --out or --record\n";
      return 2;
    }
    events_file.emplace(options.events);
    if (!events_file->status()) {
      std::cerr << "strata simulate: " << events_file->status().message() << "\n";
      return 2;
    }
    for (std::size_t i = 0; i < world->ids.size(); ++i) {
      if (names.size() <= world->ids[i].index) names.resize(world->ids[i].index + 1);
      names[world->ids[i].index] = scene->bodies[i].name;
    }
  }
  // Frames about 30 times a simulated second, whatever the scene's dt.
  const int record_every = std::max(1, static_cast<int>(std::lround(1.0f / (30.0f * scene->dt))));
  std::optional<view::Recorder> recorder;
  if (!options.record.empty()) {
    recorder.emplace(*world->system, "simulate",
                     "strata simulate: " + std::filesystem::path(options.scene).filename().string());
    if (Status fits =
            recorder->CheckFrameBudget(static_cast<std::uint64_t>(options.steps / record_every) + 2);
        !fits) {
      std::cerr << "strata simulate: --record: " << fits.message() << "\n";
      return 2;
    }
    recorder->Capture(0, 0.0f);
  }
  std::ostream& out = file ? file->stream() : std::cout;
  double slowest_ms = 0.0, total_ms = 0.0;
  int lines = 0, event_lines = 0;
  std::size_t linear_clamps = 0, angular_clamps = 0;
  // State lines going to the terminal are progress enough; a bar would break them up.
  bench::Progress progress("strata simulate", "steps", stderr, file && isatty(STDERR_FILENO));
  for (int step = 1; step <= options.steps; ++step) {
    progress.Update(static_cast<std::size_t>(step - 1), static_cast<std::size_t>(options.steps));
    const auto start = std::chrono::steady_clock::now();
    if (Status stepped = world->system->Step(scene->dt); !stepped) {
      std::cerr << "strata simulate: step " << step << ": " << stepped.message() << "\n";
      return 1;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    slowest_ms = std::max(slowest_ms, ms);
    total_ms += ms;
    if (recorder && (step % record_every == 0 || step == options.steps))
      recorder->Capture(step, static_cast<float>(step) * scene->dt);
    if (events_file)
      event_lines += WriteEvents(world->system->events(), names, step, static_cast<float>(step) * scene->dt,
                                 events_file->stream());
    linear_clamps += world->system->last_step_stats().linear_velocity_clamps;
    angular_clamps += world->system->last_step_stats().angular_velocity_clamps;
    if (step % options.every == 0 || step == options.steps) {
      out << StateLine(*scene, *world, step, static_cast<float>(step) * scene->dt, options.constraint_forces)
                 .dump()
          << "\n";
      ++lines;
    }
  }
  const Status written =
      file ? file->Commit()
           : (std::cout.flush()
                  ? Status::Ok()
                  : Status(MakeError(ErrorCode::kInvalidArgument, "standard output: write failed")));
  if (!written) {
    std::cerr << "strata simulate: " << written.message() << "\n";
    return 2;
  }
  if (events_file) {
    if (Status committed = events_file->Commit(); !committed) {
      std::cerr << "strata simulate: " << committed.message() << "\n";
      return 2;
    }
  }
  if (recorder) {
    recorder->Finish(nullptr, {});
    if (Status recorded = recorder->Write(options.record); !recorded) {
      std::cerr << "strata simulate: " << recorded.message() << "\n";
      return 2;
    }
  }
  progress.Finish(std::to_string(options.steps) + " steps, " + std::to_string(lines) + " state lines" +
                  (events_file ? ", " + std::to_string(event_lines) + " event lines" : "") +
                  (recorder ? ", " + std::to_string(recorder->frame_count()) + " frames recorded" : "") +
                  ", peak memory " + std::to_string(PeakMemoryMegabytes()) + " MB");
  if (!options.out.empty()) PrintSummary(*scene, *world, options, lines, total_ms, slowest_ms);
  // Limits are never silent: a body that hit its max_linear_velocity or max_angular_velocity is reported.
  if (linear_clamps + angular_clamps > 0)
    std::cerr
        << "strata simulate: warning: velocities were clamped to their limits " << linear_clamps
        << " time(s) (linear) and " << angular_clamps
        << " time(s) (angular); raise max_linear_velocity / max_angular_velocity if that was not meant\n";
  return 0;
}

}  // namespace

std::function<int()> AddSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* command = app.add_subcommand("simulate", "Run a JSON scene and write body states as JSON lines");
  command->add_option("scene", options->scene, "Scene file (see assets/scenes/README.md)")->required();
  command->add_option("--steps", options->steps, "Number of steps")->check(CountIn(1, 100000000, "--steps"));
  command->add_option("--out", options->out, "Write JSON lines here instead of standard output");
  command->add_option("--every", options->every, "Record every K-th step (and the last)")
      ->check(CountIn(1, 100000000, "--every"));
  command->add_flag("--constraint-forces", options->constraint_forces,
                    "Add each joint's force and torque (and whether it broke) to every state line");
  command->add_option("--threads", options->threads, "Worker threads (0 = all cores)")
      ->check(CountIn(0, kMaxThreads, "--threads"));
  command->add_option("--record", options->record, "Also write a recording of the run for `strata view`");
  command->add_option("--events", options->events,
                      "Write the contact and sensor events of bodies that ask for them (scene keys "
                      "report_contacts, sensor) as JSON lines, one an event");
  return [options] { return RunSimulate(*options); };
}

}  // namespace strata::cli
