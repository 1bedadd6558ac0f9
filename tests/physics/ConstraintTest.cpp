// Joints in the step: pendulum periods, limits under load, a long chain with a heavy end, motors,
// breaking, sleeping and waking through joints, joints that keep their bodies from colliding, the position
// step, and bad
// input refused with the world unchanged. Settings are swept (dt, substeps, passes), not tuned to one.
#include <cmath>

#include "TestWorld.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/constraints/DistanceJoint.h"
#include "physics/constraints/FixedJoint.h"
#include "physics/constraints/PointJoint.h"
#include "physics/core/ThreadPoolJobSystem.h"
#include "tools/bench/BenchRunner.h"

namespace strata::test {
namespace {

constexpr float kDegree = kPi / 180.0f;

BodyCreationSettings Bob(ShapeRef shape, const Vec3& position, float mass,
                         const Quat& rotation = Quat::Identity()) {
  BodyCreationSettings settings = Dynamic(std::move(shape), position, rotation);
  settings.mass = mass;
  settings.linear_damping = 0.0f;
  settings.angular_damping = 0.0f;
  settings.allow_sleeping = false;
  return settings;
}

ConstraintID Join(PhysicsSystem& world, const JointSettings& settings) {
  const Result<ConstraintID> id = world.constraints().Add(settings);
  EXPECT_TRUE(id.ok()) << (id.ok() ? "" : id.error().message);
  return id.ok() ? *id : ConstraintID{};
}

struct Setting {
  float dt;
  int substeps;
  int velocity_iterations;
};
const Setting kSettings[] = {
    {1.0f / 60.0f, 4, 1}, {1.0f / 120.0f, 4, 1}, {1.0f / 60.0f, 2, 2}, {1.0f / 30.0f, 8, 1}};

PhysicsSettings With(const Setting& setting) {
  PhysicsSettings settings;
  settings.substeps = setting.substeps;
  settings.velocity_iterations = setting.velocity_iterations;
  return settings;
}

// Mean period of x(t) from its downward zero crossings (linear interpolation between steps).
float MeasuredPeriod(PhysicsSystem& world, BodyID bob, float pivot_x, float dt, int steps) {
  std::vector<float> crossings;
  float previous = Position(world, bob).x() - pivot_x;
  for (int step = 1; step <= steps; ++step) {
    EXPECT_TRUE(world.Step(dt).ok());
    const float x = Position(world, bob).x() - pivot_x;
    if (previous > 0.0f && x <= 0.0f) crossings.push_back(dt * (step - 1 + previous / (previous - x)));
    previous = x;
  }
  if (crossings.size() < 2) return 0.0f;
  return (crossings.back() - crossings.front()) / static_cast<float>(crossings.size() - 1);
}

enum class PendulumJoint { kPoint, kDistance, kHinge };

TEST(Constraint, ASmallSwingPendulumKeepsItsPeriodWithinOnePercent) {
  constexpr float kLength = 1.0f, kRadius = 0.05f, kMass = 1.0f, kStart = 5.0f * kDegree;
  const Vec3 pivot(0.0f, 2.0f, 0.0f);
  // A sphere swinging about a pivot 1 m above its centre: a physical pendulum, I = m L^2 + 2/5 m r^2,
  // with the finite-amplitude correction (1 + theta0^2 / 16).
  const float inertia = kMass * kLength * kLength + 0.4f * kMass * kRadius * kRadius;
  const float expected =
      2.0f * kPi * std::sqrt(inertia / (kMass * 9.81f * kLength)) * (1.0f + kStart * kStart / 16.0f);
  for (const Setting& setting : kSettings) {
    for (const PendulumJoint kind :
         {PendulumJoint::kPoint, PendulumJoint::kDistance, PendulumJoint::kHinge}) {
      auto world = MakeWorld(With(setting));
      const Vec3 start = pivot + kLength * Vec3(std::sin(kStart), -std::cos(kStart), 0.0f);
      const BodyID bob = Add(*world, Bob(Sphere(kRadius), start, kMass));
      if (kind == PendulumJoint::kPoint) {
        PointJointSettings joint;
        joint.body_b = bob;
        joint.anchor = pivot;
        Join(*world, joint);
      } else if (kind == PendulumJoint::kDistance) {
        // A rod to the centre leaves the sphere's spin free: a point-mass pendulum of length L.
        DistanceJointSettings joint;
        joint.body_b = bob;
        joint.anchor_a = pivot;
        joint.anchor_b = start;
        Join(*world, joint);
      } else {
        HingeJointSettings joint;
        joint.body_b = bob;
        joint.anchor = pivot;
        joint.axis = Vec3::UnitZ();
        Join(*world, joint);
      }
      const float period_expected =
          kind == PendulumJoint::kDistance
              ? 2.0f * kPi * std::sqrt(kLength / 9.81f) * (1.0f + kStart * kStart / 16.0f)
              : expected;
      const float period =
          MeasuredPeriod(*world, bob, pivot.x(), setting.dt, static_cast<int>(7.0f / setting.dt));
      EXPECT_NEAR(period, period_expected, 0.01f * period_expected)
          << "joint " << static_cast<int>(kind) << " dt " << setting.dt << " substeps " << setting.substeps;
    }
  }
}

// The flap's hinge about z at `anchor` (B the flap, A `block`, or the world when invalid): limited to -20 ..
// 30 degrees when `limits`.
HingeJointSettings FlapHinge(BodyID block, BodyID flap, const Vec3& anchor, bool limits) {
  HingeJointSettings settings;
  settings.body_a = block;
  settings.body_b = flap;
  settings.anchor = anchor;
  settings.axis = Vec3::UnitZ();
  settings.normal = Vec3::UnitX();
  settings.limits = limits;
  settings.min_angle = -20.0f * kDegree;
  settings.max_angle = 30.0f * kDegree;
  return settings;
}

TEST(Constraint, AHingeLimitHoldsWithinOneDegreeUnderLoad) {
  for (const Setting& setting : kSettings) {
    auto world = MakeWorld(With(setting));
    // A 20 kg flap 1 m long on a horizontal hinge, thrown down at 6 rad/s and pushed down at its tip by
    // 400 N: both drive it into its lower limit of -20 degrees.
    const BodyID flap = Add(*world, Bob(Box(0.5f, 0.05f, 0.2f), Vec3(0.5f, 1.0f, 0.0f), 20.0f));
    ASSERT_TRUE(world->bodies().SetAngularVelocity(flap, Vec3(0.0f, 0.0f, -6.0f)).ok());
    const HingeJointSettings settings = FlapHinge(BodyID(), flap, Vec3(0.0f, 1.0f, 0.0f), true);
    const ConstraintID joint = Join(*world, settings);
    float lowest = 0.0f;
    for (int step = 0; step < static_cast<int>(3.0f / setting.dt); ++step) {
      ASSERT_TRUE(world->bodies().AddForce(flap, Vec3(0.0f, -400.0f, 0.0f), Vec3(1.0f, 1.0f, 0.0f)).ok());
      ASSERT_TRUE(world->Step(setting.dt).ok());
      const Quat rotation = *world->bodies().GetRotation(flap);
      ASSERT_TRUE(world->constraints()
                      .Read(joint,
                            [&](const Constraint& c) {
                              lowest = std::min(lowest, static_cast<const HingeJoint&>(c).Angle(
                                                            Quat::Identity(), rotation));
                            })
                      .ok());
    }
    EXPECT_GT(lowest, -21.0f * kDegree) << "dt " << setting.dt << " substeps " << setting.substeps;
    EXPECT_LT(lowest, -19.0f * kDegree) << "the load must reach the limit";
    // The anchor stays on the hinge.
    const Vec3 tip_anchor =
        Position(*world, flap) + *world->bodies().GetRotation(flap) * Vec3(-0.5f, 0.0f, 0.0f);
    EXPECT_LT((tip_anchor - settings.anchor).norm(), 0.01f);
  }
}

// A 1 kg block that a weld holds to the world at (0, 1, 0), and `heavy` beside it. A joint between the two
// goes to the exact solve (their masses differ ten times or more) with the weld's rows: it solves the rigid
// rows, and the joint's limits and motor against them.
struct HeldBlock {
  std::unique_ptr<PhysicsSystem> world;
  BodyID block;
  BodyID heavy;
};
HeldBlock MakeHeldBlock(const Setting& setting, const BodyCreationSettings& heavy) {
  HeldBlock held{MakeWorld(With(setting)), {}, {}};
  held.block = Add(*held.world, Bob(Box(0.1f, 0.1f, 0.1f), Vec3(0.0f, 1.0f, 0.0f), 1.0f));
  held.heavy = Add(*held.world, heavy);
  FixedJointSettings weld;
  weld.body_b = held.block;
  weld.anchor = Vec3(0.0f, 1.0f, 0.0f);
  Join(*held.world, weld);
  return held;
}

BodyFrame Frame(PhysicsSystem& world, BodyID body) {
  return {Position(world, body), *world.bodies().GetRotation(body)};
}

// Steps `held` for `seconds`, calling `watch(joint)` after each step; checks that the weld held the block.
template <class JointType, class Watch>
void StepHeld(HeldBlock& held, ConstraintID joint, const Setting& setting, float seconds, Watch&& watch) {
  for (int step = 0; step < static_cast<int>(seconds / setting.dt); ++step) {
    ASSERT_TRUE(held.world->Step(setting.dt).ok());
    ASSERT_TRUE(held.world->constraints()
                    .Read(joint, [&](const Constraint& c) { watch(static_cast<const JointType&>(c)); })
                    .ok());
  }
  EXPECT_LT((Position(*held.world, held.block) - Vec3(0.0f, 1.0f, 0.0f)).norm(), 0.001f) << "the weld holds";
}

// The lowest angle over 2 s of a flap of `flap_mass` hinged to the held block, thrown down at 6 rad/s, with
// or without a lower limit of -20 degrees.
float LowestFlapAngle(const Setting& setting, float flap_mass, bool limits) {
  HeldBlock held = MakeHeldBlock(setting, Bob(Box(0.5f, 0.05f, 0.2f), Vec3(0.6f, 1.0f, 0.0f), flap_mass));
  EXPECT_TRUE(held.world->bodies().SetAngularVelocity(held.heavy, Vec3(0.0f, 0.0f, -6.0f)).ok());
  const ConstraintID joint =
      Join(*held.world, FlapHinge(held.block, held.heavy, Vec3(0.1f, 1.0f, 0.0f), limits));
  float lowest = 0.0f;
  StepHeld<HingeJoint>(held, joint, setting, 2.0f, [&](const HingeJoint& hinge) {
    lowest = std::min(lowest, hinge.Angle(*held.world->bodies().GetRotation(held.block),
                                          *held.world->bodies().GetRotation(held.heavy)));
  });
  return lowest;
}

TEST(Constraint, AHingeLimitHoldsInAnIslandTheExactSolveTakes) {
  // The exact solve gives the limit the flap's effective mass about the hinge with the weld and the hinge's
  // other rows holding (a thousand times the block's and flap's own at 20:1). Solved by passes against
  // the two bodies alone, the flap opened to -40 degrees at 20:1 and to -177 at 100:1.
  for (const Setting& setting : kSettings) {
    for (const float flap_mass : {20.0f, 100.0f}) {
      const float limited = LowestFlapAngle(setting, flap_mass, true);
      EXPECT_GT(limited, -21.0f * kDegree)
          << "dt " << setting.dt << " substeps " << setting.substeps << " flap " << flap_mass << " kg";
      EXPECT_LT(limited, -19.0f * kDegree) << "the flap reaches its limit";
    }
    EXPECT_LT(LowestFlapAngle(setting, 20.0f, false), -90.0f * kDegree)
        << "dt " << setting.dt << ": without its limit the flap swings down";
  }
}

TEST(Constraint, LimitsAndAMotorActAgainstTheRigidRowsOfAnIslandTheExactSolveTakes) {
  for (const Setting& setting : kSettings) {
    const std::string where =
        "dt " + std::to_string(setting.dt) + " substeps " + std::to_string(setting.substeps);
    {  // A 50 kg box on a vertical slider under the block, dropping at 3 m/s onto its lower limit of -0.3 m.
      HeldBlock held = MakeHeldBlock(setting, Bob(Box(0.2f, 0.2f, 0.2f), Vec3(0.0f, 0.5f, 0.0f), 50.0f));
      ASSERT_TRUE(held.world->bodies().SetLinearVelocity(held.heavy, Vec3(0.0f, -3.0f, 0.0f)).ok());
      SliderJointSettings slider;
      slider.body_a = held.block;
      slider.body_b = held.heavy;
      slider.anchor = Vec3(0.0f, 0.5f, 0.0f);
      slider.axis = Vec3::UnitY();
      slider.limits = true;
      slider.min_position = -0.3f;
      slider.max_position = 0.3f;
      const ConstraintID joint = Join(*held.world, slider);
      float lowest = 0.0f;
      StepHeld<SliderJoint>(held, joint, setting, 2.0f, [&](const SliderJoint& c) {
        lowest = std::min(lowest, c.Position(Frame(*held.world, held.block), Frame(*held.world, held.heavy)));
      });
      EXPECT_GT(lowest, -0.31f) << "slider, " << where;
      EXPECT_LT(lowest, -0.29f) << "slider reaches its limit, " << where;
    }
    {  // A 50 kg limb hanging from the block on a 30-degree cone, thrown sideways at 15 rad/s.
      HeldBlock held = MakeHeldBlock(setting, Bob(Capsule(0.4f, 0.1f), Vec3(0.0f, 0.4f, 0.0f), 50.0f));
      ASSERT_TRUE(held.world->bodies().SetAngularVelocity(held.heavy, Vec3(0.0f, 0.0f, 15.0f)).ok());
      SwingTwistJointSettings cone;
      cone.body_a = held.block;
      cone.body_b = held.heavy;
      cone.anchor = Vec3(0.0f, 0.9f, 0.0f);
      cone.twist_axis = -Vec3::UnitY();
      cone.cone_half_angle = 30.0f * kDegree;
      const ConstraintID joint = Join(*held.world, cone);
      float widest = 0.0f;
      StepHeld<SwingTwistJoint>(held, joint, setting, 2.0f, [&](const SwingTwistJoint& c) {
        widest = std::max(widest, c.SwingAngle(*held.world->bodies().GetRotation(held.block),
                                               *held.world->bodies().GetRotation(held.heavy)));
      });
      EXPECT_LT(widest, 31.0f * kDegree) << "cone, " << where;
      EXPECT_GT(widest, 29.0f * kDegree) << "the limb reaches the cone, " << where;
    }
    {  // A 50 kg ball on a 1 m rope from the block, 0.5 m below it and thrown down at 5 m/s.
      HeldBlock held = MakeHeldBlock(setting, Bob(Sphere(0.1f), Vec3(0.0f, 0.5f, 0.0f), 50.0f));
      ASSERT_TRUE(held.world->bodies().SetLinearVelocity(held.heavy, Vec3(0.0f, -5.0f, 0.0f)).ok());
      DistanceJointSettings rope;
      rope.body_a = held.block;
      rope.body_b = held.heavy;
      rope.anchor_a = Vec3(0.0f, 1.0f, 0.0f);
      rope.anchor_b = Vec3(0.0f, 0.5f, 0.0f);
      rope.min_distance = 0.0f;
      rope.max_distance = 1.0f;
      const ConstraintID joint = Join(*held.world, rope);
      float longest = 0.0f;
      StepHeld<DistanceJoint>(held, joint, setting, 2.0f, [&](const DistanceJoint&) {
        longest = std::max(longest, (Position(*held.world, held.heavy) - Vec3(0.0f, 1.0f, 0.0f)).norm());
      });
      EXPECT_LT(longest, 1.01f) << "rope, " << where;
      EXPECT_GT(longest, 0.99f) << "the rope goes taut, " << where;
    }
    {  // A motor turning a 20 kg flap on the block at 2 rad/s against gravity (at most 98 N m of it).
      HeldBlock held = MakeHeldBlock(setting, Bob(Box(0.5f, 0.05f, 0.2f), Vec3(0.6f, 1.0f, 0.0f), 20.0f));
      HingeJointSettings hinge = FlapHinge(held.block, held.heavy, Vec3(0.1f, 1.0f, 0.0f), false);
      hinge.motor = {true, 2.0f, 1000.0f};
      const ConstraintID joint = Join(*held.world, hinge);
      float slowest = kLargeFloat, fastest = 0.0f;
      int step = 0;
      StepHeld<HingeJoint>(held, joint, setting, 2.0f, [&](const HingeJoint&) {
        if (++step * setting.dt < 0.5f) return;  // after the motor has brought it up to speed
        const float spin = held.world->bodies().GetAngularVelocity(held.heavy)->z();
        slowest = std::min(slowest, spin);
        fastest = std::max(fastest, spin);
      });
      EXPECT_GT(slowest, 1.95f) << "motor, " << where;
      EXPECT_LT(fastest, 2.05f) << "motor, " << where;
    }
  }
}

// A chain of `links` capsule links (1 kg, 0.2 m long, spinning at most `link_max_spin`) with a ball of
// `ball_radius` and `ball_mass` at its end, laid out straight from the anchor `top` along `along` (a unit
// vector), each joined to the one before by a point joint (the first to the world). Returns the bodies.
std::vector<BodyID> HangChain(PhysicsSystem& world, const Vec3& top, const Vec3& along, int links,
                              float ball_radius, float ball_mass, float link_max_spin) {
  constexpr float kHalf = 0.1f;
  const Quat laid = Quat::FromTwoVectors(Vec3(0.0f, -1.0f, 0.0f), along);  // a capsule's length is its y
  std::vector<BodyID> bodies;
  BodyID previous;  // the world first
  for (int i = 0; i <= links; ++i) {
    const bool ball = i == links;
    const Vec3 center = top + (ball ? 2 * links * kHalf + ball_radius : (2 * i + 1) * kHalf) * along;
    BodyCreationSettings body =
        ball ? Bob(Sphere(ball_radius), center, ball_mass) : Bob(Capsule(kHalf, 0.03f), center, 1.0f, laid);
    if (!ball) body.max_angular_velocity = link_max_spin;
    bodies.push_back(Add(world, body));
    PointJointSettings joint;
    joint.body_a = previous;
    joint.body_b = bodies.back();
    joint.anchor = top + (2 * i * kHalf) * along;
    Join(world, joint);
    previous = bodies.back();
  }
  return bodies;
}

// The widest gap between joined ends over `seconds` of a 100-link chain (1 kg links 0.2 m long) with a
// 100 kg ball at its end, laid out straight from an anchor 30 m up at `angle` from straight down.
float WidestChainGap(const PhysicsSettings& settings, float dt, float angle, float link_max_spin,
                     float seconds) {
  auto world = MakeWorld(settings);
  constexpr int kLinks = 100;
  constexpr float kHalf = 0.1f, kBallRadius = 0.3f;
  const Vec3 top(0.0f, 30.0f, 0.0f);
  const Vec3 along(std::sin(angle), -std::cos(angle), 0.0f);
  const std::vector<BodyID> bodies =
      HangChain(*world, top, along, kLinks, kBallRadius, 100.0f, link_max_spin);
  float widest = 0.0f;
  for (int step = 0; step < static_cast<int>(seconds / dt); ++step) {
    EXPECT_TRUE(world->Step(dt).ok());
    Vec3 upper_end = top;  // the joint above body i: the anchor, then the previous link's lower end
    for (int i = 0; i <= kLinks; ++i) {
      const Vec3 center = Position(*world, bodies[i]);
      if (!IsFinite(center)) return kLargeFloat;
      const Quat rotation = *world->bodies().GetRotation(bodies[i]);
      const Vec3 to_top = rotation * (i < kLinks ? Vec3(0.0f, kHalf, 0.0f) : Vec3(-kBallRadius * along));
      widest = std::max(widest, ((center + to_top) - upper_end).norm());
      upper_end = center - to_top;
    }
  }
  return widest;
}

TEST(Constraint, AHundredLinkChainHoldsAHundredTimesHeavierEndTogether) {
  // Swung from 60 degrees off straight down, every body at its default limits, at the default substep of
  // 1/240 s reached three ways. (With substeps of 1/120 s the tensioned chain tears: see physics/README.)
  const Setting settings[] = {kSettings[0], kSettings[1], kSettings[3]};
  for (const Setting& setting : settings) {
    const float default_spin = BodyCreationSettings().max_angular_velocity;
    EXPECT_LT(WidestChainGap(With(setting), setting.dt, 60.0f * kDegree, default_spin, 4.0f), 0.01f)
        << "dt " << setting.dt << " substeps " << setting.substeps;
  }
}

TEST(Constraint, WithoutTheExactSolveTheSameChainStretches) {
  // What the exact solve buys: by passes alone the same swing opens a joint by centimetres.
  PhysicsSettings settings = With(kSettings[0]);
  settings.exact_joints = false;
  EXPECT_GT(WidestChainGap(settings, kSettings[0].dt, 60.0f * kDegree,
                           BodyCreationSettings().max_angular_velocity, 4.0f),
            0.02f);
}

// Every pose, to the bit, after `steps` steps of a 20-link chain (1 kg links) with a 10 kg ball at its end,
// swung from 60 degrees off straight down from an anchor `height` up over a floor, at one substep of
// 1/60 s with `velocity_passes` velocity and `relax_passes` relax passes.
std::vector<float> SwungChainPoses(float height, int velocity_passes, int relax_passes, int steps) {
  PhysicsSettings settings;
  settings.substeps = 1;
  settings.velocity_iterations = velocity_passes;
  settings.relax_iterations = relax_passes;
  auto world = MakeWorld(settings);
  Add(*world, Static(Box(10.0f, 0.5f, 10.0f), Vec3(0.0f, -0.5f, 0.0f)));
  constexpr int kLinks = 20;
  constexpr float kBallRadius = 0.25f;
  const Vec3 top(0.0f, height, 0.0f);
  const float angle = 60.0f * kDegree;
  const Vec3 along(std::sin(angle), -std::cos(angle), 0.0f);
  const std::vector<BodyID> bodies =
      HangChain(*world, top, along, kLinks, kBallRadius, 10.0f, BodyCreationSettings().max_angular_velocity);
  StepFor(*world, steps, 1.0f / 60.0f);
  std::vector<float> poses;
  for (const BodyID body : bodies) {
    const Vec3 position = Position(*world, body);
    const Quat rotation = *world->bodies().GetRotation(body);
    poses.insert(poses.end(), {position.x(), position.y(), position.z(), rotation.x(), rotation.y(),
                               rotation.z(), rotation.w()});
  }
  return poses;
}

TEST(Constraint, MorePassesOverAChainTheExactSolveHoldsAloneChangeNothingAndWithAContactTheyDo) {
  // Nothing but its joints acts on a chain in the air: after one velocity pass of the exact solve, and one
  // relax pass, a second finds nothing left to do (it is skipped), so ten of each end where one does.
  constexpr int kSteps = 90;
  EXPECT_EQ(SwungChainPoses(12.0f, 1, 1, kSteps), SwungChainPoses(12.0f, 10, 2, kSteps));
  // Hung low, its ball strikes the floor at the bottom of the swing: contacts share the island, each pass
  // of theirs moves what the exact solve holds, and the passes count again.
  const std::vector<float> one_pass = SwungChainPoses(4.2f, 1, 1, kSteps);
  const std::vector<float> ten_passes = SwungChainPoses(4.2f, 10, 2, kSteps);
  EXPECT_NE(one_pass, ten_passes);
  // Neither lets the ball through the floor (its centre stays a radius up, to a centimetre).
  EXPECT_GT(one_pass[one_pass.size() - 6], 0.24f);
  EXPECT_GT(ten_passes[ten_passes.size() - 6], 0.24f);
}

TEST(Constraint, AMotorReachesItsTargetSpeedWithinItsTorque) {
  for (const Setting& setting : kSettings) {
    auto world = MakeWorld(With(setting));
    // A 10 kg wheel on a vertical hinge (gravity gives no torque about it), driven at 3 rad/s.
    const BodyID wheel = Add(*world, Bob(Box(0.5f, 0.1f, 0.5f), Vec3(0.0f, 1.0f, 0.0f), 10.0f));
    HingeJointSettings hinge;
    hinge.body_b = wheel;
    hinge.anchor = Vec3(0.0f, 1.0f, 0.0f);
    hinge.axis = Vec3::UnitY();
    hinge.motor = {true, 3.0f, 50.0f};
    const ConstraintID motor = Join(*world, hinge);
    StepFor(*world, static_cast<int>(2.0f / setting.dt), setting.dt);
    EXPECT_NEAR(world->bodies().GetAngularVelocity(wheel)->y(), 3.0f, 0.03f) << "dt " << setting.dt;
    // Its torque is what holds the speed against nothing: about zero once there.
    EXPECT_LT(world->constraints().GetForces(motor)->torque.y(), 1.0f);
    // A weak motor accelerates at its torque over the inertia only: I = m (0.5^2 + 0.5^2) / 3 about y.
    const float inertia = 10.0f * (0.25f + 0.25f) / 3.0f;
    ASSERT_TRUE(world->bodies().SetAngularVelocity(wheel, Vec3::Zero()).ok());
    ASSERT_TRUE(world->constraints()
                    .Modify<HingeJoint>(motor,
                                        [](HingeJoint& joint) {
                                          return joint.SetMotor({true, 3.0f, 0.5f});
                                        })
                    .ok());
    const int steps = static_cast<int>(std::lround(1.0f / setting.dt));
    StepFor(*world, steps, setting.dt);
    const float expected = 0.5f / inertia * (steps * setting.dt);
    EXPECT_NEAR(world->bodies().GetAngularVelocity(wheel)->y(), expected, 0.02f * expected);
  }
}

TEST(Constraint, ASliderMotorDrivesToItsLimitAndStops) {
  for (const Setting& setting : kSettings) {
    auto world = MakeWorld(With(setting));
    const BodyID carriage = Add(*world, Bob(Box(0.2f, 0.2f, 0.2f), Vec3(0.0f, 1.0f, 0.0f), 5.0f));
    SliderJointSettings slider;
    slider.body_b = carriage;
    slider.anchor = Vec3(0.0f, 1.0f, 0.0f);
    slider.axis = Vec3::UnitX();
    slider.limits = true;
    slider.min_position = -0.2f;
    slider.max_position = 0.5f;
    slider.motor = {true, 1.0f, 200.0f};
    Join(*world, slider);
    StepFor(*world, static_cast<int>(0.25f / setting.dt), setting.dt);
    EXPECT_NEAR(Velocity(*world, carriage).x(), 1.0f, 0.02f) << "dt " << setting.dt;
    float farthest = 0.0f;
    for (int step = 0; step < static_cast<int>(2.0f / setting.dt); ++step) {
      ASSERT_TRUE(world->Step(setting.dt).ok());
      farthest = std::max(farthest, Position(*world, carriage).x());
    }
    EXPECT_LT(farthest, 0.51f);
    EXPECT_GT(farthest, 0.49f);
    // Gravity does not pull it off its line, and it does not turn.
    EXPECT_NEAR(Position(*world, carriage).y(), 1.0f, 1e-3f);
    EXPECT_LT(world->bodies().GetRotation(carriage)->angularDistance(Quat::Identity()), 1e-3f);
  }
}

TEST(Constraint, AWeldHoldsACantileverAndAConeHoldsALimb) {
  for (const Setting& setting : kSettings) {
    auto world = MakeWorld(With(setting));
    const BodyID wall = Add(*world, Static(Box(0.1f, 1.0f, 1.0f), Vec3::Zero()));
    const BodyID beam = Add(*world, Bob(Box(0.5f, 0.05f, 0.05f), Vec3(0.6f, 0.5f, 0.0f), 20.0f));
    FixedJointSettings weld;
    weld.body_a = wall;
    weld.body_b = beam;
    weld.anchor = Vec3(0.1f, 0.5f, 0.0f);
    Join(*world, weld);
    // A limb hung from the world by a cone of 30 degrees, kicked sideways.
    const BodyID limb = Add(*world, Bob(Capsule(0.2f, 0.05f), Vec3(3.0f, 1.75f, 0.0f), 3.0f));
    SwingTwistJointSettings cone;
    cone.body_b = limb;
    cone.anchor = Vec3(3.0f, 2.0f, 0.0f);
    cone.twist_axis = -Vec3::UnitY();
    cone.cone_half_angle = 30.0f * kDegree;
    cone.min_twist = -0.2f;
    cone.max_twist = 0.2f;
    const ConstraintID cone_id = Join(*world, cone);
    ASSERT_TRUE(world->bodies().SetAngularVelocity(limb, Vec3(0.0f, 3.0f, 20.0f)).ok());
    float widest_swing = 0.0f, widest_twist = 0.0f;
    for (int step = 0; step < static_cast<int>(2.0f / setting.dt); ++step) {
      ASSERT_TRUE(world->Step(setting.dt).ok());
      const Quat turn = *world->bodies().GetRotation(limb);
      ASSERT_TRUE(world->constraints()
                      .Read(cone_id,
                            [&](const Constraint& c) {
                              const auto& joint = static_cast<const SwingTwistJoint&>(c);
                              widest_swing = std::max(widest_swing, joint.SwingAngle(Quat::Identity(), turn));
                              widest_twist =
                                  std::max(widest_twist, std::abs(joint.TwistAngle(Quat::Identity(), turn)));
                            })
                      .ok());
    }
    EXPECT_LT(widest_swing, 31.0f * kDegree) << "dt " << setting.dt;
    EXPECT_GT(widest_swing, 25.0f * kDegree) << "the kick must reach the cone";
    EXPECT_LT(widest_twist, 0.2f + 1.0f * kDegree);
    // Solved by passes (the wall does not move, so no exact solve): the 20 kg beam droops by millimetres.
    EXPECT_LT((Position(*world, beam) - Vec3(0.6f, 0.5f, 0.0f)).norm(), 5e-3f) << "dt " << setting.dt;
    EXPECT_LT(world->bodies().GetRotation(beam)->angularDistance(Quat::Identity()), 0.5f * kDegree);
  }
}

TEST(Constraint, AJointBreaksAtItsForceAndNotBelow) {
  for (const float limit : {120.0f, 80.0f}) {
    auto world = MakeWorld();
    // 10 kg hung from the world: the joint carries 98.1 N.
    const BodyID weight = Add(*world, Bob(Sphere(0.2f), Vec3(0.0f, 1.0f, 0.0f), 10.0f));
    PointJointSettings joint;
    joint.body_b = weight;
    joint.anchor = Vec3(0.0f, 1.5f, 0.0f);
    joint.max_force = limit;
    const ConstraintID id = Join(*world, joint);
    StepFor(*world, 60);
    const bool broken = *world->constraints().IsBroken(id);
    if (limit > 98.1f) {
      EXPECT_FALSE(broken);
      EXPECT_NEAR(world->constraints().GetForces(id)->force.y(), 98.1f, 2.0f);
      EXPECT_NEAR(Position(*world, weight).y(), 1.0f, 1e-3f);
    } else {
      EXPECT_TRUE(broken);
      EXPECT_LT(Position(*world, weight).y(), 0.0f) << "a broken joint lets go";
    }
  }
}

TEST(Constraint, JoinedBodiesFormOneIslandAndSleepAndWakeTogether) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10.0f, 0.5f, 10.0f), Vec3(0.0f, -0.5f, 0.0f)));
  std::vector<BodyID> boxes;
  for (int i = 0; i < 3; ++i) {
    BodyCreationSettings box = Dynamic(Box(0.25f, 0.25f, 0.25f), Vec3(1.0f * i, 0.25f, 0.0f));
    boxes.push_back(Add(*world, box));
  }
  for (int i = 0; i + 1 < 3; ++i) {
    DistanceJointSettings rod;
    rod.body_a = boxes[i];
    rod.body_b = boxes[i + 1];
    rod.anchor_a = Vec3(1.0f * i + 0.25f, 0.25f, 0.0f);
    rod.anchor_b = Vec3(1.0f * i + 0.75f, 0.25f, 0.0f);
    Join(*world, rod);
  }
  StepFor(*world, 1);
  EXPECT_EQ(world->last_step_stats().islands, 1u);
  EXPECT_EQ(world->last_step_stats().constraints, 2u);
  StepFor(*world, 120);
  for (const BodyID box : boxes) EXPECT_FALSE(*world->bodies().IsActive(box));
  // Waking one end wakes the group.
  ASSERT_TRUE(world->bodies().SetLinearVelocity(boxes[0], Vec3(0.0f, 0.0f, 0.5f)).ok());
  StepFor(*world, 1);
  for (const BodyID box : boxes) EXPECT_TRUE(*world->bodies().IsActive(box));
}

TEST(Constraint, JoinedBodiesDoNotCollideUnlessAsked) {
  for (const bool collide : {false, true}) {
    auto world = MakeWorld();
    PhysicsSettings settings;
    settings.gravity = Vec3::Zero();
    ASSERT_TRUE(world->SetSettings(settings).ok());
    // Two boxes overlapping by 10 cm, joined by a ball joint at the overlap's centre.
    const BodyID a = Add(*world, Bob(Box(0.5f, 0.5f, 0.5f), Vec3(0.0f, 0.0f, 0.0f), 1.0f));
    const BodyID b = Add(*world, Bob(Box(0.5f, 0.5f, 0.5f), Vec3(0.9f, 0.0f, 0.0f), 1.0f));
    PointJointSettings joint;
    joint.body_a = a;
    joint.body_b = b;
    joint.anchor = Vec3(0.45f, 0.0f, 0.0f);
    joint.collide_connected = collide;
    Join(*world, joint);
    StepFor(*world, 1);
    EXPECT_EQ(world->last_step_stats().manifolds > 0, collide);
  }
}

TEST(Constraint, BadJointsAreRefusedAndLeaveTheWorldAsItWas) {
  auto world = MakeWorld();
  const BodyID ground = Add(*world, Static(Box(5.0f, 0.5f, 5.0f), Vec3::Zero()));
  const BodyID other_static = Add(*world, Static(Box(1.0f, 1.0f, 1.0f), Vec3(10.0f, 0.0f, 0.0f)));
  const BodyID body = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0.0f, 2.0f, 0.0f)));
  const BodyID gone = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(3.0f, 2.0f, 0.0f)));
  ASSERT_TRUE(world->bodies().RemoveAndDestroyBody(gone).ok());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto refused = [&](const JointSettings& settings, const char* what) {
    const Result<ConstraintID> id = world->constraints().Add(settings);
    EXPECT_FALSE(id.ok()) << what;
    if (!id.ok()) {
      EXPECT_FALSE(id.error().message.empty());
    }
  };
  PointJointSettings point;
  point.body_b = body;
  point.anchor = Vec3(nan, 0.0f, 0.0f);
  refused(point, "NaN anchor");
  point.anchor = Vec3(0.0f, 1e9f, 0.0f);
  refused(point, "far anchor");
  point.anchor = Vec3::Zero();
  point.body_b = gone;
  refused(point, "stale body");
  point.body_a = body;
  point.body_b = body;
  refused(point, "one body twice");
  point.body_a = ground;
  point.body_b = other_static;
  refused(point, "nothing moves");
  point.body_a = ground;
  point.body_b = body;
  point.max_force = -1.0f;
  refused(point, "negative break force");
  HingeJointSettings hinge;
  hinge.body_b = body;
  hinge.axis = Vec3::Zero();
  refused(hinge, "no axis");
  hinge.axis = Vec3::UnitX();
  hinge.normal = Vec3::UnitX();
  refused(hinge, "normal along the axis");
  hinge.normal = Vec3::Zero();
  hinge.limits = true;
  hinge.min_angle = 0.5f;
  refused(hinge, "min_angle above 0");
  DistanceJointSettings rod;
  rod.body_b = body;
  rod.anchor_b = Vec3(0.0f, 2.0f, 0.0f);
  rod.min_distance = 2.0f;
  rod.max_distance = 1.0f;
  refused(rod, "min above max");
  SwingTwistJointSettings cone;
  cone.body_b = body;
  cone.cone_half_angle = 0.0f;
  refused(cone, "no cone");
  EXPECT_EQ(world->constraints().count(), 0u);
  EXPECT_FALSE(world->constraints().Remove(ConstraintID{0, 0}).ok());
  // A good one, removed twice: the second time its id is stale.
  point.max_force = 0.0f;
  const ConstraintID id = Join(*world, point);
  ASSERT_TRUE(world->constraints().Remove(id).ok());
  EXPECT_FALSE(world->constraints().Remove(id).ok());
  EXPECT_FALSE(world->constraints().GetForces(id).ok());
  EXPECT_EQ(world->constraints().count(), 0u);
  StepFor(*world, 10);
  EXPECT_EQ(world->last_step_stats().constraints, 0u);
}

TEST(Constraint, AJointWaitsWhileItsBodyIsOutOfTheWorld) {
  auto world = MakeWorld();
  const BodyID body = Add(*world, Bob(Sphere(0.2f), Vec3(0.0f, 1.0f, 0.0f), 1.0f));
  PointJointSettings joint;
  joint.body_b = body;
  joint.anchor = Vec3(0.0f, 1.5f, 0.0f);
  Join(*world, joint);
  ASSERT_TRUE(world->bodies().RemoveBody(body).ok());
  StepFor(*world, 10);
  EXPECT_EQ(world->last_step_stats().constraints, 0u);
  ASSERT_TRUE(world->bodies().AddBody(body).ok());
  StepFor(*world, 60);
  EXPECT_EQ(world->last_step_stats().constraints, 1u);
  EXPECT_NEAR(Position(*world, body).y(), 1.0f, 1e-3f);
}

// A heap of ragdolls dropped on a height field, from the benchmark's builder.
bench::BenchScene RagdollHeap(int count) {
  bench::BenchScene scene;
  HeightFieldGeometry& field = scene.height_fields.emplace_back();
  field.columns = field.rows = 17;
  for (std::uint32_t z = 0; z < field.rows; ++z)
    for (std::uint32_t x = 0; x < field.columns; ++x)
      field.heights.push_back(0.4f * std::sin(0.5f * x) * std::cos(0.4f * z));
  BodyDescription ground;
  ground.shape = SceneShape::kHeightField, ground.position = Vec3(-8.0f, 0.0f, -8.0f);
  ground.motion = SceneMotion::kStatic, ground.friction = 0.6f;
  scene.bodies.push_back(ground);
  for (int k = 0; k < count; ++k)
    bench::AddRagdoll(scene, Vec3(0.1f * (k % 3), 1.5f + 0.9f * k, 0.0f),
                      Quat(Eigen::AngleAxisf(0.7f * k, Vec3::UnitY())) *
                          Quat(Eigen::AngleAxisf(0.5f * kPi, Vec3::UnitX())));
  scene.sleeping = true;
  return scene;
}

TEST(Constraint, ARagdollPileSettlesWithoutNaNTheSameOnAnyThreadCount) {
  const bench::BenchScene scene = RagdollHeap(8);
  std::vector<std::vector<Vec3>> finals;
  for (const int threads : {0, 2}) {
    PhysicsSystemConfig config;
    if (threads == 0)
      config.job_system = std::make_shared<SerialJobSystem>();
    else
      config.job_system = std::make_shared<ThreadPoolJobSystem>(threads);
    std::optional<bench::StrataScene> built = bench::BuildStrataScene(scene, config);
    ASSERT_TRUE(built.has_value());
    PhysicsSystem& world = *built->world;
    EXPECT_EQ(world.constraints().count(), 8u * 11u);
    for (int step = 0; step < 480; ++step) {
      ASSERT_TRUE(world.Step(1.0f / 60.0f).ok());
      for (const BodyID part : built->dynamic_bodies) ASSERT_TRUE(IsFinite(Position(world, part))) << step;
    }
    float fastest = 0.0f;
    std::vector<Vec3> positions;
    for (const BodyID part : built->dynamic_bodies) {
      fastest = std::max(fastest, Velocity(world, part).norm());
      positions.push_back(Position(world, part));
      EXPECT_GT(positions.back().y(), -1.0f) << "nothing falls through the field";
    }
    EXPECT_LT(fastest, 0.3f) << "the pile settles";
    finals.push_back(positions);
  }
  EXPECT_EQ(finals[0], finals[1]);
}

// A position step on its own: two boxes held by a joint are pulled apart (or turned) by hand, as integration
// drifts them, and one step must take Constraint::kPositionFraction of the error out, moving each side that
// moves against its inverse mass and leaving the world side where it is.
struct DriftedPair {
  SolverBody bodies[3];  // 0: the fixed body; A at 1, B at 2
  SolverPose poses[3];
};
DriftedPair MakeDriftedPair(const Vec3& drift, const Quat& turn) {
  DriftedPair pair;
  const float inverse_masses[3] = {0.0f, 1.0f, 0.25f};
  for (int i = 1; i < 3; ++i) {
    pair.bodies[i].inverse_mass = inverse_masses[i];
    for (int axis = 0; axis < 3; ++axis)
      pair.bodies[i].inverse_inertia[axis] = ToVec4(3.0f * inverse_masses[i] * Vec3::Unit(axis));
  }
  pair.poses[1].center_of_mass = ToVec4(Vec3(0.0f, 0.0f, 0.0f));
  pair.poses[2].center_of_mass = ToVec4(Vec3(1.0f, 0.0f, 0.0f) + drift);
  pair.poses[2].rotation = turn;
  return pair;
}
// Separation of the anchors (made at x = 0.5 between boxes at 0 and 1) and B's turn relative to A.
std::pair<Vec3, float> PairError(const DriftedPair& pair) {
  const Vec3 on_a = ToVec3(pair.poses[1].center_of_mass) + pair.poses[1].rotation * Vec3(0.5f, 0.0f, 0.0f);
  const Vec3 on_b = ToVec3(pair.poses[2].center_of_mass) + pair.poses[2].rotation * Vec3(-0.5f, 0.0f, 0.0f);
  return {on_b - on_a, pair.poses[2].rotation.angularDistance(pair.poses[1].rotation)};
}

TEST(Constraint, APositionStepTakesItsShareOfTheDriftOut) {
  const BodyFrame at_a{Vec3::Zero(), Quat::Identity()}, at_b{Vec3(1.0f, 0.0f, 0.0f), Quat::Identity()};
  const float share = 1.0f - Constraint::kPositionFraction;
  const Vec3 drift(0.0f, 0.04f, -0.03f);
  // About the arm, so the turn alone does not move B's anchor.
  const Quat turn(Eigen::AngleAxisf(0.1f, Vec3::UnitX()));
  for (const bool world_side : {false, true}) {
    PointJointSettings point;
    point.body_a = world_side ? BodyID{} : BodyID{0, 0};
    point.body_b = BodyID{1, 0};
    point.anchor = Vec3(0.5f, 0.0f, 0.0f);
    FixedJointSettings weld;
    static_cast<JointSettingsBase&>(weld) = point;
    weld.anchor = point.anchor;
    std::vector<std::unique_ptr<Constraint>> joints;
    joints.push_back(std::move(*PointJoint::Create(point, at_a, at_b)));
    joints.push_back(std::move(*FixedJoint::Create(weld, at_a, at_b)));
    for (const auto& joint : joints) {
      const bool welded = joint->type() == ConstraintType::kFixed;
      DriftedPair pair = MakeDriftedPair(drift, welded ? turn : Quat::Identity());
      const auto [gap_before, turn_before] = PairError(pair);
      ConstraintSide a, b;
      a.solver_index = world_side ? 0 : 1;
      a.start = at_a;
      b.solver_index = 2;
      joint->BeginStep(a, b, 1.0f / 240.0f);
      const SolverPose poses_before[3] = {pair.poses[0], pair.poses[1], pair.poses[2]};
      joint->SolvePosition(pair.bodies, pair.poses, 0.0f);
      const auto [gap_after, turn_after] = PairError(pair);
      const std::string what = std::string(ToString(joint->type())) + (world_side ? " to the world" : "");
      // Linear in the error up to the turn's second order.
      EXPECT_NEAR(gap_after.norm(), share * gap_before.norm(), 0.02f * gap_before.norm()) << what;
      if (welded) {
        EXPECT_NEAR(turn_after, share * turn_before, 0.02f * turn_before) << what;
      }
      for (int i = 1; i < 3; ++i) {
        const Vec3 moved = ToVec3(pair.poses[i].center_of_mass - poses_before[i].center_of_mass);
        // The write-back applies the deltas: they must carry the move.
        EXPECT_LT((ToVec3(pair.bodies[i].delta_position) - moved).norm(), 1e-6f) << what;
        EXPECT_TRUE(pair.bodies[i].linear_velocity.isZero(0.0f)) << what << ": velocities stay";
      }
      const Vec3 moved_a = ToVec3(pair.poses[1].center_of_mass - poses_before[1].center_of_mass);
      const Vec3 moved_b = ToVec3(pair.poses[2].center_of_mass - poses_before[2].center_of_mass);
      if (world_side) {
        EXPECT_TRUE(moved_a.isZero(0.0f)) << what << ": the world side never moves";
      } else {
        // Equal and opposite pushes: each side moves by its inverse mass.
        EXPECT_LT((moved_a / 1.0f + moved_b / 0.25f).norm(), 1e-5f) << what;
      }
    }
  }
}

}  // namespace
}  // namespace strata::test
