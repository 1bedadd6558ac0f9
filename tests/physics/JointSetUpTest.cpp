// Joints set their rows up once per pose version (SolverPass::pose_version) and keep them for every pass
// that sees the same poses: the velocities must come out bit for bit as if each pass had set them up anew,
// and a new version must set them up again.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <variant>
#include <vector>

#include "physics/constraints/ConstraintManager.h"

namespace strata {
namespace {

// Every kind of joint, with its limits, motors and friction on, so every row takes part.
std::vector<JointSettings> EveryKind() {
  const Vec3 anchor(0.1f, 1.0f, -0.2f);
  const PointJointSettings point;
  HingeJointSettings hinge;
  hinge.axis = Vec3(0.0f, 0.0f, 1.0f);
  hinge.limits = true;
  hinge.min_angle = -0.05f;
  hinge.max_angle = 0.05f;
  hinge.motor = JointMotor{true, 3.0f, 50.0f};
  SwingTwistJointSettings swing_twist;
  swing_twist.twist_axis = Vec3(0.0f, -1.0f, 0.0f);
  swing_twist.cone_half_angle = 0.1f;
  swing_twist.min_twist = -0.05f;
  swing_twist.max_twist = 0.05f;
  swing_twist.max_friction_torque = 2.0f;
  SliderJointSettings slider;
  slider.axis = Vec3(1.0f, 0.2f, 0.0f);
  slider.limits = true;
  slider.min_position = -0.01f;
  slider.max_position = 0.01f;
  slider.max_friction_force = 5.0f;
  DistanceJointSettings distance;
  distance.anchor_a = anchor;
  distance.anchor_b = anchor + Vec3(0.0f, -0.5f, 0.0f);
  distance.rest_length = 0.46f;
  distance.min_distance = 0.45f;
  distance.max_distance = 0.48f;
  distance.spring_hertz = 4.0f;
  const FixedJointSettings fixed;
  std::vector<JointSettings> kinds = {point, hinge, swing_twist, slider, distance, fixed};
  // Each at the anchor, between bodies 0 and 1.
  for (JointSettings& kind : kinds)
    std::visit(
        [&](auto& settings) {
          settings.body_a = BodyID{0, 1};
          settings.body_b = BodyID{1, 1};
          if constexpr (requires { settings.anchor; }) settings.anchor = anchor;
        },
        kind);
  return kinds;
}

std::unique_ptr<Constraint> Make(const JointSettings& settings, const BodyFrame& a, const BodyFrame& b) {
  auto joint = MakeJoint(settings, a, b);
  EXPECT_TRUE(joint.ok()) << joint.error().message;
  return joint ? std::move(joint.value()) : nullptr;
}

// Two moving bodies (solver indices 1 and 2; 0 is the no-impulse slot), moving apart and turning.
struct Bodies {
  SolverBody body[3];
  SolverPose pose[3];
};

Bodies MakeBodies(const BodyFrame& a, const BodyFrame& b) {
  Bodies bodies;
  const BodyFrame frames[2] = {a, b};
  const float inverse_masses[2] = {0.5f, 2.0f};
  const Mat3 inverse_local = Vec3(1.5f, 0.7f, 2.2f).asDiagonal();
  for (int k = 0; k < 2; ++k) {
    SolverBody& body = bodies.body[k + 1];
    body.inverse_mass = inverse_masses[k];
    InverseInertiaColumns(frames[k].rotation.toRotationMatrix(), inverse_local, body.inverse_inertia);
    bodies.pose[k + 1].center_of_mass = ToVec4(frames[k].center_of_mass);
    bodies.pose[k + 1].rotation = frames[k].rotation;
  }
  bodies.body[1].linear_velocity = ToVec4(Vec3(0.3f, -1.0f, 0.2f));
  bodies.body[1].angular_velocity = ToVec4(Vec3(0.5f, 2.0f, -1.0f));
  bodies.body[2].linear_velocity = ToVec4(Vec3(-0.4f, 0.8f, 0.1f));
  bodies.body[2].angular_velocity = ToVec4(Vec3(-2.5f, 0.3f, 1.5f));
  return bodies;
}

ConstraintPassContext Context(int pose_version, bool use_bias) {
  ConstraintPassContext pass;
  pass.h = 1.0f / 240.0f;
  pass.inverse_h = 240.0f;
  pass.rigid_spring = MakeSoftSpring(60.0f, 5.0f, pass.h);
  pass.use_bias = use_bias;
  pass.pose_version = pose_version;
  return pass;
}

// A substep's passes: warm start and three velocity passes at `first_version`, then the poses move (an
// integration) and two relax passes run at `relax_version`. Returns the bodies' velocities.
std::vector<float> RunPasses(Constraint& joint, Bodies bodies, int first_version, int relax_version) {
  const ConstraintSide side_a{1, {}, Vec3::Zero(), Vec3::Zero()};
  const ConstraintSide side_b{2, {}, Vec3::Zero(), Vec3::Zero()};
  joint.BeginStep(side_a, side_b, 1.0f / 240.0f);
  auto pass = [&](int version, bool use_bias, bool warm_start) {
    SolverBody stand_in_a, stand_in_b;
    ConstraintBodies view = joint.BodiesForPass(bodies.body, bodies.pose, 0.0f, stand_in_a, stand_in_b);
    if (warm_start)
      joint.WarmStart(view, Context(version, use_bias));
    else
      joint.SolveVelocity(view, Context(version, use_bias), true);
  };
  pass(first_version, true, true);
  for (int iteration = 0; iteration < 3; ++iteration) pass(first_version, true, false);
  for (int k = 1; k <= 2; ++k) {
    SolverPose& pose = bodies.pose[k];
    pose.center_of_mass += 0.02f * bodies.body[k].linear_velocity;
    TurnBy(pose.rotation, 0.02f * bodies.body[k].angular_velocity);
  }
  for (int iteration = 0; iteration < 2; ++iteration) pass(relax_version, false, false);
  std::vector<float> velocities;
  for (int k = 1; k <= 2; ++k)
    for (const Vec4* v : {&bodies.body[k].linear_velocity, &bodies.body[k].angular_velocity})
      for (int i = 0; i < 3; ++i) velocities.push_back((*v)[i]);
  return velocities;
}

bool BitIdentical(const std::vector<float>& x, const std::vector<float>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
}

TEST(JointSetUp, PassesOfOnePoseVersionGiveTheVelocitiesOfPassesThatEachSetUpAnew) {
  const BodyFrame a{Vec3(0.0f, 1.5f, 0.0f), Quat(Eigen::AngleAxisf(0.4f, Vec3(1, 2, 0).normalized()))};
  const BodyFrame b{Vec3(0.1f, 0.6f, -0.1f), Quat(Eigen::AngleAxisf(-0.7f, Vec3(0, 1, 3).normalized()))};
  for (const JointSettings& kind : EveryKind()) {
    const Bodies bodies = MakeBodies(a, b);
    const std::unique_ptr<Constraint> kept = Make(kind, a, b), anew = Make(kind, a, b),
                                      stale = Make(kind, a, b);
    ASSERT_TRUE(kept && anew && stale);
    SCOPED_TRACE(ToString(kept->type()));
    const std::vector<float> with_versions = RunPasses(*kept, bodies, 0, 1);
    const std::vector<float> every_pass = RunPasses(*anew, bodies, -1, -1);
    EXPECT_TRUE(BitIdentical(with_versions, every_pass));
    // Had the relax passes been told the poses were unchanged, they would have solved the old rows: the
    // version is what the joints go by.
    const std::vector<float> unchanged_version = RunPasses(*stale, bodies, 0, 0);
    EXPECT_FALSE(BitIdentical(unchanged_version, every_pass));
  }
}

}  // namespace
}  // namespace strata
