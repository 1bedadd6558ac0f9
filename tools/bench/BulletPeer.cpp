// The Bullet side of the side-by-side benchmark: the same BenchScene in btDiscreteDynamicsWorld with
// default margins, Bullet's DBVT broad phase and sequential-impulse solver at the scene's iteration count.
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <memory>
#include <vector>

#include "tools/bench/BenchRunner.h"

namespace strata::bench {

namespace {

btVector3 ToBullet(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

EngineResult RunBullet(const BenchScene& scene) {
  EngineResult result;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, -9.81f, 0));
  // As many passes over the contacts as Strata makes in a step.
  world.getSolverInfo().m_numIterations =
      scene.substeps * (scene.velocity_iterations + scene.relax_iterations);

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motion_states;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<btRigidBody*> dynamic_bodies;
  std::unique_ptr<btTriangleIndexVertexArray> mesh_data;
  btCollisionShape* hull = nullptr;
  std::vector<int> indices;
  for (const auto& triangle : scene.mesh_triangles)
    for (std::uint32_t index : triangle) indices.push_back(static_cast<int>(index));

  for (const BenchBody& body : scene.bodies) {
    btCollisionShape* shape = nullptr;
    switch (body.shape) {
      case BenchShape::kBox:
        shapes.push_back(std::make_unique<btBoxShape>(ToBullet(body.half_extents)));
        break;
      case BenchShape::kSphere:
        shapes.push_back(std::make_unique<btSphereShape>(body.radius));
        break;
      case BenchShape::kCapsule:
        shapes.push_back(std::make_unique<btCapsuleShape>(body.radius, 2.0f * body.half_height));
        break;
      case BenchShape::kHull:
        if (!hull) {
          auto convex = std::make_unique<btConvexHullShape>();
          for (const Vec3& p : scene.hull_points) convex->addPoint(ToBullet(p));
          hull = convex.get();
          shapes.push_back(std::move(convex));
        }
        shape = hull;
        break;
      case BenchShape::kMesh: {
        mesh_data = std::make_unique<btTriangleIndexVertexArray>(
            static_cast<int>(scene.mesh_triangles.size()), indices.data(), 3 * static_cast<int>(sizeof(int)),
            static_cast<int>(scene.mesh_vertices.size()),
            const_cast<btScalar*>(scene.mesh_vertices.front().data()), static_cast<int>(sizeof(Vec3)));
        shapes.push_back(std::make_unique<btBvhTriangleMeshShape>(mesh_data.get(), true));
        break;
      }
    }
    if (!shape) shape = shapes.back().get();
    btTransform transform;
    transform.setIdentity();
    transform.setOrigin(ToBullet(body.position));
    btScalar mass = 0;
    btVector3 inertia(0, 0, 0);
    if (body.dynamic) {
      mass = BenchMass(scene, body);  // the mass Strata gives the same shape at its default density
      shape->calculateLocalInertia(mass, inertia);
    }
    motion_states.push_back(std::make_unique<btDefaultMotionState>(transform));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motion_states.back().get(), shape, inertia);
    info.m_friction = body.friction;
    info.m_restitution = body.restitution;
    bodies.push_back(std::make_unique<btRigidBody>(info));
    if (body.dynamic && !scene.sleeping) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(bodies.back().get());
    if (body.dynamic) dynamic_bodies.push_back(bodies.back().get());
  }

  std::vector<double> times;
  times.reserve(scene.steps);
  for (int step = 0; step < scene.steps; ++step) {
    const auto start = std::chrono::steady_clock::now();
    world.stepSimulation(scene.dt, 0, scene.dt);  // exactly one fixed step, no interpolation
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  SummarizeTimes(std::move(times), result);
  std::vector<FinalPose> poses;
  for (btRigidBody* body : dynamic_bodies) {
    const btTransform& transform = body->getWorldTransform();
    const btQuaternion q = transform.getRotation();
    poses.push_back({Vec3(transform.getOrigin().x(), transform.getOrigin().y(), transform.getOrigin().z()),
                     Quat(q.w(), q.x(), q.y(), q.z())});
  }
  Summarize(scene, poses, result);
  result.bodies = static_cast<int>(scene.bodies.size());
  result.peak_memory_kb = PeakMemoryKb();
  result.ok = true;
  for (auto& body : bodies) world.removeRigidBody(body.get());
  return result;
}

}  // namespace strata::bench
