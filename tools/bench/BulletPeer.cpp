// The Bullet side of the side-by-side benchmark: the same BenchScene in btDiscreteDynamicsWorld with
// default margins, Bullet's DBVT broad phase and sequential-impulse solver at the scene's iteration count.
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "tools/bench/BenchRunner.h"

namespace strata::bench {

namespace {

btVector3 ToBullet(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

// The scene's Bullet objects, declared in the order Bullet needs them torn down in reverse.
class BulletScene {
 public:
  explicit BulletScene(const BenchScene& scene)
      : scene_(scene),
        dispatcher_(&configuration_),
        world_(&dispatcher_, &broadphase_, &solver_, &configuration_) {
    world_.setGravity(btVector3(0, -9.81f, 0));
    // As many passes over the contacts as Strata makes in a step.
    world_.getSolverInfo().m_numIterations =
        scene.substeps * (scene.velocity_iterations + scene.relax_iterations);
    for (const BodyDescription& body : scene.bodies) AddBody(body);
    for (const JointDescription& joint : scene.joints) AddJoint(joint);
  }
  ~BulletScene() {
    for (auto& joint : joints_) world_.removeConstraint(joint.get());
    for (auto& body : bodies_) world_.removeRigidBody(body.get());
  }
  BulletScene(const BulletScene&) = delete;
  BulletScene& operator=(const BulletScene&) = delete;

  EngineResult Run() {
    EngineResult result;
    if (!unsupported_.empty()) {
      std::fprintf(stderr, "bullet peer: scene %s has %s, which the peer does not build\n",
                   scene_.name.c_str(), unsupported_.c_str());
      return result;
    }
    std::vector<double> times;
    times.reserve(scene_.steps);
    for (int step = 0; step < scene_.steps; ++step) {
      const auto start = std::chrono::steady_clock::now();
      world_.stepSimulation(scene_.dt, 0, scene_.dt);  // exactly one fixed step, no interpolation
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      if (ReadsJointGapsAfter(scene_, step)) WidenJointGap(scene_, Poses(), result);
    }
    SummarizeTimes(std::move(times), result);
    Summarize(scene_, Poses(), result);
    result.bodies = static_cast<int>(scene_.bodies.size());
    result.peak_memory_kb = PeakMemoryKb();
    result.ok = true;
    return result;
  }

 private:
  std::vector<FinalPose> Poses() const {
    std::vector<FinalPose> poses;
    poses.reserve(dynamic_bodies_.size());
    for (const btRigidBody* body : dynamic_bodies_) {
      const btTransform& transform = body->getWorldTransform();
      const btQuaternion q = transform.getRotation();
      poses.push_back({Vec3(transform.getOrigin().x(), transform.getOrigin().y(), transform.getOrigin().z()),
                       Quat(q.w(), q.x(), q.y(), q.z())});
    }
    return poses;
  }

  btCollisionShape* ShapeFor(const BodyDescription& body) {
    switch (body.shape) {
      case SceneShape::kBox:
        return Keep(std::make_unique<btBoxShape>(ToBullet(body.half_extents)));
      case SceneShape::kSphere:
        return Keep(std::make_unique<btSphereShape>(body.radius));
      case SceneShape::kCapsule:
        return Keep(std::make_unique<btCapsuleShape>(body.radius, 2.0f * body.half_height));
      case SceneShape::kHull:
        return Shared(body, [&] {
          auto convex = std::make_unique<btConvexHullShape>();
          for (const Vec3& p : scene_.hulls.at(body.geometry).points) convex->addPoint(ToBullet(p));
          return convex;
        });
      case SceneShape::kHeightField:
        return Shared(body, [&] { return HeightField(body.geometry); });
      case SceneShape::kMesh:
        return Shared(body, [&] { return Mesh(body.geometry); });
    }
    return nullptr;
  }

  // One Bullet shape per hull, mesh or height field of the scene, shared by the bodies that use it.
  template <class Make>
  btCollisionShape* Shared(const BodyDescription& body, Make make) {
    btCollisionShape*& shape = shared_[{body.shape, body.geometry}];
    if (!shape) shape = Keep(make());
    return shape;
  }

  std::unique_ptr<btCollisionShape> Mesh(std::uint32_t geometry) {
    const MeshGeometry& mesh = scene_.meshes.at(geometry);
    std::vector<int>& indices = mesh_indices_.emplace_back();
    for (const auto& triangle : mesh.triangles)
      for (std::uint32_t index : triangle) indices.push_back(static_cast<int>(index));
    mesh_data_.push_back(std::make_unique<btTriangleIndexVertexArray>(
        static_cast<int>(mesh.triangles.size()), indices.data(), 3 * static_cast<int>(sizeof(int)),
        static_cast<int>(mesh.vertices.size()), const_cast<btScalar*>(mesh.vertices.front().data()),
        static_cast<int>(sizeof(Vec3))));
    return std::make_unique<btBvhTriangleMeshShape>(mesh_data_.back().get(), true);
  }

  std::unique_ptr<btCollisionShape> HeightField(std::uint32_t geometry) {
    // Bullet centres a height field on its bounds; its flipped quad edges are Strata's diagonals.
    const HeightFieldGeometry& grid = scene_.height_fields.at(geometry);
    const auto [low, high] = std::minmax_element(grid.heights.begin(), grid.heights.end());
    auto field = std::make_unique<btHeightfieldTerrainShape>(static_cast<int>(grid.columns),
                                                             static_cast<int>(grid.rows), grid.heights.data(),
                                                             *low, *high, 1, true);
    field->setLocalScaling(btVector3(grid.cell, 1.0f, grid.cell));
    field_offsets_[geometry] =
        Vec3(0.5f * grid.cell * static_cast<float>(grid.columns - 1), 0.5f * (*low + *high),
             0.5f * grid.cell * static_cast<float>(grid.rows - 1));
    return field;
  }

  btCollisionShape* Keep(std::unique_ptr<btCollisionShape> shape) {
    shapes_.push_back(std::move(shape));
    return shapes_.back().get();
  }

  void AddBody(const BodyDescription& body) {
    btCollisionShape* shape = ShapeFor(body);
    btTransform transform;
    transform.setIdentity();
    transform.setOrigin(ToBullet(body.shape == SceneShape::kHeightField
                                     ? Vec3(body.position + field_offsets_.at(body.geometry))
                                     : body.position));
    transform.setRotation(
        btQuaternion(body.rotation.x(), body.rotation.y(), body.rotation.z(), body.rotation.w()));
    btScalar mass = 0;
    btVector3 inertia(0, 0, 0);
    if (body.IsDynamic()) {
      mass = BenchMass(scene_, body);  // the mass Strata gives the same shape at its default density
      shape->calculateLocalInertia(mass, inertia);
    }
    motion_states_.push_back(std::make_unique<btDefaultMotionState>(transform));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motion_states_.back().get(), shape, inertia);
    info.m_friction = body.friction;
    info.m_restitution = body.restitution;
    bodies_.push_back(std::make_unique<btRigidBody>(info));
    if (body.IsDynamic() && !scene_.sleeping) bodies_.back()->setActivationState(DISABLE_DEACTIVATION);
    world_.addRigidBody(bodies_.back().get());
    if (body.IsDynamic()) dynamic_bodies_.push_back(bodies_.back().get());
  }

  // A joint as Bullet's matching constraint; joined bodies do not collide, as in Strata.
  void AddJoint(const JointDescription& joint) {
    btRigidBody& b = *bodies_[joint.body_b];
    btRigidBody& a = joint.body_a >= 0 ? *bodies_[joint.body_a] : btTypedConstraint::getFixedBody();
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
      case JointKind::kPoint: {
        const btTransform in_a = frame_in(a, axes), in_b = frame_in(b, axes);
        joints_.push_back(
            std::make_unique<btPoint2PointConstraint>(a, b, in_a.getOrigin(), in_b.getOrigin()));
        break;
      }
      case JointKind::kHinge: {
        // Bullet's hinge turns about its frame's z.
        Mat3 hinge_axes;
        hinge_axes.col(0) = axes.col(1);
        hinge_axes.col(1) = axes.col(2);
        hinge_axes.col(2) = axes.col(0);
        auto hinge =
            std::make_unique<btHingeConstraint>(a, b, frame_in(a, hinge_axes), frame_in(b, hinge_axes));
        if (joint.limits) hinge->setLimit(joint.min_limit, joint.max_limit);
        joints_.push_back(std::move(hinge));
        break;
      }
      case JointKind::kSwingTwist: {
        // Bullet's cone twists about its frame's x; both swing spans are the cone's half angle.
        auto cone = std::make_unique<btConeTwistConstraint>(a, b, frame_in(a, axes), frame_in(b, axes));
        cone->setLimit(joint.cone, joint.cone, 0.5f * (joint.max_limit - joint.min_limit));
        joints_.push_back(std::move(cone));
        break;
      }
      case JointKind::kFixed:
        joints_.push_back(std::make_unique<btFixedConstraint>(a, b, frame_in(a, axes), frame_in(b, axes)));
        break;
      case JointKind::kSlider: {
        // Bullet's slider moves along its frame's x, the joint's axis.
        auto slider = std::make_unique<btSliderConstraint>(a, b, frame_in(a, axes), frame_in(b, axes), true);
        slider->setLowerLinLimit(joint.limits ? joint.min_limit : 1.0f);  // lower above upper: free
        slider->setUpperLinLimit(joint.limits ? joint.max_limit : -1.0f);
        slider->setLowerAngLimit(0.0f);
        slider->setUpperAngLimit(0.0f);
        joints_.push_back(std::move(slider));
        break;
      }
      case JointKind::kDistance:
        unsupported_ = "distance joints";  // no Bullet constraint holds a rod's length alone
        return;
    }
    world_.addConstraint(joints_.back().get(), true);
  }

  const BenchScene& scene_;
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motion_states_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<btRigidBody*> dynamic_bodies_;
  std::map<std::pair<SceneShape, std::uint32_t>, btCollisionShape*> shared_;
  std::deque<std::vector<int>> mesh_indices_;  // a deque: Bullet keeps pointers into each list
  std::vector<std::unique_ptr<btTriangleIndexVertexArray>> mesh_data_;
  std::map<std::uint32_t, Vec3> field_offsets_;
  std::vector<std::unique_ptr<btTypedConstraint>> joints_;
  std::string unsupported_;  // what the scene has that the peer cannot build
};

}  // namespace

EngineResult RunBullet(const BenchScene& scene) {
  BulletScene bullet(scene);
  return bullet.Run();
}

}  // namespace strata::bench
