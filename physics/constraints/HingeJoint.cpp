#include "physics/constraints/HingeJoint.h"

#include <cmath>
#include <limits>

namespace strata {

namespace {
// The angle from `from` to `to` about `axis` (all unit, `from` and `to` at right angles to it).
float SignedAngle(const Vec3& from, const Vec3& to, const Vec3& axis) {
  return FastAtan2(from.cross(to).dot(axis), from.dot(to));
}
}  // namespace

Result<std::unique_ptr<HingeJoint>> HingeJoint::Create(const HingeJointSettings& settings, const BodyFrame& a,
                                                       const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor, "anchor"); !valid) return valid.error();
  const Result<Vec3> axis = UnitAxis(settings.axis, "axis");
  if (!axis) return axis.error();
  const Result<Vec3> normal = PerpendicularAxis(axis.value(), settings.normal, "normal");
  if (!normal) return normal.error();
  if (!std::isfinite(settings.min_angle) || !std::isfinite(settings.max_angle) ||
      settings.min_angle < -kPi - 1e-6f || settings.min_angle > 0.0f || settings.max_angle < 0.0f ||
      settings.max_angle > kPi + 1e-6f)
    return MakeError(ErrorCode::kInvalidArgument,
                     "hinge limits must be min_angle in [-pi, 0] and max_angle in [0, pi] (rad)");
  if (Status valid = ValidateDrive(settings.max_friction_torque, "max_friction_torque", settings.motor);
      !valid)
    return valid.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, axis.value(), normal.value());
  return std::unique_ptr<HingeJoint>(new HingeJoint(settings, frames));
}

HingeJoint::HingeJoint(const HingeJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kHinge, settings, frames),
      free_(settings.limits, settings.min_angle, settings.max_angle, settings.max_friction_torque,
            settings.motor) {}

std::string HingeJoint::Describe() const {
  return free_.Describe("hinge joint", "rad");
}

float HingeJoint::Angle(const Quat& rotation_a, const Quat& rotation_b) const {
  const Mat3 axes_a = (rotation_a * local().frame_a).toRotationMatrix();
  const Mat3 axes_b = (rotation_b * local().frame_b).toRotationMatrix();
  return SignedAngle(axes_a.col(1), axes_b.col(1), axes_a.col(0));
}

void HingeJoint::SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  if (!NeedsSetUp(pass)) return;
  const WorldFrames frames = Frames(bodies);
  const Vec3 axis = frames.axes_a.col(0);
  point_.Prepare(frames.r_a, frames.r_b);
  separation_ = frames.separation;
  rotation_.Prepare(bodies, axis, frames.axes_b.col(1), frames.axes_b.col(2));
  free_.Prepare(bodies, axis);
  if (free_.limits()) angle_ = SignedAngle(frames.axes_a.col(1), frames.axes_b.col(1), axis);
}

void HingeJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  point_.WarmStart(bodies);
  rotation_.WarmStart(bodies);
  free_.WarmStart(bodies);
}

void HingeJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) {
  SetUp(bodies, pass);
  // The free axis first (drive, then limits); the axis and the point last, which matter most.
  free_.Solve(bodies, pass, angle_);
  if (!rigid_rows) return;
  rotation_.Solve(bodies, pass);
  const RowTarget target = EqualityTarget(1.0f, pass);
  point_.Solve(bodies, target.bias * separation_, target);
}

int HingeJoint::RigidRowCount() const {
  return 5;
}

void HingeJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldFrames frames = Frames(bodies);
  point_.Prepare(frames.r_a, frames.r_b);
  rotation_.Prepare(bodies, frames.axes_a.col(0), frames.axes_b.col(1), frames.axes_b.col(2));
  point_.Rows(frames.separation, rows);
  rotation_.Rows(rows + 3);
}

int HingeJoint::FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass, JointRow* rows) {
  SetUp(bodies, pass);
  return free_.FreeRows(rows);
}

int HingeJoint::FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) {
  return free_.Passes(pass, angle_, 0, rows);
}

Constraint::Impulses HingeJoint::AccumulatedImpulses() const {
  return {point_.impulse(), rotation_.AngularImpulse() + free_.lower().AngularImpulse() +
                                free_.upper().AngularImpulse() + free_.drive().AngularImpulse()};
}

void HingeJoint::ScaleImpulses(float ratio) {
  point_.ScaleImpulse(ratio);
  rotation_.ScaleImpulse(ratio);
  free_.ScaleImpulses(ratio);
}

}  // namespace strata
