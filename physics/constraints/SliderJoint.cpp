#include "physics/constraints/SliderJoint.h"

#include <cmath>
#include <limits>

namespace strata {

namespace {
constexpr float kUnbounded = std::numeric_limits<float>::infinity();
}  // namespace

Result<std::unique_ptr<SliderJoint>> SliderJoint::Create(const SliderJointSettings& settings,
                                                         const BodyFrame& a, const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor, "anchor"); !valid) return valid.error();
  const Result<Vec3> axis = UnitAxis(settings.axis, "axis");
  if (!axis) return axis.error();
  const Result<Vec3> normal = PerpendicularAxis(axis.value(), Vec3::Zero(), "normal");
  if (!normal) return normal.error();
  auto invalid = [](const char* message) { return MakeError(ErrorCode::kInvalidArgument, message); };
  if (!std::isfinite(settings.min_position) || !std::isfinite(settings.max_position) ||
      settings.min_position > 0.0f || settings.max_position < 0.0f)
    return invalid("slider limits must be min_position <= 0 <= max_position (m)");
  if (!std::isfinite(settings.max_friction_force) || settings.max_friction_force < 0.0f)
    return invalid("max_friction_force must be finite and >= 0");
  if (Status valid = ValidateMotor(settings.motor); !valid) return valid.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, axis.value(), normal.value());
  return std::unique_ptr<SliderJoint>(new SliderJoint(settings, frames));
}

SliderJoint::SliderJoint(const SliderJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kSlider, settings, frames),
      limits_(settings.limits),
      min_position_(settings.min_position),
      max_position_(settings.max_position),
      max_friction_force_(settings.max_friction_force),
      motor_(settings.motor) {}

std::string SliderJoint::Describe() const {
  std::string text = "slider joint";
  if (limits_)
    text += ", limits [" + std::to_string(min_position_) + ", " + std::to_string(max_position_) + "] m";
  if (motor_.enabled) text += ", motor " + std::to_string(motor_.target_speed) + " m/s";
  return text;
}

Status SliderJoint::SetMotor(const JointMotor& motor) {
  if (Status valid = ValidateMotor(motor); !valid) return valid;
  if (motor.enabled != motor_.enabled) drive_.ResetImpulse();
  motor_ = motor;
  return Status::Ok();
}

float SliderJoint::Position(const BodyFrame& a, const BodyFrame& b) const {
  const Vec3 anchor_a = a.center_of_mass + a.rotation * local().anchor_a;
  const Vec3 anchor_b = b.center_of_mass + b.rotation * local().anchor_b;
  return ((a.rotation * local().frame_a) * Vec3::UnitX()).dot(anchor_b - anchor_a);
}

void SliderJoint::PrepareRows(const ConstraintBodies& bodies, const WorldFrames& frames) {
  // The axis turns with A, so A's arm reaches to B's anchor: the rows then also hold A's turn.
  const Vec3 arm_a = frames.r_a + frames.separation;
  rotation_.Prepare(bodies);
  side_[0].Prepare(bodies, arm_a, frames.r_b, frames.axes_a.col(1));
  side_[1].Prepare(bodies, arm_a, frames.r_b, frames.axes_a.col(2));
  const Vec3 axis = frames.axes_a.col(0);
  if (limits_) {
    lower_.Prepare(bodies, arm_a, frames.r_b, axis);
    upper_.Prepare(bodies, arm_a, frames.r_b, -axis);
  }
  if (motor_.enabled || max_friction_force_ > 0.0f) drive_.Prepare(bodies, arm_a, frames.r_b, axis);
}

void SliderJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext&) {
  const WorldFrames frames = Frames(bodies);
  PrepareRows(bodies, frames);
  rotation_.WarmStart(bodies);
  side_[0].WarmStart(bodies);
  side_[1].WarmStart(bodies);
  if (limits_) {
    lower_.WarmStart(bodies);
    upper_.WarmStart(bodies);
  }
  if (motor_.enabled || max_friction_force_ > 0.0f) drive_.WarmStart(bodies);
}

void SliderJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass,
                                bool rigid_rows) {
  const WorldFrames frames = Frames(bodies);
  PrepareRows(bodies, frames);
  if (motor_.enabled) {
    const float most = motor_.max_torque * pass.h;
    drive_.Solve(bodies, RowTarget{-motor_.target_speed, 1.0f, 0.0f}, -most, most);
  } else if (max_friction_force_ > 0.0f) {
    const float most = max_friction_force_ * pass.h;
    drive_.Solve(bodies, RowTarget{}, -most, most);
  }
  if (limits_) {
    const float position = frames.axes_a.col(0).dot(frames.separation);
    lower_.Solve(bodies, LimitTarget(position - min_position_, pass), 0.0f, kUnbounded);
    upper_.Solve(bodies, LimitTarget(max_position_ - position, pass), 0.0f, kUnbounded);
  }
  if (!rigid_rows) return;
  const RowTarget target = EqualityTarget(1.0f, pass);
  rotation_.Solve(bodies, target.bias * RotationConstraintPart::Error(bodies, RestRotation()), target);
  for (int k = 0; k < 2; ++k) {
    const float offset = frames.axes_a.col(k + 1).dot(frames.separation);
    side_[k].Solve(bodies, EqualityTarget(offset, pass), -kUnbounded, kUnbounded);
  }
}

int SliderJoint::RigidRowCount() const {
  return 5;
}

void SliderJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldFrames frames = Frames(bodies);
  rotation_.Prepare(bodies);
  rotation_.Rows(RotationConstraintPart::Error(bodies, RestRotation()), rows);
  const Vec3 arm_a = frames.r_a + frames.separation;
  for (int k = 0; k < 2; ++k) {
    side_[k].Prepare(bodies, arm_a, frames.r_b, frames.axes_a.col(k + 1));
    rows[3 + k] = side_[k].Row(frames.axes_a.col(k + 1).dot(frames.separation));
  }
}

Constraint::Impulses SliderJoint::AccumulatedImpulses() const {
  return {side_[0].LinearImpulse() + side_[1].LinearImpulse() + lower_.LinearImpulse() +
              upper_.LinearImpulse() + drive_.LinearImpulse(),
          rotation_.impulse()};
}

void SliderJoint::ScaleImpulses(float ratio) {
  rotation_.ScaleImpulse(ratio);
  for (AxisConstraintPart& side : side_) side.ScaleImpulse(ratio);
  lower_.ScaleImpulse(ratio);
  upper_.ScaleImpulse(ratio);
  drive_.ScaleImpulse(ratio);
}

}  // namespace strata
