// Free motion and fast motion: gyroscopic torque (Euler's equations), linear casts against thin walls, the
// first step's swept bounds, velocity limits that are counted, and motion 10 km from the origin.
#include <cmath>
#include <limits>

#include "TestWorld.h"
#include "physics/body/GyroscopicTorque.h"
#include "physics/constraints/ContactConstraint.h"

namespace strata::test {
namespace {

Vec3 BodyMomentum(const Mat3& inertia, const Vec3& spin) {
  return inertia * spin;
}

TEST(Gyroscopic, ImplicitMidpointKeepsEnergyAndMomentumAtHighSpin) {
  const Mat3 inertia = Vec3(0.1f, 0.26f, 0.34f).asDiagonal();
  EXPECT_TRUE(HasGyroscopicTorque(inertia));
  EXPECT_FALSE(HasGyroscopicTorque(Mat3::Identity() * 0.4f));
  for (const float dt : {1.0f / 30.0f, 1.0f / 60.0f, 1.0f / 240.0f}) {
    Vec3 spin(30.0f, 80.0f, -20.0f);  // about 4000 rpm on no principal axis
    const float energy = spin.dot(inertia * spin), momentum = BodyMomentum(inertia, spin).norm();
    // Body frame = world frame here (identity rotation): the rule's own invariants.
    for (int step = 0; step < 600; ++step) spin = SpinWithoutTorque(inertia, Quat::Identity(), spin, dt);
    ASSERT_TRUE(IsFinite(spin)) << dt;
    EXPECT_NEAR(spin.dot(inertia * spin), energy, 1e-3f * energy) << dt;
    EXPECT_NEAR(BodyMomentum(inertia, spin).norm(), momentum, 1e-3f * momentum) << dt;
  }
}

// A spin no body reaches (a solver that blew up) or one that is not finite costs bounded work: before the
// cap on its pieces, 1e12 rad/s at 60 Hz took 3e10 midpoint steps, and a chain that blew up hung its step.
TEST(Gyroscopic, AHugeOrNonFiniteSpinTakesBoundedPieces) {
  constexpr float kDt = 1.0f / 60.0f;
  EXPECT_EQ(SpinPieces(0.0f, kDt), 1);
  EXPECT_EQ(SpinPieces(29.0f, kDt), 1);    // 0.48 rad
  EXPECT_EQ(SpinPieces(31.0f, kDt), 2);    // 0.52 rad
  EXPECT_EQ(SpinPieces(590.0f, kDt), 20);  // 9.8 rad
  const float kNaN = std::numeric_limits<float>::quiet_NaN(),
              kInfinity = std::numeric_limits<float>::infinity();
  for (const float speed : {1e12f, 3.4e38f, kNaN, kInfinity})
    EXPECT_EQ(SpinPieces(speed, kDt), kMaxSpinPieces);
  // And the step itself returns on them (a hang here is a ctest timeout).
  const Mat3 inertia = Vec3(0.1f, 0.26f, 0.34f).asDiagonal();
  for (const Vec3& spin : {Vec3(1e12f, 3e11f, -2e12f), Vec3(kNaN, 0.0f, 1.0f), Vec3(kInfinity, 0.0f, 0.0f)})
    SpinWithoutTorque(inertia, Quat::Identity(), spin, kDt);
}

// A diagonal inertia takes a shorter path; the same inertia seen in turned axes (no longer diagonal) takes
// the general one. Both must be the same rule.
TEST(Gyroscopic, DiagonalAndGeneralInertiaGiveTheSameSpin) {
  const Mat3 diagonal = Vec3(0.1f, 0.26f, 0.34f).asDiagonal();
  const Mat3 turn = Quat(Eigen::AngleAxisf(0.8f, Vec3(1, -2, 0.5f).normalized())).toRotationMatrix();
  const Mat3 general = turn * diagonal * turn.transpose();
  // One step each (over many, the intermediate axis amplifies rounding differences as it should).
  for (const float dt : {1.0f / 30.0f, 1.0f / 240.0f})
    for (const Vec3& start : {Vec3(30.0f, 80.0f, -20.0f), Vec3(1.0f, 2.0f, 3.0f)}) {
      const Vec3 spin = SpinWithoutTorque(diagonal, Quat::Identity(), start, dt);
      const Vec3 turned = SpinWithoutTorque(general, Quat::Identity(), turn * start, dt);
      EXPECT_LT((turn * spin - turned).norm(), 1e-5f * spin.norm()) << dt;
      EXPECT_GT((spin - start).norm(), 1e-3f * start.norm()) << dt;  // it did turn
    }
}

// A diagonal inertia with two equal moments (a capsule's) takes the rule in closed form; the same inertia
// turned takes Newton. Both must be the same rule, about whichever axis is the odd one.
TEST(Gyroscopic, ASymmetricBodyTakesTheSameRuleInClosedForm) {
  const Mat3 turn = Quat(Eigen::AngleAxisf(0.8f, Vec3(1, -2, 0.5f).normalized())).toRotationMatrix();
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 moments = Vec3::Constant(0.3f);
    moments[axis] = 0.12f;
    const Mat3 diagonal = moments.asDiagonal();
    const Mat3 general = turn * diagonal * turn.transpose();
    for (const float dt : {1.0f / 30.0f, 1.0f / 240.0f})
      for (const Vec3& start : {Vec3(30.0f, 80.0f, -20.0f), Vec3(1.0f, 2.0f, 3.0f)}) {
        const Vec3 spin = SpinWithoutTorque(diagonal, Quat::Identity(), start, dt);
        const Vec3 turned = SpinWithoutTorque(general, Quat::Identity(), turn * start, dt);
        EXPECT_LT((turn * spin - turned).norm(), 1e-5f * spin.norm()) << axis << " " << dt;
        EXPECT_EQ(spin[axis], start[axis]) << axis;                      // the odd axis keeps its spin
        EXPECT_GT((spin - start).norm(), 1e-3f * start.norm()) << axis;  // the rest precesses
        EXPECT_NEAR(spin.dot(diagonal * spin), start.dot(diagonal * start),
                    1e-5f * start.dot(diagonal * start));
      }
  }
}

// What a bounce reverses: the approach speed when the points meet, from the step's start across the gap.
TEST(Restitution, ApproachSpeedIsTakenAtImpact) {
  constexpr float kSubstep = 1.0f / 60.0f, kGravity = 9.81f;
  const float gain = -kGravity * kSubstep;  // the first substep's share, already in the velocity
  // 0.1 m above the floor at 5 m/s: meets it at sqrt(25 + 2 g 0.1).
  EXPECT_NEAR(ApproachAtImpact(-5.0f + gain, gain, kSubstep, 0.1f),
              -std::sqrt(25.0f + 2.0f * kGravity * 0.1f), 1e-4f);
  // Touching already: the speed at the step's start. Separating, or not pulled together: unchanged.
  EXPECT_NEAR(ApproachAtImpact(-5.0f + gain, gain, kSubstep, 0.0f), -5.0f, 1e-5f);
  EXPECT_NEAR(ApproachAtImpact(1.0f + gain, gain, kSubstep, 0.1f), 1.0f, 1e-5f);
  EXPECT_NEAR(ApproachAtImpact(-5.0f, 0.0f, kSubstep, 0.1f), -5.0f, 1e-6f);
}

TEST(Gyroscopic, SwitchingItOffLeavesSpinConstantAndMomentumDrifting) {
  for (const bool gyroscopic : {false, true}) {
    PhysicsSettings settings;
    settings.gravity = Vec3::Zero();
    settings.gyroscopic_torque = gyroscopic;
    auto world = MakeWorld(settings);
    BodyCreationSettings box = Dynamic(Box(0.5f, 0.3f, 0.1f), Vec3::Zero());
    box.angular_velocity = Vec3(1, 2, 3);
    box.angular_damping = 0.0f;
    const BodyID id = Add(*world, box);
    StepFor(*world, 120);
    BodyLockRead lock(world->body_manager(), id);
    const Body& body = lock.body();
    const Mat3 rotation = body.rotation().toRotationMatrix();
    const Vec3 momentum = rotation * body.inertia_local() * rotation.transpose() * body.angular_velocity();
    const Vec3 start = body.inertia_local() * Vec3(1, 2, 3);
    if (gyroscopic)
      EXPECT_LT((momentum - start).norm(), 0.03f * start.norm());
    else
      EXPECT_TRUE(body.angular_velocity().isApprox(Vec3(1, 2, 3), 1e-5f));
  }
}

BodyID ThinWallAndBullet(PhysicsSystem& world, MotionQuality quality, BodyID& wall) {
  wall = Add(world, Static(Box(0.05f, 2, 2), Vec3(10, 0, 0)));
  BodyCreationSettings bullet = Dynamic(Sphere(0.05f), Vec3::Zero());
  bullet.linear_velocity = Vec3(500, 0, 0);
  bullet.gravity_factor = 0.0f;
  bullet.motion_quality = quality;
  return Add(world, bullet);
}

TEST(LinearCast, FastSphereStopsAtAThinWallAtEveryDt) {
  for (const float dt : {1.0f / 30.0f, 1.0f / 60.0f, 1.0f / 10.0f}) {
    auto world = MakeWorld();
    BodyID wall;
    const BodyID bullet = ThinWallAndBullet(*world, MotionQuality::kLinearCast, wall);
    std::size_t hits = 0;
    for (int step = 0; step < 10; ++step) {
      ASSERT_TRUE(world->Step(dt).ok());
      hits += world->last_step_stats().linear_cast_hits;
      EXPECT_LT(Position(*world, bullet).x(), 9.9f + 1e-3f) << "dt " << dt << " step " << step;
    }
    EXPECT_GE(hits, 1u) << dt;
  }
}

TEST(LinearCast, BodiesThatDoNotAskAreNotCast) {
  auto world = MakeWorld();
  BodyID wall;
  ThinWallAndBullet(*world, MotionQuality::kDiscrete, wall);
  for (int step = 0; step < 10; ++step) {
    ASSERT_TRUE(world->Step(1.0f / 30.0f).ok());
    EXPECT_EQ(world->last_step_stats().linear_cast_hits, 0u);
  }
}

TEST(LinearCast, FirstStepBoundsCoverTheRealDt) {
  // A discrete body added before the first step, which is twice as long as the default: its swept bounds
  // must reach the wall in that step, so the speculative contact stops it.
  auto world = MakeWorld();
  BodyID wall;
  const BodyID bullet = ThinWallAndBullet(*world, MotionQuality::kDiscrete, wall);
  for (int step = 0; step < 10; ++step) ASSERT_TRUE(world->Step(1.0f / 30.0f).ok());
  EXPECT_LT(Position(*world, bullet).x(), 9.9f + 1e-3f);
}

TEST(BodyRanges, BodiesAtTheEdgesOfTheDocumentedRangesStayFinite) {
  auto world = MakeWorld();
  Add(*world, Static(Box(50, 1, 50), Vec3(0, -1, 0)));
  const float tiny = BodyCreationSettings::kMinHalfExtent;
  std::vector<BodyID> ids = {Add(*world, Dynamic(Box(tiny, tiny, tiny), Vec3(-3, 0.2f, 0)))};
  BodyCreationSettings light = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0));
  light.mass = BodyCreationSettings::kMinMass;
  ids.push_back(Add(*world, light));
  ids.push_back(Add(*world, Dynamic(Sphere(0.3f), Vec3(0, 2, 0))));  // lands on the light box
  BodyCreationSettings heavy = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(3, 0.6f, 0));
  heavy.mass = BodyCreationSettings::kMaxMass;
  heavy.angular_velocity = Vec3(1, 2, 3);
  ids.push_back(Add(*world, heavy));
  for (int step = 0; step < 300; ++step) {
    ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
    for (const BodyID id : ids) ASSERT_TRUE(IsFinite(Position(*world, id)) && IsFinite(Velocity(*world, id)));
  }
  // Just outside the range: refused, and nothing was added.
  const std::size_t before = world->body_count_in_world();
  BodyCreationSettings too_light = light;
  too_light.mass = 0.5f * BodyCreationSettings::kMinMass;
  EXPECT_FALSE(world->bodies().CreateAndAddBody(too_light).ok());
  EXPECT_FALSE(world->bodies().CreateAndAddBody(Dynamic(Sphere(0.5f * tiny), Vec3::Zero())).ok());
  EXPECT_EQ(world->body_count_in_world(), before);
}

TEST(VelocityLimits, ClampsAreCounted) {
  PhysicsSettings settings;
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  BodyCreationSettings fast = Dynamic(Sphere(0.5f), Vec3::Zero());
  fast.linear_velocity = Vec3(50, 0, 0);
  fast.max_linear_velocity = 10.0f;
  fast.angular_velocity = Vec3(0, 0, 40);
  fast.max_angular_velocity = 5.0f;
  const BodyID id = Add(*world, fast);
  ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
  EXPECT_EQ(world->last_step_stats().linear_velocity_clamps, 1u);
  EXPECT_EQ(world->last_step_stats().angular_velocity_clamps, 1u);
  EXPECT_NEAR(Velocity(*world, id).norm(), 10.0f, 1e-4f);
  ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
  EXPECT_EQ(world->last_step_stats().linear_velocity_clamps, 0u);  // already within its limit
}

// How far a box on a floor at `origin` travels (x) and where it ends up (y) after `steps`, from `speed`.
Vec3d SlideFrom(const Vec3& origin, float speed, float friction, float dt, int substeps, int steps) {
  PhysicsSettings settings;
  settings.substeps = substeps;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  BodyCreationSettings floor = Static(Box(50, 1, 50), origin + Vec3(0, -1, 0));
  floor.friction = friction;
  Add(*world, floor);
  BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), origin + Vec3(0, 0.5f, 0));
  box.friction = friction;
  box.linear_velocity = Vec3(speed, 0, 0);
  box.linear_damping = 0.0f;
  const BodyID id = Add(*world, box);
  StepFor(*world, steps, dt);
  return *world->bodies().GetPrecisePosition(id) - origin.cast<double>();
}

TEST(LargeWorlds, BoxesSlideAndStop10KilometresOutAsTheyDoAtTheOrigin) {
  const Vec3 far(10000.0f, 0.0f, -10000.0f);
  for (const float dt : {1.0f / 30.0f, 1.0f / 60.0f, 1.0f / 120.0f})
    for (const int substeps : {1, 4}) {
      const auto steps = static_cast<int>(std::lround(2.0f / dt));
      // 2 cm/s without friction: each step's 0.3 mm is below a float's step there.
      const Vec3d near_slide = SlideFrom(Vec3::Zero(), 0.02f, 0.0f, dt, substeps, steps);
      const Vec3d far_slide = SlideFrom(far, 0.02f, 0.0f, dt, substeps, steps);
      EXPECT_NEAR(near_slide.x(), 0.04, 0.0004) << dt << " " << substeps;
      EXPECT_NEAR(far_slide.x(), near_slide.x(), 0.01 * near_slide.x()) << dt << " " << substeps;
      EXPECT_NEAR(far_slide.y(), near_slide.y(), 1e-3) << dt << " " << substeps;
      // 1 m/s with friction 0.5: it stops after about v^2 / (2 mu g) = 10 cm, wherever it is.
      const Vec3d near_stop = SlideFrom(Vec3::Zero(), 1.0f, 0.5f, dt, substeps, steps);
      const Vec3d far_stop = SlideFrom(far, 1.0f, 0.5f, dt, substeps, steps);
      EXPECT_NEAR(far_stop.x(), near_stop.x(), 0.01 * near_stop.x()) << dt << " " << substeps;
    }
}

TEST(LargeWorlds, TeleportingDropsTheRemainder) {
  PhysicsSettings settings;
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(10000.0f, 0.0f, 0.0f));
  box.linear_velocity = Vec3(0.02f, 0, 0);
  box.linear_damping = 0.0f;
  const BodyID id = Add(*world, box);
  StepFor(*world, 30);
  const Vec3d moved = *world->bodies().GetPrecisePosition(id);
  EXPECT_NEAR(moved.x() - 10000.0, 0.01, 1e-5);
  EXPECT_EQ(Position(*world, id).x(), static_cast<float>(moved.x()));  // the float is the nearest one
  ASSERT_TRUE(world->bodies().SetPosition(id, Vec3(5.0f, 0.0f, 0.0f)).ok());
  EXPECT_EQ(world->bodies().GetPrecisePosition(id)->x(), 5.0);
}

}  // namespace
}  // namespace strata::test
