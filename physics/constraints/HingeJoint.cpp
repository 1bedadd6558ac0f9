#include "physics/constraints/HingeJoint.h"

#include <cmath>
#include <limits>

namespace strata {

namespace {
constexpr float kUnbounded = std::numeric_limits<float>::infinity();

// The angle from `from` to `to` about `axis` (all unit, `from` and `to` at right angles to it).
float SignedAngle(const Vec3& from, const Vec3& to, const Vec3& axis) {
  return std::atan2(from.cross(to).dot(axis), from.dot(to));
}
}  // namespace

Status ValidateMotor(const JointMotor& motor) {
  if (!std::isfinite(motor.target_speed))
    return MakeError(ErrorCode::kInvalidArgument, "motor target_speed must be finite");
  if (!std::isfinite(motor.max_torque) || motor.max_torque < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "motor max_torque must be finite and >= 0");
  return Status::Ok();
}

Result<std::unique_ptr<HingeJoint>> HingeJoint::Create(const HingeJointSettings& settings, const BodyFrame& a,
                                                       const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor, "anchor"); !valid) return valid.error();
  const Result<Vec3> axis = UnitAxis(settings.axis, "axis");
  if (!axis) return axis.error();
  const Result<Vec3> normal = PerpendicularAxis(axis.value(), settings.normal, "normal");
  if (!normal) return normal.error();
  auto invalid = [](const char* message) { return MakeError(ErrorCode::kInvalidArgument, message); };
  if (!std::isfinite(settings.min_angle) || !std::isfinite(settings.max_angle) ||
      settings.min_angle < -kPi - 1e-6f || settings.min_angle > 0.0f || settings.max_angle < 0.0f ||
      settings.max_angle > kPi + 1e-6f)
    return invalid("hinge limits must be min_angle in [-pi, 0] and max_angle in [0, pi] (rad)");
  if (!std::isfinite(settings.max_friction_torque) || settings.max_friction_torque < 0.0f)
    return invalid("max_friction_torque must be finite and >= 0");
  if (Status valid = ValidateMotor(settings.motor); !valid) return valid.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, axis.value(), normal.value());
  return std::unique_ptr<HingeJoint>(new HingeJoint(settings, frames));
}

HingeJoint::HingeJoint(const HingeJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kHinge, settings, frames),
      limits_(settings.limits),
      min_angle_(settings.min_angle),
      max_angle_(settings.max_angle),
      max_friction_torque_(settings.max_friction_torque),
      motor_(settings.motor) {}

std::string HingeJoint::Describe() const {
  std::string text = "hinge joint";
  if (limits_)
    text += ", limits [" + std::to_string(min_angle_) + ", " + std::to_string(max_angle_) + "] rad";
  if (motor_.enabled) text += ", motor " + std::to_string(motor_.target_speed) + " rad/s";
  return text;
}

Status HingeJoint::SetMotor(const JointMotor& motor) {
  if (Status valid = ValidateMotor(motor); !valid) return valid;
  // The drive row switches between motor and friction: last step's impulse belongs to the other one.
  if (motor.enabled != motor_.enabled) drive_.ResetImpulse();
  motor_ = motor;
  return Status::Ok();
}

float HingeJoint::Angle(const Quat& rotation_a, const Quat& rotation_b) const {
  const Mat3 axes_a = (rotation_a * local().frame_a).toRotationMatrix();
  const Mat3 axes_b = (rotation_b * local().frame_b).toRotationMatrix();
  return SignedAngle(axes_a.col(1), axes_b.col(1), axes_a.col(0));
}

void HingeJoint::PrepareRows(const ConstraintBodies& bodies, const WorldFrames& frames) {
  const Vec3 axis = frames.axes_a.col(0);
  point_.Prepare(bodies, frames.r_a, frames.r_b);
  rotation_.Prepare(bodies, axis, frames.axes_b.col(1), frames.axes_b.col(2));
  if (limits_) {
    lower_.Prepare(bodies, axis);
    upper_.Prepare(bodies, -axis);
  }
  if (motor_.enabled || max_friction_torque_ > 0.0f) drive_.Prepare(bodies, axis);
}

void HingeJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext&) {
  const WorldFrames frames = Frames(bodies);
  PrepareRows(bodies, frames);
  point_.WarmStart(bodies);
  rotation_.WarmStart(bodies);
  if (limits_) {
    lower_.WarmStart(bodies);
    upper_.WarmStart(bodies);
  }
  if (motor_.enabled || max_friction_torque_ > 0.0f) drive_.WarmStart(bodies);
}

void HingeJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) {
  const WorldFrames frames = Frames(bodies);
  PrepareRows(bodies, frames);
  // The drive first and the limits after it, so a motor cannot push through a limit; the axis and the
  // point last, which matter most.
  if (motor_.enabled) {
    const float most = motor_.max_torque * pass.h;
    drive_.Solve(bodies, RowTarget{-motor_.target_speed, 1.0f, 0.0f}, -most, most);
  } else if (max_friction_torque_ > 0.0f) {
    const float most = max_friction_torque_ * pass.h;
    drive_.Solve(bodies, RowTarget{}, -most, most);
  }
  if (limits_) {
    const float angle = SignedAngle(frames.axes_a.col(1), frames.axes_b.col(1), frames.axes_a.col(0));
    lower_.Solve(bodies, LimitTarget(angle - min_angle_, pass), 0.0f, kUnbounded);
    upper_.Solve(bodies, LimitTarget(max_angle_ - angle, pass), 0.0f, kUnbounded);
  }
  if (!rigid_rows) return;
  rotation_.Solve(bodies, pass);
  const RowTarget target = EqualityTarget(1.0f, pass);
  point_.Solve(bodies, target.bias * frames.separation, target);
}

int HingeJoint::RigidRowCount() const {
  return 5;
}

void HingeJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldFrames frames = Frames(bodies);
  point_.Prepare(bodies, frames.r_a, frames.r_b);
  rotation_.Prepare(bodies, frames.axes_a.col(0), frames.axes_b.col(1), frames.axes_b.col(2));
  point_.Rows(frames.separation, rows);
  rotation_.Rows(rows + 3);
}

Constraint::Impulses HingeJoint::AccumulatedImpulses() const {
  return {point_.impulse(), rotation_.AngularImpulse() + lower_.AngularImpulse() + upper_.AngularImpulse() +
                                drive_.AngularImpulse()};
}

void HingeJoint::ScaleImpulses(float ratio) {
  point_.ScaleImpulse(ratio);
  rotation_.ScaleImpulse(ratio);
  lower_.ScaleImpulse(ratio);
  upper_.ScaleImpulse(ratio);
  drive_.ScaleImpulse(ratio);
}

}  // namespace strata
