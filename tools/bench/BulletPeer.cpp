// The Bullet side of the side-by-side benchmark: the same BenchScene in btDiscreteDynamicsWorld with
// default margins, Bullet's DBVT broad phase and sequential-impulse solver at the scene's iteration count.
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
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
  Vec3 field_offset = Vec3::Zero();
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
      case BenchShape::kHeightField: {
        // Bullet centres a height field on its bounds; its flipped quad edges are Strata's diagonals.
        const auto [low, high] = std::minmax_element(scene.field_heights.begin(), scene.field_heights.end());
        auto field = std::make_unique<btHeightfieldTerrainShape>(
            static_cast<int>(scene.field_columns), static_cast<int>(scene.field_rows),
            scene.field_heights.data(), *low, *high, 1, true);
        field->setLocalScaling(btVector3(scene.field_cell, 1.0f, scene.field_cell));
        field_offset =
            Vec3(0.5f * scene.field_cell * static_cast<float>(scene.field_columns - 1), 0.5f * (*low + *high),
                 0.5f * scene.field_cell * static_cast<float>(scene.field_rows - 1));
        shapes.push_back(std::move(field));
        break;
      }
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
    transform.setOrigin(ToBullet(body.shape == BenchShape::kHeightField ? Vec3(body.position + field_offset)
                                                                        : body.position));
    transform.setRotation(
        btQuaternion(body.rotation.x(), body.rotation.y(), body.rotation.z(), body.rotation.w()));
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

  // Joints with Bullet's matching constraints; joined bodies do not collide, as in Strata.
  std::vector<std::unique_ptr<btTypedConstraint>> joints;
  for (const BenchJoint& joint : scene.joints) {
    btRigidBody& b = *bodies[joint.body_b];
    btRigidBody& a = joint.body_a >= 0 ? *bodies[joint.body_a] : btTypedConstraint::getFixedBody();
    // The joint's frame (x = its axis) in each body's frame.
    Mat3 axes;
    axes.col(0) = joint.axis.normalized();
    axes.col(1) = (joint.normal - joint.normal.dot(axes.col(0)) * axes.col(0)).normalized();
    axes.col(2) = axes.col(0).cross(axes.col(1));
    auto frame_in = [&](const btRigidBody& body, const Mat3& world_axes) {
      const btTransform inverse = body.getWorldTransform().inverse();
      btMatrix3x3 basis;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) basis[r][c] = world_axes(r, c);
      return btTransform(inverse.getBasis() * basis, inverse * ToBullet(joint.anchor));
    };
    switch (joint.kind) {
      case BenchJointKind::kPoint: {
        const btTransform in_a = frame_in(a, axes), in_b = frame_in(b, axes);
        joints.push_back(std::make_unique<btPoint2PointConstraint>(a, b, in_a.getOrigin(), in_b.getOrigin()));
        break;
      }
      case BenchJointKind::kHinge: {
        // Bullet's hinge turns about its frame's z.
        Mat3 hinge_axes;
        hinge_axes.col(0) = axes.col(1);
        hinge_axes.col(1) = axes.col(2);
        hinge_axes.col(2) = axes.col(0);
        auto hinge =
            std::make_unique<btHingeConstraint>(a, b, frame_in(a, hinge_axes), frame_in(b, hinge_axes));
        hinge->setLimit(joint.min_angle, joint.max_angle);
        joints.push_back(std::move(hinge));
        break;
      }
      case BenchJointKind::kSwingTwist: {
        // Bullet's cone twists about its frame's x; both swing spans are the cone's half angle.
        auto cone = std::make_unique<btConeTwistConstraint>(a, b, frame_in(a, axes), frame_in(b, axes));
        cone->setLimit(joint.cone, joint.cone, 0.5f * (joint.max_angle - joint.min_angle));
        joints.push_back(std::move(cone));
        break;
      }
    }
    world.addConstraint(joints.back().get(), true);
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
  for (auto& joint : joints) world.removeConstraint(joint.get());
  for (auto& body : bodies) world.removeRigidBody(body.get());
  return result;
}

}  // namespace strata::bench
