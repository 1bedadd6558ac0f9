#include "tools/bench/GameplayBench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "assets/level/LevelLoader.h"
#include "physics/body/BodyInterface.h"
#include "physics/character/Character.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/world/PhysicsSystem.h"
#include "physics/world/WorldQuery.h"
#include "tools/bench/BenchRunner.h"

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The open world's bodies as static boxes of their bounds, in one world, its broad phase built whole.
std::unique_ptr<PhysicsSystem> BoxWorld(const OpenWorld& open) {
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(open.bounds.size()) + 16;
  config.job_system = std::make_shared<SerialJobSystem>();
  auto world = std::move(*PhysicsSystem::Create(config));
  std::vector<BodyID> ids;
  for (std::size_t i = 0; i < open.bounds.size(); ++i) {
    BodyCreationSettings box;
    box.shape = *BoxShape::Create(open.bounds[i].HalfExtents());
    box.position = open.bounds[i].Center();
    box.motion_type = MotionType::kStatic;
    box.object_layer = open.layers[i];
    ids.push_back(*world->bodies().CreateBody(box));
  }
  (void)world->bodies().AddBodies(ids);
  world->broad_phase().Optimize();
  return world;
}

ShapeRef CastShapeOf(CastShapeKind kind) {
  return kind == CastShapeKind::kSphere ? *SphereShape::Create(0.5f) : *CapsuleShape::Create(0.6f, 0.3f);
}

}  // namespace

const char* ToString(CastShapeKind kind) {
  return kind == CastShapeKind::kSphere ? "sphere 0.5 m" : "capsule 0.3 x 1.8 m";
}

CastRun MeasureStrataCasts(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape,
                           int repeats) {
  const std::unique_ptr<PhysicsSystem> boxes = BoxWorld(world);
  const ShapeRef cast = CastShapeOf(shape);
  const WorldQuery& query = boxes->query();
  CastRun run;
  const std::size_t count = queries.ray_origins.size();
  double best = 1e30;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    std::vector<float> fractions(count, -1.0f);
    const auto start = Clock::now();
    for (std::size_t i = 0; i < count; ++i) {
      const auto hit = query.CastShape(*cast, Pose{queries.ray_origins[i], Quat::Identity()},
                                       queries.ray_directions_10m[i]);
      if (hit.ok() && hit->has_value()) fractions[i] = (*hit)->fraction;
    }
    best = std::min(best, SecondsSince(start));
    run.fractions = std::move(fractions);
  }
  run.casts_per_second = static_cast<double>(count) / best;
  run.hits = static_cast<int>(std::count_if(run.fractions.begin(), run.fractions.end(),
                                            [](float fraction) { return fraction >= 0.0f; }));
  return run;
}

CastAgreement CompareCasts(const CastRun& a, const CastRun& b, float tolerance) {
  CastAgreement agreement;
  for (std::size_t i = 0; i < std::min(a.fractions.size(), b.fractions.size()); ++i) {
    const float fa = a.fractions[i], fb = b.fractions[i];
    if (fa >= 0.0f && fb < 0.0f) (fa == 0.0f ? agreement.only_a_at_start : agreement.only_a) += 1;
    if (fb >= 0.0f && fa < 0.0f) ++agreement.only_b;
    if (fa < 0.0f || fb < 0.0f) continue;
    ++agreement.both_hit;
    if (std::abs(fa - fb) <= tolerance)
      ++agreement.same_place;
    else
      (fa < fb ? agreement.a_earlier : agreement.b_earlier) += 1;
  }
  return agreement;
}

EventFigures MeasureEventCost(int threads, int steps, int rounds) {
  EventFigures figures;
  BenchScene quiet = MakePyramid();
  quiet.steps = steps;
  BenchScene reporting = quiet;
  reporting.report_contacts = true;
  std::vector<double> quiet_ms, reporting_ms;
  // Alternated, so that a slow spell of a shared machine falls on both.
  for (int round = 0; round < rounds; ++round) {
    const EngineResult without = RunIsolated([&] { return RunStrata(quiet, threads); });
    const EngineResult with = RunIsolated([&] { return RunStrata(reporting, threads); });
    if (!without.ok || !with.ok) return figures;
    quiet_ms.push_back(without.mean_step_ms);
    reporting_ms.push_back(with.mean_step_ms);
    figures.events_per_step = with.contact_events_per_step;
    figures.threads = with.threads;
  }
  figures.quiet_step_ms = Median(quiet_ms);
  figures.reporting_step_ms = Median(reporting_ms);
  return figures;
}

CharacterFigures MeasureCharacterUpdates(const std::string& level_path, int walkers, int frames) {
  CharacterFigures figures;
  PhysicsSystemConfig config;
  config.job_system = std::make_shared<SerialJobSystem>();
  auto world = std::move(*PhysicsSystem::Create(config));
  const Result<LoadedLevel> level = LoadLevel(*world, level_path);
  if (!level) return figures;
  std::mt19937 random(5);
  std::uniform_real_distribution<float> x(level->bounds.min.x(), level->bounds.max.x());
  std::uniform_real_distribution<float> z(level->bounds.min.z(), level->bounds.max.z());
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<std::unique_ptr<Character>> characters;
  for (int attempt = 0; attempt < 100 * walkers && static_cast<int>(characters.size()) < walkers; ++attempt) {
    const auto floor =
        world->query().CastRay(Vec3(x(random), level->bounds.max.y() + 2.0f, z(random)), Vec3(0, -100, 0));
    if (!floor.ok() || !floor->has_value() || (*floor)->normal.y() < 0.7f) continue;
    auto character = Character::Create(*world, {}, (*floor)->position + Vec3(0, 0.05f, 0));
    if (character) characters.push_back(std::move(*character));
  }
  std::vector<Vec3> velocities(characters.size(), Vec3::Zero());
  std::vector<double> times;
  for (int frame = 0; frame < frames; ++frame) {
    for (std::size_t k = 0; k < characters.size(); ++k) {
      if (frame % 60 == 0) {
        const float angle = 6.2832f * unit(random), speed = 1.0f + 4.0f * unit(random);
        velocities[k] = Vec3(speed * std::cos(angle), 0.0f, speed * std::sin(angle));
      }
      const auto start = Clock::now();
      (void)characters[k]->Update(1.0f / 60.0f, velocities[k], Vec3(0, -9.81f, 0));
      times.push_back(SecondsSince(start) * 1e6);
    }
  }
  if (times.empty()) return figures;
  figures.updates = static_cast<int>(times.size());
  double total = 0.0;
  for (const double t : times) total += t;
  figures.mean_us = total / static_cast<double>(times.size());
  std::sort(times.begin(), times.end());
  figures.median_us = times[times.size() / 2];
  figures.p99_us = times[times.size() * 99 / 100];
  figures.max_us = times.back();
  return figures;
}

}  // namespace strata::bench
