// Bullet's convex sweep on the gameplay benchmark's casts: the open world's boxes as btCollisionObjects in a
// btCollisionWorld (DBVT broad phase), each query a btCollisionWorld::convexSweepTest with the closest-hit
// callback, one thread.
#include <btBulletCollisionCommon.h>

#include <chrono>
#include <memory>

#include "tools/bench/GameplayBench.h"

namespace strata::bench {

namespace {

btVector3 ToBullet(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

CastRun MeasureBulletCasts(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape,
                           int repeats) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broad_phase;
  btCollisionWorld collision_world(&dispatcher, &broad_phase, &configuration);
  std::vector<std::unique_ptr<btBoxShape>> boxes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  for (const AABB& bounds : world.bounds) {
    boxes.push_back(std::make_unique<btBoxShape>(ToBullet(bounds.HalfExtents())));
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(boxes.back().get());
    object->setWorldTransform(btTransform(btQuaternion::getIdentity(), ToBullet(bounds.Center())));
    collision_world.addCollisionObject(object.get());
    objects.push_back(std::move(object));
  }
  collision_world.updateAabbs();
  // The same shapes: a 0.5 m sphere, and a capsule of radius 0.3 m around a 1.2 m segment (1.8 m tall).
  btSphereShape sphere(0.5f);
  btCapsuleShape capsule(0.3f, 1.2f);
  const btConvexShape* cast = shape == CastShapeKind::kSphere ? static_cast<btConvexShape*>(&sphere)
                                                              : static_cast<btConvexShape*>(&capsule);
  CastRun run;
  const std::size_t count = queries.ray_origins.size();
  double best = 1e30;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    std::vector<float> fractions(count, -1.0f);
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < count; ++i) {
      const btVector3 from = ToBullet(queries.ray_origins[i]);
      const btVector3 to = from + ToBullet(queries.ray_directions_10m[i]);
      btCollisionWorld::ClosestConvexResultCallback callback(from, to);
      collision_world.convexSweepTest(cast, btTransform(btQuaternion::getIdentity(), from),
                                      btTransform(btQuaternion::getIdentity(), to), callback);
      if (callback.hasHit()) fractions[i] = callback.m_closestHitFraction;
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    run.fractions = std::move(fractions);
  }
  run.casts_per_second = static_cast<double>(count) / best;
  run.hits = static_cast<int>(std::count_if(run.fractions.begin(), run.fractions.end(),
                                            [](float fraction) { return fraction >= 0.0f; }));
  for (const auto& object : objects) collision_world.removeCollisionObject(object.get());
  return run;
}

}  // namespace strata::bench
