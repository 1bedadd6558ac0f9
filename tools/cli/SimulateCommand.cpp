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
    bodies.push_back({{"name", scene.description.bodies[i].name},
                      {"position", {p.x(), p.y(), p.z()}},
                      {"rotation", {q.w(), q.x(), q.y(), q.z()}},
                      {"linear_velocity", {v.x(), v.y(), v.z()}},
                      {"angular_velocity", {w.x(), w.y(), w.z()}},
                      {"sleeping", !active && scene.description.bodies[i].motion != SceneMotion::kStatic}});
  }
  nlohmann::json line = {{"step", step}, {"time", time}, {"bodies", bodies}};
  if (!constraint_forces) return line;
  // Each joint's force and torque on its body_b over the last step (N, N m, world axes).
  nlohmann::json joints = nlohmann::json::array();
  for (std::size_t i = 0; i < world.constraint_ids.size(); ++i) {
    const ConstraintID id = world.constraint_ids[i];
    const ConstraintForces forces = *world.system->constraints().GetForces(id);
    joints.push_back({{"name", scene.description.joints[i].name},
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
      options.scene.c_str(), scene.description.bodies.size(), options.steps, scene.description.dt,
      options.steps * scene.description.dt, total_ms, total_ms / options.steps, slowest_ms);
  std::printf("wrote %d state lines to %s\n%-12s %28s %10s %s\n", lines, options.out.c_str(), "body",
              "position (m)", "speed m/s", "state");
  BodyInterface& interface = world.system->bodies();
  for (std::size_t i = 0; i < world.ids.size(); ++i) {
    const Vec3 p = *interface.GetPosition(world.ids[i]);
    const float speed = interface.GetLinearVelocity(world.ids[i])->norm();
    const bool fixed = scene.description.bodies[i].motion == SceneMotion::kStatic;
    const char* state = fixed ? "static" : (*interface.IsActive(world.ids[i]) ? "awake" : "asleep");
    std::printf("%-12s (%8.3f, %8.3f, %8.3f) %10.3f %s\n", scene.description.bodies[i].name.c_str(), p.x(),
                p.y(), p.z(), speed, state);
  }
}

// Where a run's lines go: --out (or standard output), --events and --record, each written whole at the end.
struct SimulateOutputs {
  std::optional<OutputFile> file;
  std::optional<OutputFile> events_file;
  std::vector<std::string> names;  // by body index, for the events
  std::optional<view::Recorder> recorder;
  int record_every = 1;
};

int Fail(const std::string& message, int exit_code = 2) {
  std::cerr << "strata simulate: " << message << "\n";
  return exit_code;
}

// Opens every output before the run, so a run never ends in "cannot write"; a message on failure.
std::optional<std::string> OpenOutputs(const SimulateOptions& options, const Scene& scene, SceneWorld& world,
                                       SimulateOutputs& outputs) {
  // Written beside --out and renamed over it at the end: a failed or killed run leaves the old file whole.
  if (!options.out.empty()) {
    outputs.file.emplace(options.out);
    if (!outputs.file->status()) return outputs.file->status().message();
  }
  if (!options.events.empty()) {
    // One file written twice would end as whichever was renamed over it last.
    const auto same = [](const std::string& a, const std::string& b) {
      return !b.empty() && std::filesystem::absolute(a).lexically_normal() ==
                               std::filesystem::absolute(b).lexically_normal();
    };
    if (same(options.events, options.out) || same(options.events, options.record))
      return std::string("--events names the same file as --out or --record");
    outputs.events_file.emplace(options.events);
    if (!outputs.events_file->status()) return outputs.events_file->status().message();
    for (std::size_t i = 0; i < world.ids.size(); ++i) {
      if (outputs.names.size() <= world.ids[i].index) outputs.names.resize(world.ids[i].index + 1);
      outputs.names[world.ids[i].index] = scene.description.bodies[i].name;
    }
  }
  // Frames about 30 times a simulated second, whatever the scene's dt.
  outputs.record_every = std::max(1, static_cast<int>(std::lround(1.0f / (30.0f * scene.description.dt))));
  if (options.record.empty()) return std::nullopt;
  outputs.recorder.emplace(*world.system, "simulate",
                           "strata simulate: " + std::filesystem::path(options.scene).filename().string());
  const auto frames = static_cast<std::uint64_t>(options.steps / outputs.record_every) + 2;
  if (Status fits = outputs.recorder->CheckFrameBudget(frames); !fits) return "--record: " + fits.message();
  outputs.recorder->Capture(0, 0.0f);
  return std::nullopt;
}

// Renames every output over its target (standard output flushed); the first failure's message.
std::optional<std::string> CommitOutputs(const SimulateOptions& options, SimulateOutputs& outputs) {
  const Status written =
      outputs.file ? outputs.file->Commit()
                   : (std::cout.flush()
                          ? Status::Ok()
                          : Status(MakeError(ErrorCode::kInvalidArgument, "standard output: write failed")));
  if (!written) return written.message();
  if (outputs.events_file)
    if (Status committed = outputs.events_file->Commit(); !committed) return committed.message();
  if (!outputs.recorder) return std::nullopt;
  outputs.recorder->Finish(nullptr, {});
  if (Status recorded = outputs.recorder->Write(options.record); !recorded) return recorded.message();
  return std::nullopt;
}

// What the run counted, for the summary.
struct RunFigures {
  double slowest_ms = 0.0, total_ms = 0.0;
  int lines = 0, event_lines = 0;
  std::size_t linear_clamps = 0, angular_clamps = 0;
};

int RunSimulate(const SimulateOptions& options) {
  Result<Scene> scene = LoadScene(options.scene);
  if (!scene) return Fail(scene.error().message);
  PhysicsSystemConfig config;
  config.thread_count = options.threads;
  Result<SceneWorld> world = BuildSceneWorld(*scene, config);
  if (!world) return Fail(options.scene + ": " + world.error().message);
  SimulateOutputs outputs;
  if (auto failed = OpenOutputs(options, *scene, *world, outputs)) return Fail(*failed);
  std::ostream& out = outputs.file ? outputs.file->stream() : std::cout;
  RunFigures figures;
  // State lines going to the terminal are progress enough; a bar would break them up.
  bench::Progress progress("strata simulate", "steps", stderr, outputs.file && isatty(STDERR_FILENO));
  for (int step = 1; step <= options.steps; ++step) {
    progress.Update(static_cast<std::size_t>(step - 1), static_cast<std::size_t>(options.steps));
    const auto start = std::chrono::steady_clock::now();
    if (Status stepped = world->system->Step(scene->description.dt); !stepped)
      return Fail("step " + std::to_string(step) + ": " + stepped.message(), 1);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    figures.slowest_ms = std::max(figures.slowest_ms, ms);
    figures.total_ms += ms;
    const float time = static_cast<float>(step) * scene->description.dt;
    if (outputs.recorder && (step % outputs.record_every == 0 || step == options.steps))
      outputs.recorder->Capture(step, time);
    if (outputs.events_file)
      figures.event_lines +=
          WriteEvents(world->system->events(), outputs.names, step, time, outputs.events_file->stream());
    figures.linear_clamps += world->system->last_step_stats().linear_velocity_clamps;
    figures.angular_clamps += world->system->last_step_stats().angular_velocity_clamps;
    if (step % options.every == 0 || step == options.steps) {
      out << StateLine(*scene, *world, step, time, options.constraint_forces).dump() << "\n";
      ++figures.lines;
    }
  }
  if (auto failed = CommitOutputs(options, outputs)) return Fail(*failed);
  progress.Finish(
      std::to_string(options.steps) + " steps, " + std::to_string(figures.lines) + " state lines" +
      (outputs.events_file ? ", " + std::to_string(figures.event_lines) + " event lines" : "") +
      (outputs.recorder ? ", " + std::to_string(outputs.recorder->frame_count()) + " frames recorded" : "") +
      ", peak memory " + std::to_string(PeakMemoryMegabytes()) + " MB");
  if (!options.out.empty())
    PrintSummary(*scene, *world, options, figures.lines, figures.total_ms, figures.slowest_ms);
  // Limits are never silent: a body that hit its max_linear_velocity or max_angular_velocity is reported.
  if (figures.linear_clamps + figures.angular_clamps > 0)
    std::cerr
        << "strata simulate: warning: velocities were clamped to their limits " << figures.linear_clamps
        << " time(s) (linear) and " << figures.angular_clamps
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
