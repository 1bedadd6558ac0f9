#include "tools/bench/BroadPhaseBench.h"

#include <algorithm>
#include <atomic>
#include <barrier>
#include <chrono>
#include <random>
#include <thread>

#include "physics/body/BodyInterface.h"
#include "physics/broadphase/QuadTreeBroadPhase.h"
#include "physics/shapes/BoxShape.h"
#include "physics/world/PhysicsSystem.h"
#include "physics/world/WorldQuery.h"

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;

double MicrosecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

/// The value `fraction` of the way up the sorted values (0.5: the median, 0.99: the 99th percentile).
double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const auto rank = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank), values.end());
  return values[rank];
}

double Median(std::vector<double> values) {
  return Percentile(std::move(values), 0.5);
}

constexpr float kTileSize = 256.0f;
constexpr int kTilesPerRow = 7;

AABB RandomBody(std::mt19937& random, const Vec3& tile_corner, bool is_static) {
  std::uniform_real_distribution<float> across(0.0f, kTileSize), unit(0.0f, 1.0f);
  const Vec3 base = tile_corner + Vec3(across(random), 0.0f, across(random));
  if (is_static) {
    const Vec3 half(0.25f + 3.75f * unit(random), 0.25f + 3.75f * unit(random), 0.25f + 3.75f * unit(random));
    return AABB::FromCenterHalfExtents(base + Vec3(0, half.y(), 0), half);
  }
  const Vec3 half = Vec3::Constant(0.15f + 0.85f * unit(random));
  return AABB::FromCenterHalfExtents(base + Vec3(0, half.y() + 30.0f * unit(random) * unit(random), 0), half);
}

// Counts hits; the cheapest collector, so the figures are the tree's.
class CountingCollector final : public BroadPhaseCollector {
 public:
  void AddHit(BodyID, float) override { ++hits; }
  std::size_t hits = 0;
};

struct QueryTimes {
  double aabb_us, ray_10m_us, ray_100m_us, hits_per_block, hits_per_100m_ray;
};

QueryTimes TimeQueries(const BroadPhase& broad_phase, const QuerySet& queries) {
  QueryTimes times{};
  CountingCollector blocks;
  auto start = Clock::now();
  for (const AABB& block : queries.blocks) broad_phase.CollideAABB(broad_phase.Pin(), block, {}, blocks);
  times.aabb_us = MicrosecondsSince(start) / static_cast<double>(queries.blocks.size());
  times.hits_per_block = static_cast<double>(blocks.hits) / static_cast<double>(queries.blocks.size());
  CountingCollector short_rays;
  start = Clock::now();
  for (std::size_t i = 0; i < queries.ray_origins.size(); ++i)
    broad_phase.CastRay(broad_phase.Pin(), queries.ray_origins[i], queries.ray_directions_10m[i], {},
                        short_rays);
  times.ray_10m_us = MicrosecondsSince(start) / static_cast<double>(queries.ray_origins.size());
  CountingCollector long_rays;
  start = Clock::now();
  for (std::size_t i = 0; i < queries.ray_origins.size(); ++i)
    broad_phase.CastRay(broad_phase.Pin(), queries.ray_origins[i], queries.ray_directions_100m[i], {},
                        long_rays);
  times.ray_100m_us = MicrosecondsSince(start) / static_cast<double>(queries.ray_origins.size());
  times.hits_per_100m_ray =
      static_cast<double>(long_rays.hits) / static_cast<double>(queries.ray_origins.size());
  return times;
}

}  // namespace

OpenWorld MakeOpenWorld(int body_count, int tile_count, unsigned seed) {
  OpenWorld world;
  std::mt19937 random(seed);
  world.tiles.resize(static_cast<std::size_t>(tile_count));
  for (int i = 0; i < body_count; ++i) {
    const int tile = i % tile_count;
    const Vec3 corner(static_cast<float>(tile % kTilesPerRow) * kTileSize, 0.0f,
                      static_cast<float>(tile / kTilesPerRow) * kTileSize);
    const bool is_static = random() % 10 < 7;
    world.bounds.push_back(RandomBody(random, corner, is_static));
    world.layers.push_back(is_static ? layers::kNonMoving : layers::kMoving);
    world.tile_of.push_back(static_cast<std::uint32_t>(tile));
    world.tiles[static_cast<std::size_t>(tile)].push_back(static_cast<std::uint32_t>(i));
    world.extent.Encapsulate(world.bounds.back());
  }
  return world;
}

QuerySet MakeQuerySet(const OpenWorld& world, int count, unsigned seed) {
  QuerySet set;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> x(world.extent.min.x(), world.extent.max.x()),
      z(world.extent.min.z(), world.extent.max.z()), height(0.5f, 10.0f), angle(0.0f, 2.0f * kPi),
      pitch(-0.3f, 0.05f);
  for (int i = 0; i < count; ++i) {
    const Vec3 corner(x(random), 0.0f, z(random));
    set.blocks.emplace_back(corner, corner + Vec3(12.8f, 20.0f, 12.8f));
    set.ray_origins.emplace_back(x(random), height(random), z(random));
    const float a = angle(random);
    const Vec3 direction = Vec3(std::cos(a), pitch(random), std::sin(a)).normalized();
    set.ray_directions_10m.push_back(direction * 10.0f);
    set.ray_directions_100m.push_back(direction * 100.0f);
  }
  return set;
}

BodyID BenchId(std::uint32_t index) {
  return BodyID{index, 1};
}

// Streams the tiles in: prepare on this thread (timed per body), finalize each tile; then a full rebuild.
void StreamIn(QuadTreeBroadPhase& broad_phase, const OpenWorld& world, BroadPhaseFigures& figures) {
  const auto body_count = static_cast<std::uint32_t>(world.bounds.size());
  auto id_of = BenchId;
  double prepare_us = 0.0;
  for (const auto& tile : world.tiles) {
    std::vector<BodyID> ids;
    std::vector<AABB> bounds;
    std::vector<ObjectLayer> layers;
    for (const std::uint32_t i : tile)
      ids.push_back(id_of(i)), bounds.push_back(world.bounds[i]), layers.push_back(world.layers[i]);
    const auto start = Clock::now();
    Result<AddBatch> batch = broad_phase.AddBodiesPrepare(ids, bounds, layers);
    prepare_us += MicrosecondsSince(start);
    (void)broad_phase.AddBodiesFinalize(*batch);
  }
  figures.prepare_per_body_us = prepare_us / body_count;
  auto start = Clock::now();
  broad_phase.Optimize();
  figures.full_rebuild_ms = MicrosecondsSince(start) / 1000.0;
}

// Finalize cost per batch size (prepared beforehand, removed again afterwards).
void MeasureFinalize(QuadTreeBroadPhase& broad_phase, const OpenWorld& world, BroadPhaseFigures& figures) {
  const auto body_count = static_cast<std::uint32_t>(world.bounds.size());
  auto id_of = BenchId;
  Clock::time_point start;
  std::mt19937 random(9);
  std::uniform_real_distribution<float> x(world.extent.min.x(), world.extent.max.x()),
      z(world.extent.min.z(), world.extent.max.z());
  for (const int size : kBatchSizes) {
    const int repetitions = size <= 100 ? 200 : size <= 1000 ? 20 : 5;
    std::vector<double> samples;
    for (int r = 0; r < repetitions; ++r) {
      std::vector<BodyID> ids;
      std::vector<AABB> bounds;
      std::vector<ObjectLayer> layers(static_cast<std::size_t>(size), layers::kMoving);
      for (int i = 0; i < size; ++i) {
        ids.push_back(id_of(body_count + static_cast<std::uint32_t>(i)));
        bounds.push_back(AABB::FromCenterHalfExtents(Vec3(x(random), 2.0f, z(random)), Vec3::Constant(0.5f)));
      }
      Result<AddBatch> batch = broad_phase.AddBodiesPrepare(ids, bounds, layers);
      start = Clock::now();
      (void)broad_phase.AddBodiesFinalize(*batch);
      samples.push_back(MicrosecondsSince(start));
      (void)broad_phase.RemoveBodies(ids);
      broad_phase.Update();
    }
    figures.finalize_us.push_back(Median(samples));
  }
}

// Removes single bodies, then streams them back in.
void MeasureRemove(QuadTreeBroadPhase& broad_phase, const OpenWorld& world, BroadPhaseFigures& figures) {
  const auto body_count = static_cast<std::uint32_t>(world.bounds.size());
  auto id_of = BenchId;
  std::vector<BodyID> victims;
  for (std::uint32_t i = 0; i < body_count; i += 10) victims.push_back(id_of(i));
  auto start = Clock::now();
  for (const BodyID id : victims) (void)broad_phase.RemoveBody(id);
  figures.remove_us = MicrosecondsSince(start) / static_cast<double>(victims.size());
  {
    std::vector<AABB> bounds;
    std::vector<ObjectLayer> layers;
    for (const BodyID id : victims)
      bounds.push_back(world.bounds[id.index]), layers.push_back(world.layers[id.index]);
    Result<AddBatch> batch = broad_phase.AddBodiesPrepare(victims, bounds, layers);
    (void)broad_phase.AddBodiesFinalize(*batch);
    broad_phase.Optimize();
  }
}

// A step's worth of moving bodies, then the incremental rebuild the step runs.
void MeasureMoves(QuadTreeBroadPhase& broad_phase, const OpenWorld& world,
                  const std::vector<std::uint32_t>& dynamic, BroadPhaseFigures& figures) {
  auto id_of = BenchId;
  Clock::time_point start;
  std::vector<double> move_samples, rebuild_samples;
  for (int round = 0; round < 20; ++round) {
    start = Clock::now();
    for (std::size_t k = 0; k < 600; ++k) {
      const std::uint32_t i = dynamic[(static_cast<std::size_t>(round) * 600 + k * 7) % dynamic.size()];
      const Vec3 nudge(0.05f * static_cast<float>(round % 3), -0.1f, 0.05f);
      (void)broad_phase.UpdateBody(id_of(i), AABB(world.bounds[i].min + nudge, world.bounds[i].max + nudge));
    }
    move_samples.push_back(MicrosecondsSince(start) / 600.0);
    start = Clock::now();
    broad_phase.Update();
    rebuild_samples.push_back(MicrosecondsSince(start) / 1000.0);
  }
  figures.move_us = Median(move_samples);
  figures.incremental_rebuild_ms = Median(rebuild_samples);
  broad_phase.Optimize();
}

// The queries again while two threads remove, re-add (as batches) and move their own dynamic bodies.
void MeasureQueriesUnderChurn(QuadTreeBroadPhase& broad_phase, const OpenWorld& world,
                              const std::vector<std::uint32_t>& dynamic, const QuerySet& queries,
                              BroadPhaseFigures& figures) {
  auto id_of = BenchId;
  // The same queries while two threads remove, re-add (as batches) and move their own dynamic bodies.
  std::atomic<bool> stop{false};
  // Two threads change their own dynamic bodies at a game's pace: every 16 ms frame each removes 100 and
  // streams them back in as 10 batches, and moves 1000; the first also runs the step's rebuild each frame.
  // Each thread owns up to 1000 dynamic bodies from its half of them.
  auto churn = [&](std::size_t half) {
    std::mt19937 churn_random(static_cast<unsigned>(half + 1));
    const std::size_t first = half * dynamic.size() / 2;
    const std::size_t count = std::min<std::size_t>(1000, dynamic.size() / 2);
    std::vector<std::uint32_t> mine(dynamic.begin() + static_cast<std::ptrdiff_t>(first),
                                    dynamic.begin() + static_cast<std::ptrdiff_t>(first + count));
    while (!stop.load(std::memory_order_relaxed)) {
      const auto frame_end = Clock::now() + std::chrono::milliseconds(16);
      for (int batch_number = 0; batch_number < 10; ++batch_number) {
        std::vector<BodyID> out;
        std::vector<AABB> bounds;
        std::vector<ObjectLayer> layers;
        for (int k = 0; k < 10; ++k) {
          const std::uint32_t i = mine[churn_random() % mine.size()];
          if (std::find(out.begin(), out.end(), id_of(i)) != out.end()) continue;
          out.push_back(id_of(i)), bounds.push_back(world.bounds[i]), layers.push_back(layers::kMoving);
        }
        (void)broad_phase.RemoveBodies(out);
        Result<AddBatch> batch = broad_phase.AddBodiesPrepare(out, bounds, layers);
        if (batch) (void)broad_phase.AddBodiesFinalize(*batch);
      }
      for (int k = 0; k < 1000; ++k) {
        const std::uint32_t i = mine[churn_random() % mine.size()];
        (void)broad_phase.UpdateBody(id_of(i), world.bounds[i].Expanded(0.01f * static_cast<float>(k % 5)));
      }
      if (half == 0) broad_phase.Update();
      std::this_thread::sleep_until(frame_end);
    }
  };
  std::thread first_churn(churn, 0), second_churn(churn, 1);
  const QueryTimes busy = TimeQueries(broad_phase, queries);
  stop = true;
  first_churn.join();
  second_churn.join();
  figures.aabb_query_busy_us = busy.aabb_us, figures.ray_10m_busy_us = busy.ray_10m_us;
  figures.ray_100m_busy_us = busy.ray_100m_us;
}

BroadPhaseFigures MeasureStrata(const OpenWorld& world, const QuerySet& queries) {
  BroadPhaseFigures figures;
  const auto body_count = static_cast<std::uint32_t>(world.bounds.size());
  constexpr std::uint32_t kExtra = 10000;
  QuadTreeBroadPhase broad_phase(body_count + kExtra + 16, std::make_shared<DefaultLayerSetup>());
  StreamIn(broad_phase, world, figures);
  MeasureFinalize(broad_phase, world, figures);
  MeasureRemove(broad_phase, world, figures);
  std::vector<std::uint32_t> dynamic;
  for (std::uint32_t i = 0; i < body_count; ++i)
    if (world.layers[i] == layers::kMoving) dynamic.push_back(i);
  MeasureMoves(broad_phase, world, dynamic, figures);
  const QueryTimes idle = TimeQueries(broad_phase, queries);
  figures.aabb_query_us = idle.aabb_us, figures.ray_10m_us = idle.ray_10m_us,
  figures.ray_100m_us = idle.ray_100m_us;
  figures.hits_per_block = idle.hits_per_block, figures.hits_per_100m_ray = idle.hits_per_100m_ray;

  MeasureQueriesUnderChurn(broad_phase, world, dynamic, queries, figures);
  return figures;
}

// Static level geometry and kinematic game objects (they move only when the game moves them); returns the
// objects.
std::vector<BodyID> AddOpenWorld(BodyInterface& bodies, const OpenWorld& world) {
  std::vector<BodyID> objects;
  for (const auto& tile : world.tiles) {
    std::vector<BodyID> batch;
    for (const std::uint32_t i : tile) {
      BodyCreationSettings settings;
      settings.shape = *BoxShape::Create(world.bounds[i].HalfExtents());
      settings.position = world.bounds[i].Center();
      const bool is_static = world.layers[i] == layers::kNonMoving;
      settings.motion_type = is_static ? MotionType::kStatic : MotionType::kKinematic;
      settings.object_layer = world.layers[i];
      const BodyID id = *bodies.CreateBody(settings);
      batch.push_back(id);
      if (!is_static) objects.push_back(id);
    }
    (void)bodies.AddBodies(batch);
  }
  return objects;
}

// The lock-wait figures over every thread's frames.
void SummarizeLockWaits(const std::vector<std::vector<double>>& waits,
                        const std::vector<std::uint64_t>& acquisitions,
                        const std::vector<std::uint64_t>& contended, int threads, int frames,
                        GameObjectFigures& figures) {
  std::vector<double> all_waits;
  for (const auto& per_thread : waits)
    all_waits.insert(all_waits.end(), per_thread.begin(), per_thread.end());
  double total = 0.0;
  for (const double wait : all_waits)
    total += wait, figures.max_lock_wait_us = std::max(figures.max_lock_wait_us, wait);
  figures.lock_wait_us_per_thread_frame =
      all_waits.empty() ? 0.0 : total / static_cast<double>(all_waits.size());
  figures.median_lock_wait_us = Median(all_waits);
  const double thread_frames = static_cast<double>(threads) * static_cast<double>(frames);
  for (int t = 0; t < threads; ++t) {
    const auto thread = static_cast<std::size_t>(t);
    figures.acquisitions_per_thread_frame += static_cast<double>(acquisitions[thread]) / thread_frames;
    figures.contended_per_thread_frame += static_cast<double>(contended[thread]) / thread_frames;
  }
  figures.p99_lock_wait_us = Percentile(all_waits, 0.99);
}

GameObjectFigures MeasureGameObjectUpdate(const OpenWorld& world, int threads, std::uint32_t mutexes,
                                          int frames, double work_us) {
  GameObjectFigures figures;
  figures.threads = threads;
  figures.mutexes = mutexes;
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(world.bounds.size()) + 16;
  config.body_mutex_count = mutexes;
  config.job_system = std::make_shared<SerialJobSystem>();
  auto system = std::move(*PhysicsSystem::Create(config));
  BodyInterface& bodies = system->bodies();
  const std::vector<BodyID> objects = AddOpenWorld(bodies, world);
  system->broad_phase().Optimize();

  // Each thread takes a contiguous range of the game objects, as a parallel-for over them would.
  std::vector<std::vector<BodyID>> owned(static_cast<std::size_t>(threads));
  for (std::size_t k = 0; k < objects.size(); ++k)
    owned[k * static_cast<std::size_t>(threads) / objects.size()].push_back(objects[k]);
  std::vector<std::vector<double>> waits(static_cast<std::size_t>(threads));
  std::vector<std::uint64_t> acquisitions(static_cast<std::size_t>(threads), 0);
  std::vector<std::uint64_t> contended(static_cast<std::size_t>(threads), 0);
  std::vector<double> frame_ms;
  Clock::time_point frame_start;
  std::barrier sync(threads, [&]() noexcept {
    const auto now = Clock::now();
    if (frame_start != Clock::time_point{})
      frame_ms.push_back(std::chrono::duration<double, std::milli>(now - frame_start).count());
    frame_start = now;
  });
  auto update = [&](int t) {
    const std::vector<BodyID>& mine = owned[static_cast<std::size_t>(t)];
    sync.arrive_and_wait();
    for (int frame = 0; frame < frames; ++frame) {
      const std::uint64_t before = ThreadBodyLockWaitNanoseconds();
      const BodyLockCounts counts_before = ThreadBodyLockCounts();
      const float sway = 0.05f * static_cast<float>(frame % 2 == 0 ? 1 : -1);
      for (std::size_t k = 0; k < mine.size(); ++k) {
        // The object's own game logic, outside any lock.
        if (work_us > 0.0) {
          const auto busy_until = Clock::now() + std::chrono::duration<double, std::micro>(work_us);
          while (Clock::now() < busy_until) {
          }
        }
        const Vec3 position = *bodies.GetPosition(mine[k]);
        (void)bodies.SetPosition(mine[k], position + Vec3(sway, 0, 0));
        if (k % 4 == 0) (void)system->query().CastRay(position + Vec3(0, 2, 0), Vec3(0, -10, 0));
      }
      waits[static_cast<std::size_t>(t)].push_back(
          static_cast<double>(ThreadBodyLockWaitNanoseconds() - before) / 1000.0);
      const BodyLockCounts counts_after = ThreadBodyLockCounts();
      acquisitions[static_cast<std::size_t>(t)] += counts_after.acquisitions - counts_before.acquisitions;
      contended[static_cast<std::size_t>(t)] += counts_after.contended - counts_before.contended;
      sync.arrive_and_wait();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(update, t);
  for (std::thread& thread : pool) thread.join();
  SummarizeLockWaits(waits, acquisitions, contended, threads, frames, figures);
  figures.frame_ms = Median(frame_ms);
  return figures;
}

}  // namespace strata::bench
