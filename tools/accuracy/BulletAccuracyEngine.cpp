// The Bullet side of the accuracy suite (built only when Debian's libbullet-dev is found).
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>

#include "tools/accuracy/AccuracyEngine.h"

namespace strata::accuracy {

namespace {

btVector3 ToBullet(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}
Vec3 FromBullet(const btVector3& v) {
  return {v.x(), v.y(), v.z()};
}

class BulletEngine final : public AccuracyEngine {
 public:
  BulletEngine()
      : dispatcher_(&configuration_), world_(&dispatcher_, &broadphase_, &solver_, &configuration_) {}
  ~BulletEngine() override {
    for (auto& body : bodies_) world_.removeRigidBody(body.get());
  }

  std::string name() const override { return "bullet"; }
  bool Runs(const AccuracySetting& setting) const override { return setting.exact_small_islands; }

  Status Build(const SceneDescription& scene, const AccuracySetting& setting) override {
    world_.setGravity(ToBullet(scene.gravity));
    world_.getSolverInfo().m_numIterations = setting.velocity_iterations + setting.relax_iterations;
    world_.getSolverInfo().m_restitutionVelocityThreshold = scene.min_velocity_for_restitution;
    dt_ = setting.dt;
    substeps_ = setting.substeps;
    for (const BodyDescription& body : scene.bodies) {
      if (body.shape == SceneShape::kBox)
        shapes_.push_back(std::make_unique<btBoxShape>(ToBullet(body.half_extents)));
      else
        shapes_.push_back(std::make_unique<btSphereShape>(body.radius));
      btCollisionShape* shape = shapes_.back().get();
      btTransform transform;
      transform.setIdentity();
      transform.setOrigin(ToBullet(body.position));
      transform.setRotation(
          btQuaternion(body.rotation.x(), body.rotation.y(), body.rotation.z(), body.rotation.w()));
      btScalar mass = 0;
      btVector3 inertia(0, 0, 0);
      if (body.IsDynamic()) {
        const float volume = body.shape == SceneShape::kBox
                                 ? 8.0f * body.half_extents.prod()
                                 : 4.0f / 3.0f * kPi * body.radius * body.radius * body.radius;
        mass = body.mass > 0.0f ? body.mass : 1000.0f * volume;
        shape->calculateLocalInertia(mass, inertia);
      }
      states_.push_back(std::make_unique<btDefaultMotionState>(transform));
      btRigidBody::btRigidBodyConstructionInfo info(mass, states_.back().get(), shape, inertia);
      // Bullet multiplies the two bodies' friction and restitution: give each side the square root of the
      // pair's friction, and static bodies restitution 1 so a pair gets the moving body's.
      info.m_friction = std::sqrt(body.friction);
      info.m_restitution = body.IsDynamic() ? body.restitution : 1.0f;
      info.m_linearDamping = 0.0f;
      info.m_angularDamping = 0.0f;
      bodies_.push_back(std::make_unique<btRigidBody>(info));
      btRigidBody& created = *bodies_.back();
      if (body.IsDynamic()) {
        created.setActivationState(DISABLE_DEACTIVATION);
        created.setLinearVelocity(ToBullet(body.linear_velocity));
        created.setAngularVelocity(ToBullet(body.angular_velocity));
        created.setFlags(created.getFlags() | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
        if (setting.linear_cast) {
          const float size = body.shape == SceneShape::kBox ? body.half_extents.minCoeff() : body.radius;
          created.setCcdMotionThreshold(0.5f * size);
          created.setCcdSweptSphereRadius(0.9f * size);
        }
      }
      world_.addRigidBody(&created);
    }
    step_ms_ = 0.0;
    return Status::Ok();
  }

  Status Step() override {
    const auto start = std::chrono::steady_clock::now();
    const float fixed = dt_ / static_cast<float>(substeps_);
    world_.stepSimulation(dt_, substeps_, fixed);
    step_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return Status::Ok();
  }

  AccuracyBodyState State(std::size_t body) const override {
    const btRigidBody& b = *bodies_[body];
    const btTransform& transform = b.getWorldTransform();
    const btQuaternion q = transform.getRotation();
    return {FromBullet(transform.getOrigin()).cast<double>(), Quat(q.w(), q.x(), q.y(), q.z()),
            FromBullet(b.getLinearVelocity()), FromBullet(b.getAngularVelocity())};
  }

  Vec3 PrincipalInertia(std::size_t body) const override {
    const btVector3 inverse = bodies_[body]->getInvInertiaDiagLocal();
    return {1.0f / inverse.x(), 1.0f / inverse.y(), 1.0f / inverse.z()};
  }

 private:
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> states_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  float dt_ = 1.0f / 60.0f;
  int substeps_ = 1;
};

}  // namespace

std::unique_ptr<AccuracyEngine> MakeBulletEngine() {
  return std::make_unique<BulletEngine>();
}

}  // namespace strata::accuracy
