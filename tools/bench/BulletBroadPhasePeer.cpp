// Bullet's btDbvtBroadphase on the broad-phase benchmark's work, for the side-by-side figures. Its pair
// cache is never asked for pairs here, so every figure is the dynamic AABB tree's own cost.
#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <chrono>
#include <random>

#include "tools/bench/BroadPhaseBench.h"

namespace strata::bench {

namespace {

using Clock = std::chrono::steady_clock;

double MicrosecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

btVector3 ToBullet(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

class CountingAabbCallback final : public btBroadphaseAabbCallback {
 public:
  bool process(const btBroadphaseProxy*) override {
    ++hits;
    return true;
  }
  std::size_t hits = 0;
};

class CountingRayCallback final : public btBroadphaseRayCallback {
 public:
  // Set up as btCollisionWorld::rayTest does for its own ray callback.
  CountingRayCallback(const btVector3& from, const btVector3& to) {
    btVector3 direction = to - from;
    direction.normalize();
    for (int axis = 0; axis < 3; ++axis) {
      m_rayDirectionInverse[axis] =
          direction[axis] == btScalar(0.0) ? btScalar(BT_LARGE_FLOAT) : btScalar(1.0) / direction[axis];
      m_signs[axis] = m_rayDirectionInverse[axis] < 0.0 ? 1 : 0;
    }
    m_lambda_max = direction.dot(to - from);
  }
  bool process(const btBroadphaseProxy*) override {
    ++hits;
    return true;
  }
  std::size_t hits = 0;
};

// Bullet's DBVT with one proxy slot per body of the world and room for the batches.
class BulletBroadPhase {
 public:
  explicit BulletBroadPhase(std::size_t slots) : dispatcher_(&configuration_), proxies_(slots, nullptr) {}
  ~BulletBroadPhase() {
    for (btBroadphaseProxy* proxy : proxies_)
      if (proxy != nullptr) broad_phase_.destroyProxy(proxy, &dispatcher_);
  }
  BulletBroadPhase(const BulletBroadPhase&) = delete;
  BulletBroadPhase& operator=(const BulletBroadPhase&) = delete;

  void Create(std::size_t i, const AABB& bounds, ObjectLayer layer) {
    const bool is_static = layer == layers::kNonMoving;
    proxies_[i] = broad_phase_.createProxy(
        ToBullet(bounds.min), ToBullet(bounds.max), BOX_SHAPE_PROXYTYPE, nullptr,
        is_static ? int(btBroadphaseProxy::StaticFilter) : int(btBroadphaseProxy::DefaultFilter),
        is_static ? int(btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter)
                  : int(btBroadphaseProxy::AllFilter),
        &dispatcher_);
  }
  void Destroy(std::size_t i) {
    broad_phase_.destroyProxy(proxies_[i], &dispatcher_);
    proxies_[i] = nullptr;
  }
  void Move(std::size_t i, const AABB& bounds) {
    broad_phase_.setAabb(proxies_[i], ToBullet(bounds.min), ToBullet(bounds.max), &dispatcher_);
  }
  btDbvtBroadphase& tree() { return broad_phase_; }

 private:
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broad_phase_;
  std::vector<btBroadphaseProxy*> proxies_;
};

double MedianOf(std::vector<double> samples) {
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(samples.size() / 2),
                   samples.end());
  return samples[samples.size() / 2];
}

// Bullet has no batch insertion: the streamed tiles, then batches of each size, go in one proxy at a time.
void MeasureAdds(BulletBroadPhase& bullet, const OpenWorld& world, BroadPhaseFigures& figures) {
  const std::size_t body_count = world.bounds.size();
  auto start = Clock::now();
  for (const auto& tile : world.tiles)
    for (const std::uint32_t i : tile) bullet.Create(i, world.bounds[i], world.layers[i]);
  figures.prepare_per_body_us = MicrosecondsSince(start) / static_cast<double>(body_count);
  start = Clock::now();
  bullet.tree().optimize();
  figures.full_rebuild_ms = MicrosecondsSince(start) / 1000.0;
  std::mt19937 random(9);
  std::uniform_real_distribution<float> x(world.extent.min.x(), world.extent.max.x()),
      z(world.extent.min.z(), world.extent.max.z());
  for (const int size : kBatchSizes) {
    const int repetitions = size <= 100 ? 200 : size <= 1000 ? 20 : 5;
    std::vector<double> samples;
    for (int r = 0; r < repetitions; ++r) {
      std::vector<AABB> bounds;
      for (int i = 0; i < size; ++i)
        bounds.push_back(AABB::FromCenterHalfExtents(Vec3(x(random), 2.0f, z(random)), Vec3::Constant(0.5f)));
      start = Clock::now();
      for (int i = 0; i < size; ++i)
        bullet.Create(body_count + static_cast<std::size_t>(i), bounds[static_cast<std::size_t>(i)],
                      layers::kMoving);
      samples.push_back(MicrosecondsSince(start));
      for (int i = 0; i < size; ++i) bullet.Destroy(body_count + static_cast<std::size_t>(i));
    }
    figures.finalize_us.push_back(MedianOf(std::move(samples)));
  }
}

void MeasureRemovesAndMoves(BulletBroadPhase& bullet, const OpenWorld& world, BroadPhaseFigures& figures) {
  const std::size_t body_count = world.bounds.size();
  std::vector<std::size_t> victims;
  for (std::size_t i = 0; i < body_count; i += 10) victims.push_back(i);
  auto start = Clock::now();
  for (const std::size_t i : victims) bullet.Destroy(i);
  figures.remove_us = MicrosecondsSince(start) / static_cast<double>(victims.size());
  for (const std::size_t i : victims) bullet.Create(i, world.bounds[i], world.layers[i]);
  bullet.tree().optimize();
  std::vector<std::size_t> dynamic;
  for (std::size_t i = 0; i < body_count; ++i)
    if (world.layers[i] == layers::kMoving) dynamic.push_back(i);
  std::vector<double> move_samples;
  for (int round = 0; round < 20; ++round) {
    start = Clock::now();
    for (std::size_t k = 0; k < 600; ++k) {
      const std::size_t i = dynamic[(static_cast<std::size_t>(round) * 600 + k * 7) % dynamic.size()];
      const Vec3 nudge(0.05f * static_cast<float>(round % 3), -0.1f, 0.05f);
      bullet.Move(i, AABB(world.bounds[i].min + nudge, world.bounds[i].max + nudge));
    }
    move_samples.push_back(MicrosecondsSince(start) / 600.0);
  }
  std::nth_element(move_samples.begin(), move_samples.begin() + 10, move_samples.end());
  figures.move_us = move_samples[10];
  bullet.tree().optimize();
}

void MeasureQueries(BulletBroadPhase& bullet, const QuerySet& queries, BroadPhaseFigures& figures) {
  CountingAabbCallback blocks;
  auto start = Clock::now();
  for (const AABB& block : queries.blocks)
    bullet.tree().aabbTest(ToBullet(block.min), ToBullet(block.max), blocks);
  figures.aabb_query_us = MicrosecondsSince(start) / static_cast<double>(queries.blocks.size());
  figures.hits_per_block = static_cast<double>(blocks.hits) / static_cast<double>(queries.blocks.size());
  for (const bool long_ray : {false, true}) {
    std::size_t hits = 0;
    start = Clock::now();
    for (std::size_t i = 0; i < queries.ray_origins.size(); ++i) {
      const Vec3 to = queries.ray_origins[i] +
                      (long_ray ? queries.ray_directions_100m[i] : queries.ray_directions_10m[i]);
      CountingRayCallback callback(ToBullet(queries.ray_origins[i]), ToBullet(to));
      bullet.tree().rayTest(ToBullet(queries.ray_origins[i]), ToBullet(to), callback);
      hits += callback.hits;
    }
    const double per_ray = MicrosecondsSince(start) / static_cast<double>(queries.ray_origins.size());
    (long_ray ? figures.ray_100m_us : figures.ray_10m_us) = per_ray;
    if (long_ray)
      figures.hits_per_100m_ray = static_cast<double>(hits) / static_cast<double>(queries.ray_origins.size());
  }
}

}  // namespace

BroadPhaseFigures MeasureBullet(const OpenWorld& world, const QuerySet& queries) {
  BroadPhaseFigures figures;
  BulletBroadPhase bullet(world.bounds.size() + 10000);
  MeasureAdds(bullet, world, figures);
  MeasureRemovesAndMoves(bullet, world, figures);
  MeasureQueries(bullet, queries, figures);
  return figures;
}

}  // namespace strata::bench
