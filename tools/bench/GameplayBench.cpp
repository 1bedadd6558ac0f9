#include "tools/bench/GameplayBench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
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
    // Sharp: the casts' exact answers are measured on sharp boxes.
    box.shape = *BoxShape::Create(open.bounds[i].HalfExtents(), 0.0f);
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

namespace {

// The open world's boxes by their low x, so that a cast looks only at the run its sweep can reach, and the
// exact gap between them and the cast shape's core (a point or an upright segment) with its radius.
class BoxesNearCasts {
 public:
  BoxesNearCasts(const OpenWorld& world, CastShapeKind shape)
      : world_(world),
        radius_(shape == CastShapeKind::kSphere ? 0.5 : 0.3),
        half_height_(shape == CastShapeKind::kSphere ? 0.0 : 0.6),
        by_x_(world.bounds.size()) {
    for (std::uint32_t i = 0; i < by_x_.size(); ++i) by_x_[i] = i;
    std::sort(by_x_.begin(), by_x_.end(), [&](std::uint32_t a, std::uint32_t b) {
      return world.bounds[a].min.x() < world.bounds[b].min.x();
    });
    for (const AABB& box : world.bounds) widest_ = std::max(widest_, box.max.x() - box.min.x());
  }

  // Every box the shape can touch sweeping from `from` to `to`.
  template <class Visit>
  void ForEachNear(const Vec3& from, const Vec3& to, Visit visit) const {
    const Vec3 reach(static_cast<float>(radius_), static_cast<float>(radius_ + half_height_),
                     static_cast<float>(radius_));
    const AABB swept(from.cwiseMin(to) - reach, from.cwiseMax(to) + reach);
    const auto first =
        std::lower_bound(by_x_.begin(), by_x_.end(), swept.min.x() - widest_,
                         [&](std::uint32_t i, float x) { return world_.bounds[i].min.x() < x; });
    for (auto it = first; it != by_x_.end() && world_.bounds[*it].min.x() <= swept.max.x(); ++it)
      if (world_.bounds[*it].Overlaps(swept)) visit(world_.bounds[*it]);
  }

  // Negative where the shape at `centre` overlaps the box.
  double Gap(const AABB& box, const Eigen::Vector3d& centre) const {
    const auto outside = [](double value, double from, double to) {
      return std::max({from - value, value - to, 0.0});
    };
    const double dx = outside(centre.x(), box.min.x(), box.max.x());
    const double dz = outside(centre.z(), box.min.z(), box.max.z());
    const double dy =
        std::max({box.min.y() - (centre.y() + half_height_), (centre.y() - half_height_) - box.max.y(), 0.0});
    return std::sqrt(dx * dx + dy * dy + dz * dz) - radius_;
  }

 private:
  const OpenWorld& world_;
  double radius_, half_height_;
  std::vector<std::uint32_t> by_x_;
  float widest_ = 0.0f;
};

// The first touch of the sweep origin + t direction (t in [0, 1]) with one box, 2 for none. The gap is convex
// in t: the lowest by ternary search, then the first zero before it by bisection.
double FirstTouch(const BoxesNearCasts& boxes, const AABB& box, const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& direction) {
  const auto gap = [&](double t) { return boxes.Gap(box, origin + t * direction); };
  if (gap(0.0) <= 0.0) return 0.0;
  double low = 0.0, high = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double a = low + (high - low) / 3.0, b = high - (high - low) / 3.0;
    if (gap(a) < gap(b))
      high = b;
    else
      low = a;
  }
  double touching = 0.5 * (low + high);
  if (gap(touching) > 0.0) return 2.0;
  double before = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double middle = 0.5 * (before + touching);
    if (gap(middle) > 0.0)
      before = middle;
    else
      touching = middle;
  }
  return touching;
}

}  // namespace

std::vector<float> ExactCastFractions(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape) {
  const BoxesNearCasts boxes(world, shape);
  std::vector<float> fractions(queries.ray_origins.size(), -1.0f);
  for (std::size_t c = 0; c < fractions.size(); ++c) {
    const Eigen::Vector3d origin = queries.ray_origins[c].cast<double>();
    const Eigen::Vector3d direction = queries.ray_directions_10m[c].cast<double>();
    double nearest = 2.0;
    boxes.ForEachNear(
        queries.ray_origins[c], queries.ray_origins[c] + queries.ray_directions_10m[c],
        [&](const AABB& box) { nearest = std::min(nearest, FirstTouch(boxes, box, origin, direction)); });
    if (nearest <= 1.0) fractions[c] = static_cast<float>(nearest);
  }
  return fractions;
}

std::vector<double> ExactGapsAt(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape,
                                const std::vector<float>& fractions) {
  const BoxesNearCasts boxes(world, shape);
  std::vector<double> gaps(fractions.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t c = 0; c < std::min(fractions.size(), queries.ray_origins.size()); ++c) {
    if (fractions[c] < 0.0f) continue;
    const Eigen::Vector3d centre = queries.ray_origins[c].cast<double>() +
                                   double{fractions[c]} * queries.ray_directions_10m[c].cast<double>();
    const Vec3 at = queries.ray_origins[c] + fractions[c] * queries.ray_directions_10m[c];
    const Vec3 nearby = Vec3::Constant(0.1f);  // any gap a hit leaves is far below this
    double nearest = std::numeric_limits<double>::infinity();
    boxes.ForEachNear(at - nearby, at + nearby,
                      [&](const AABB& box) { nearest = std::min(nearest, boxes.Gap(box, centre)); });
    gaps[c] = nearest;
  }
  return gaps;
}

CastAccuracy MeasureCastAccuracy(const CastRun& run, const std::vector<float>& exact,
                                 const std::vector<double>& gaps, float cast_length) {
  CastAccuracy accuracy;
  double total_mm = 0.0;
  int both = 0;
  for (std::size_t i = 0; i < std::min(run.fractions.size(), exact.size()); ++i) {
    const float hit = run.fractions[i], truth = exact[i];
    if (truth >= 0.0f) ++accuracy.exact_hits;
    if (truth == 0.0f) ++accuracy.starts_inside;
    if (truth >= 0.0f && hit < 0.0f) {
      ++accuracy.missed;
      if (truth == 0.0f) ++accuracy.missed_inside;
    }
    if (truth < 0.0f && hit >= 0.0f) ++accuracy.false_hits;
    if (hit >= 0.0f && i < gaps.size() && gaps[i] == gaps[i]) {
      accuracy.widest_gap_mm = std::max(accuracy.widest_gap_mm, 1000.0 * gaps[i]);
      if (truth != 0.0f)
        accuracy.deepest_overlap_mm = std::max(accuracy.deepest_overlap_mm, -1000.0 * gaps[i]);
    }
    if (truth < 0.0f || hit < 0.0f) continue;
    const double error_mm = 1000.0 * static_cast<double>(cast_length) * (static_cast<double>(hit) - truth);
    accuracy.earliest_mm = std::min(accuracy.earliest_mm, error_mm);
    accuracy.latest_mm = std::max(accuracy.latest_mm, error_mm);
    if (std::abs(error_mm) <= 1.0) ++accuracy.within_1mm;
    total_mm += std::abs(error_mm);
    ++both;
  }
  if (both > 0) accuracy.mean_abs_mm = total_mm / both;
  return accuracy;
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
    // A step's median, not its mean: a preempted step or a warm-up step that grows the event arrays says
    // nothing about what reporting costs in a running game.
    quiet_ms.push_back(without.median_step_ms);
    reporting_ms.push_back(with.median_step_ms);
    figures.events_per_step = with.contact_events_per_step;
    figures.threads = with.threads;
  }
  figures.quiet_step_ms = Median(quiet_ms);
  figures.reporting_step_ms = Median(reporting_ms);
  return figures;
}

Result<CharacterFigures> MeasureCharacterUpdates(const std::string& level_path, int walkers, int frames) {
  CharacterFigures figures;
  PhysicsSystemConfig config;
  config.job_system = std::make_shared<SerialJobSystem>();
  auto world = std::move(*PhysicsSystem::Create(config));
  const Result<LoadedLevel> level = LoadLevel(*world, level_path);
  if (!level) return level.error();
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
