// Joints set their rows up once per pose version (SolverPass::pose_version) and keep them for every pass
// that sees the same poses: the velocities must come out bit for bit as if each pass had set them up anew,
// and a new version must set them up again.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "physics/constraints/DistanceJoint.h"
#include "physics/constraints/FixedJoint.h"
#include "physics/constraints/HingeJoint.h"
#include "physics/constraints/PointJoint.h"
#include "physics/constraints/SliderJoint.h"
#include "physics/constraints/SwingTwistJoint.h"

namespace strata {
namespace {

using JointFactory = std::function<std::unique_ptr<Constraint>(const BodyFrame&, const BodyFrame&)>;

template <class Joint, class Settings>
std::unique_ptr<Constraint> Make(Settings settings, const BodyFrame& a, const BodyFrame& b) {
  settings.body_a = BodyID{0, 1};
  settings.body_b = BodyID{1, 1};
  auto joint = Joint::Create(settings, a, b);
  EXPECT_TRUE(joint.ok()) << joint.error().message;
  return joint ? std::move(joint.value()) : nullptr;
}

// Every kind of joint, with its limits, motors and friction on, so every row takes part.
std::vector<std::pair<std::string, JointFactory>> Factories() {
  const Vec3 anchor(0.1f, 1.0f, -0.2f);
  std::vector<std::pair<std::string, JointFactory>> factories;
  factories.emplace_back("point", [=](const BodyFrame& a, const BodyFrame& b) {
    PointJointSettings settings;
    settings.anchor = anchor;
    return Make<PointJoint>(settings, a, b);
  });
  factories.emplace_back("hinge", [=](const BodyFrame& a, const BodyFrame& b) {
    HingeJointSettings settings;
    settings.anchor = anchor;
    settings.axis = Vec3(0.0f, 0.0f, 1.0f);
    settings.limits = true;
    settings.min_angle = -0.05f;
    settings.max_angle = 0.05f;
    settings.motor = JointMotor{true, 3.0f, 50.0f};
    return Make<HingeJoint>(settings, a, b);
  });
  factories.emplace_back("swing_twist", [=](const BodyFrame& a, const BodyFrame& b) {
    SwingTwistJointSettings settings;
    settings.anchor = anchor;
    settings.twist_axis = Vec3(0.0f, -1.0f, 0.0f);
    settings.cone_half_angle = 0.1f;
    settings.min_twist = -0.05f;
    settings.max_twist = 0.05f;
    settings.max_friction_torque = 2.0f;
    return Make<SwingTwistJoint>(settings, a, b);
  });
  factories.emplace_back("slider", [=](const BodyFrame& a, const BodyFrame& b) {
    SliderJointSettings settings;
    settings.anchor = anchor;
    settings.axis = Vec3(1.0f, 0.2f, 0.0f);
    settings.limits = true;
    settings.min_position = -0.01f;
    settings.max_position = 0.01f;
    settings.max_friction_force = 5.0f;
    return Make<SliderJoint>(settings, a, b);
  });
  factories.emplace_back("distance", [=](const BodyFrame& a, const BodyFrame& b) {
    DistanceJointSettings settings;
    settings.anchor_a = anchor;
    settings.anchor_b = anchor + Vec3(0.0f, -0.5f, 0.0f);
    settings.rest_length = 0.46f;
    settings.min_distance = 0.45f;
    settings.max_distance = 0.48f;
    settings.spring_hertz = 4.0f;
    return Make<DistanceJoint>(settings, a, b);
  });
  factories.emplace_back("fixed", [=](const BodyFrame& a, const BodyFrame& b) {
    FixedJointSettings settings;
    settings.anchor = anchor;
    return Make<FixedJoint>(settings, a, b);
  });
  return factories;
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
  for (const auto& [name, make] : Factories()) {
    SCOPED_TRACE(name);
    const Bodies bodies = MakeBodies(a, b);
    const std::unique_ptr<Constraint> kept = make(a, b), anew = make(a, b), stale = make(a, b);
    ASSERT_TRUE(kept && anew && stale);
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
