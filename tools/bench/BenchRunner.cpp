#include "tools/bench/BenchRunner.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>

#include "assets/scene/SceneBuilder.h"
#include "physics/body/BodyInterface.h"
#include "physics/core/ThreadPoolJobSystem.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::bench {

namespace {

void HashBytes(std::uint64_t& hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
}

// Sums a step's stage figures into `result` (stages matched by position; every step has the same list).
void AddProfile(const StepProfile& profile, EngineResult& result) {
  result.stage_count = static_cast<int>(std::min<std::size_t>(profile.stage_count, EngineResult::kMaxStages));
  for (int s = 0; s < result.stage_count; ++s) {
    const StageTiming& timing = profile.stages[s];
    StageFigures& figures = result.stages[s];
    std::snprintf(figures.name, sizeof(figures.name), "%s", timing.name);
    figures.wall_ms += timing.end_ms - timing.start_ms;
    figures.busy_ms += timing.busy_ms;
    figures.jobs = timing.width;
    figures.parallel = timing.parallel;
  }
}

struct JointGaps {
  double max_mm = 0.0;
  double mean_mm = 0.0;
};

// Each joint's anchor, carried along by body a and by body b (a static body or the world keeps it in place),
// and how far apart the two ends up.
JointGaps MeasureJointGaps(const BenchScene& scene, const std::vector<FinalPose>& poses) {
  std::vector<int> dynamic_index(scene.bodies.size(), -1);
  int next = 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    if (scene.bodies[i].IsDynamic()) dynamic_index[i] = next++;
  const auto carried = [&](int body, const Vec3& anchor) {
    if (body < 0 || dynamic_index[static_cast<std::size_t>(body)] < 0) return anchor;
    const BodyDescription& start = scene.bodies[static_cast<std::size_t>(body)];
    const FinalPose& end = poses[static_cast<std::size_t>(dynamic_index[static_cast<std::size_t>(body)])];
    return Vec3(end.rotation * (start.rotation.conjugate() * (anchor - start.position)) + end.position);
  };
  JointGaps gaps;
  double sum = 0.0;
  for (const JointDescription& joint : scene.joints) {
    const double gap =
        1000.0 * static_cast<double>(
                     (carried(joint.body_a, joint.anchor) - carried(joint.body_b, joint.anchor)).norm());
    gaps.max_mm = std::max(gaps.max_mm, gap);
    sum += gap;
  }
  gaps.mean_mm = scene.joints.empty() ? 0.0 : sum / static_cast<double>(scene.joints.size());
  return gaps;
}

std::vector<FinalPose> StrataPoses(PhysicsSystem& world, const std::vector<BodyID>& dynamic_ids) {
  std::vector<FinalPose> poses;
  poses.reserve(dynamic_ids.size());
  for (const BodyID id : dynamic_ids)
    poses.push_back({*world.bodies().GetPosition(id), *world.bodies().GetRotation(id)});
  return poses;
}

}  // namespace

bool ReadsJointGapsAfter(const BenchScene& scene, int step) {
  return !scene.joints.empty() && ((step + 1) % kJointGapSampleSteps == 0 || step + 1 == scene.steps);
}

void WidenJointGap(const BenchScene& scene, const std::vector<FinalPose>& poses, EngineResult& result) {
  result.widest_joint_gap_mm = std::max(result.widest_joint_gap_mm, MeasureJointGaps(scene, poses).max_mm);
}

float BenchMass(const BenchScene& scene, const BodyDescription& body) {
  if (body.mass > 0.0f) return body.mass;
  return (*MakeShape(scene, body))->ComputeMassProperties(BodyCreationSettings().density).mass;
}

void Summarize(const BenchScene& scene, const std::vector<FinalPose>& poses, EngineResult& result) {
  const JointGaps gaps = MeasureJointGaps(scene, poses);
  result.max_joint_gap_mm = gaps.max_mm;
  result.mean_joint_gap_mm = gaps.mean_mm;
  result.state_hash = 1469598103934665603ull;
  result.bodies_in_footprint = 0;
  for (const FinalPose& pose : poses) {
    HashBytes(result.state_hash, pose.position.data(), sizeof(float) * 3);
    HashBytes(result.state_hash, pose.rotation.coeffs().data(), sizeof(float) * 4);
    const bool inside = scene.name == "pyramid"
                            ? std::abs(pose.position.x()) <= 16.0f && std::abs(pose.position.z()) <= 16.0f &&
                                  pose.position.y() > 0.0f
                            : pose.position.y() > 0.0f;
    result.bodies_in_footprint += inside ? 1 : 0;
  }
}

void SummarizeTimes(std::vector<double> step_seconds, EngineResult& result) {
  result.steps = static_cast<int>(step_seconds.size());
  result.total_seconds = 0.0;
  for (double s : step_seconds) result.total_seconds += s;
  if (step_seconds.empty()) return;
  result.mean_step_ms = 1000.0 * result.total_seconds / static_cast<double>(step_seconds.size());
  result.max_step_ms = 1000.0 * *std::max_element(step_seconds.begin(), step_seconds.end());
  std::nth_element(step_seconds.begin(), step_seconds.begin() + step_seconds.size() / 2, step_seconds.end());
  result.median_step_ms = 1000.0 * step_seconds[step_seconds.size() / 2];
}

long PeakMemoryKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

std::optional<StrataScene> BuildStrataScene(const BenchScene& scene, PhysicsSystemConfig config) {
  config.max_bodies = static_cast<std::uint32_t>(scene.bodies.size()) + 16;
  PhysicsSettings settings = ToPhysicsSettings(scene);
  settings.body_pair_cache_max_distance = scene.pair_cache_max_distance;
  settings.body_pair_cache_max_angle = scene.pair_cache_max_angle;
  auto system = PhysicsSystem::Create(config, settings);
  if (!system) return std::nullopt;
  Result<std::vector<ShapeRef>> shapes = MakeShapes(scene);
  if (!shapes) return std::nullopt;
  StrataScene built{std::move(*system), {}};
  PhysicsSystem& world = *built.world;
  std::vector<BodyID> all_ids;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDescription& body = scene.bodies[i];
    BodyCreationSettings create = ToBodySettings(body, (*shapes)[i]);
    create.report_contacts = scene.report_contacts && body.IsDynamic();
    auto id = world.bodies().CreateBody(create);
    if (!id) return std::nullopt;
    all_ids.push_back(*id);
    if (body.IsDynamic()) built.dynamic_bodies.push_back(*id);
  }
  if (!world.bodies().AddBodies(all_ids).ok()) return std::nullopt;
  for (const JointDescription& joint : scene.joints)
    if (!world.constraints().Add(ToJointSettings(joint, all_ids))) return std::nullopt;
  return built;
}

EngineResult RunStrata(const BenchScene& scene, int threads, JobSystemKind job_system) {
  EngineResult result;
  PhysicsSystemConfig config;
  config.thread_count = threads;
  if (job_system == JobSystemKind::kThreadPool)
    config.job_system = std::make_shared<ThreadPoolJobSystem>(threads);
  std::optional<StrataScene> built = BuildStrataScene(scene, config);
  if (!built) return result;
  PhysicsSystem& world = *built->world;
  const std::vector<BodyID>& dynamic_ids = built->dynamic_bodies;
  std::vector<double> times;
  times.reserve(scene.steps);
  std::size_t pairs = 0, replayed = 0, kept_apart = 0, events = 0;
  for (int step = 0; step < scene.steps; ++step) {
    const auto start = std::chrono::steady_clock::now();
    if (!world.Step(scene.dt).ok()) return result;
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const StepEvents& step_events = world.events();
    events += step_events.contact_begin.size() + step_events.contact_persist.size() +
              step_events.contact_end.size();
    AddProfile(world.last_step_profile(), result);
    pairs += world.last_step_stats().pairs;
    replayed += world.last_step_stats().pairs_replayed;
    kept_apart += world.last_step_stats().pairs_kept_apart;
    if (ReadsJointGapsAfter(scene, step)) WidenJointGap(scene, StrataPoses(world, dynamic_ids), result);
  }
  for (int s = 0; s < result.stage_count; ++s) {
    result.stages[s].wall_ms /= scene.steps;
    result.stages[s].busy_ms /= scene.steps;
  }
  result.replayed_pair_share = pairs > 0 ? static_cast<double>(replayed) / static_cast<double>(pairs) : 0.0;
  result.kept_apart_pair_share =
      pairs > 0 ? static_cast<double>(kept_apart) / static_cast<double>(pairs) : 0.0;
  result.contact_events_per_step = static_cast<double>(events) / std::max(scene.steps, 1);
  result.threads = world.job_system().ThreadCount();
  SummarizeTimes(std::move(times), result);
  Summarize(scene, StrataPoses(world, dynamic_ids), result);
  result.bodies = static_cast<int>(scene.bodies.size());
  result.peak_memory_kb = PeakMemoryKb();
  result.ok = true;
  return result;
}

EngineResult RunIsolated(const std::function<EngineResult()>& run) {
  int fds[2];
  if (pipe(fds) != 0) return run();
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]), close(fds[1]);
    return run();
  }
  if (child == 0) {
    close(fds[0]);
    const EngineResult result = run();
    const ssize_t written = write(fds[1], &result, sizeof(result));
    _exit(written == static_cast<ssize_t>(sizeof(result)) ? 0 : 1);
  }
  close(fds[1]);
  EngineResult result;
  std::size_t received = 0;
  auto* bytes = reinterpret_cast<char*>(&result);
  while (received < sizeof(result)) {
    const ssize_t n = read(fds[0], bytes + received, sizeof(result) - received);
    if (n <= 0) break;
    received += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (received != sizeof(result) || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return EngineResult{};
  return result;
}

}  // namespace strata::bench
