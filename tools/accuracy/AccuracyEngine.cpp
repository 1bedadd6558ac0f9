#include "tools/accuracy/AccuracyEngine.h"

#include <chrono>

#include "assets/scene/SceneBuilder.h"
#include "physics/body/BodyInterface.h"
#include "physics/core/JobSystem.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::accuracy {

namespace {

class StrataEngine final : public AccuracyEngine {
 public:
  std::string name() const override { return "strata"; }

  Status Build(const SceneDescription& scene, const AccuracySetting& setting) override {
    PhysicsSettings settings = ToPhysicsSettings(scene);
    settings.substeps = setting.substeps;
    settings.velocity_iterations = setting.velocity_iterations;
    settings.relax_iterations = setting.relax_iterations;
    settings.exact_small_islands = setting.exact_small_islands;
    settings.allow_sleeping = false;  // the cases measure motion, not rest
    PhysicsSystemConfig config;
    config.max_bodies = static_cast<std::uint32_t>(scene.bodies.size()) + 16;
    config.job_system = std::shared_ptr<JobSystem>(new SerialJobSystem());
    config.stage_timings = false;  // the suite times whole steps, as it does Bullet's
    Result<std::unique_ptr<PhysicsSystem>> world = PhysicsSystem::Create(config, settings);
    if (!world) return world.error();
    world_ = std::move(*world);
    dt_ = setting.dt;
    ids_.clear();
    for (const BodyDescription& body : scene.bodies) {
      Result<ShapeRef> shape = MakeShape(scene, body);
      if (!shape) return shape.error();
      BodyCreationSettings created = ToBodySettings(body, *shape);
      created.motion_quality =
          body.IsDynamic() && setting.linear_cast ? MotionQuality::kLinearCast : MotionQuality::kDiscrete;
      created.linear_damping = 0.0f;
      created.angular_damping = 0.0f;
      created.max_angular_velocity = 1000.0f;
      created.max_linear_velocity = 1000.0f;
      Result<BodyID> id = world_->bodies().CreateAndAddBody(created);
      if (!id) return id.error();
      ids_.push_back(*id);
    }
    step_ms_ = 0.0;
    return Status::Ok();
  }

  Status Step() override {
    const auto start = std::chrono::steady_clock::now();
    Status stepped = world_->Step(dt_);
    step_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return stepped;
  }

  AccuracyBodyState State(std::size_t body) const override {
    BodyLockRead lock(world_->body_manager(), ids_[body]);
    const Body& b = lock.body();
    return {b.PreciseCenterOfMass(), b.rotation(), b.linear_velocity(), b.angular_velocity()};
  }

  Vec3 PrincipalInertia(std::size_t body) const override {
    BodyLockRead lock(world_->body_manager(), ids_[body]);
    return lock.body().inertia_local().diagonal();
  }

 private:
  std::unique_ptr<PhysicsSystem> world_;
  std::vector<BodyID> ids_;
  float dt_ = 1.0f / 60.0f;
};

}  // namespace

std::unique_ptr<AccuracyEngine> MakeStrataEngine() {
  return std::make_unique<StrataEngine>();
}

#ifndef STRATA_HAVE_BULLET
std::unique_ptr<AccuracyEngine> MakeBulletEngine() {
  return nullptr;
}
#endif

}  // namespace strata::accuracy
