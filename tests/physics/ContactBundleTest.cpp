// A bundle whose every lane pushes against the fixed body skips B's side: it must move the bodies exactly as
// the general path does, pass by pass.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "physics/constraints/ContactBundle.h"

namespace strata::test {
namespace {

struct Scene {
  BlockArena arena;
  std::vector<SolverBody> bodies;
  std::vector<ContactConstraint*> constraints;
};

// One constraint per lane, each against the fixed body (solver body 0) from a body of its own, with 1 to 4
// overlapping points, and last step's impulses to warm start from.
void MakeScene(Scene& scene, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  auto vector = [&] { return Vec3(unit(random), unit(random), unit(random)); };
  scene.bodies.assign(ContactBundle::kLanes + 1, SolverBody());
  for (int lane = 0; lane < ContactBundle::kLanes; ++lane) {
    SolverBody& body = scene.bodies[lane + 1];
    const Vec3 normal = Vec3(0.2f * unit(random), 1.0f, 0.2f * unit(random)).normalized();
    // Towards the fixed body (the normal runs from A to B), so that every lane's contact pushes.
    body.linear_velocity = ToVec4(2.0f * normal + 0.5f * vector());
    body.angular_velocity = ToVec4(vector());
    body.inverse_mass = 0.75f + 0.25f * unit(random);
    const Mat3 rotation =
        Quat(unit(random), unit(random), unit(random), 1.0f).normalized().toRotationMatrix();
    InverseInertiaColumns(rotation, Vec3(2.0f, 1.0f, 3.0f).asDiagonal().toDenseMatrix(),
                          body.inverse_inertia);
    body.delta_position = ToVec4(0.0005f * vector());
    body.delta_rotation = ToVec4(0.0005f * vector());
    const int points = 1 + static_cast<int>(random() % ContactManifold::kMaxPoints);
    auto* c = new (scene.arena.Allocate(ContactConstraint::Bytes(points), alignof(ContactConstraint)))
        ContactConstraint{};
    c->normal = normal;
    c->body_a = static_cast<std::uint32_t>(lane + 1);
    c->body_b = 0;
    c->friction = 0.5f;
    c->restitution = 0.6f;
    c->point_count = static_cast<std::uint8_t>(points);
    c->dynamic_a = true;
    for (int i = 0; i < points; ++i) {
      ContactConstraintPoint& p = c->points()[i];
      p.r_a = vector();
      p.r_b = vector();
      p.warm_friction = 0.1f * vector();
      p.warm_normal = 0.5f + 0.5f * unit(random);
      p.separation = -0.005f + 0.004f * unit(random);
      p.normal_velocity = -4.0f * (1.0f + unit(random));
    }
    scene.constraints.push_back(c);
  }
}

// Every pass the solver runs on a bundle, in a step's order.
void RunPasses(ContactBundle& bundle, std::vector<SolverBody>& bodies) {
  SubstepContext context;
  context.against_fixed = MakeSoftSpring(60.0f, 10.0f, 1.0f / 240.0f);
  context.between_moving = MakeSoftSpring(30.0f, 10.0f, 1.0f / 240.0f);
  context.inverse_h = 240.0f;
  context.max_push_velocity = 3.0f;
  context.restitution_threshold = 1.0f;
  SetupBundle(bundle, bodies.data(), context);
  WarmStartBundle(bundle, bodies.data());
  for (int pass = 0; pass < 4; ++pass) {
    context.elapsed = pass / 240.0f;
    SolveBundleVelocity(bundle, bodies.data(), context, true, pass % 2 == 1, nullptr);
  }
  SolveBundleVelocity(bundle, bodies.data(), context, false, false, nullptr);
  ApplyBundleRestitution(bundle, bodies.data(), context);
}

TEST(ContactBundle, ABundleAgainstTheFixedBodyMovesItsBodiesAsTheGeneralPathDoes) {
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    Scene scene;
    MakeScene(scene, seed);
    ContactBundle& fast = *AllocateBundle(scene.arena, scene.constraints);
    ContactBundle& general = *AllocateBundle(scene.arena, scene.constraints);
    ASSERT_TRUE(fast.fixed_b);
    general.fixed_b = false;
    std::vector<SolverBody> fast_bodies = scene.bodies, general_bodies = scene.bodies;
    RunPasses(fast, fast_bodies);
    RunPasses(general, general_bodies);
    for (int body = 1; body <= ContactBundle::kLanes; ++body) {
      // Something happened, and the same thing: lanes push, and the skipped side only ever added zeros.
      EXPECT_GT((fast_bodies[body].linear_velocity - scene.bodies[body].linear_velocity).norm(), 1e-3f)
          << "body " << body;
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(fast_bodies[body].linear_velocity[k], general_bodies[body].linear_velocity[k]) << body;
        EXPECT_EQ(fast_bodies[body].angular_velocity[k], general_bodies[body].angular_velocity[k]) << body;
      }
    }
    // The fixed body itself is never written.
    EXPECT_EQ(fast_bodies[0].linear_velocity, Vec4::Zero());
    EXPECT_EQ(general_bodies[0].linear_velocity, Vec4::Zero());
  }
}

TEST(ContactBundle, OneLaneAgainstAKinematicBodyMakesTheBundleGeneral) {
  // A kinematic body is a solver body of its own (it has a velocity) that the solver does not move.
  Scene scene;
  MakeScene(scene, 7);
  scene.constraints.back()->body_b = 1;
  EXPECT_FALSE(AllocateBundle(scene.arena, scene.constraints)->fixed_b);
  scene.constraints.pop_back();
  EXPECT_TRUE(AllocateBundle(scene.arena, scene.constraints)->fixed_b);
}

}  // namespace
}  // namespace strata::test
