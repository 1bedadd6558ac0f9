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
  if (!std::isfinite(settings.min_position) || !std::isfinite(settings.max_position) ||
      settings.min_position > 0.0f || settings.max_position < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument,
                     "slider limits must be min_position <= 0 <= max_position (m)");
  if (Status valid = ValidateDrive(settings.max_friction_force, "max_friction_force", settings.motor); !valid)
    return valid.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, axis.value(), normal.value());
  return std::unique_ptr<SliderJoint>(new SliderJoint(settings, frames));
}

SliderJoint::SliderJoint(const SliderJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kSlider, settings, frames),
      free_(settings.limits, settings.min_position, settings.max_position, settings.max_friction_force,
            settings.motor) {}

std::string SliderJoint::Describe() const {
  return free_.Describe("slider joint", "m");
}

float SliderJoint::Position(const BodyFrame& a, const BodyFrame& b) const {
  const Vec3 anchor_a = a.center_of_mass + a.rotation * local().anchor_a;
  const Vec3 anchor_b = b.center_of_mass + b.rotation * local().anchor_b;
  return ((a.rotation * local().frame_a) * Vec3::UnitX()).dot(anchor_b - anchor_a);
}

void SliderJoint::SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  if (!NeedsSetUp(pass)) return;
  const WorldFrames frames = Frames(bodies);
  const Vec3 arm_a = frames.r_a + frames.separation;
  rotation_.Prepare();
  rotation_error_ = RotationConstraintPart::Error(bodies, RestRotation());
  for (int k = 0; k < 2; ++k) {
    side_[k].Prepare(bodies, arm_a, frames.r_b, frames.axes_a.col(k + 1));
    offset_[k] = frames.axes_a.col(k + 1).dot(frames.separation);
  }
  free_.Prepare(bodies, frames.axes_a.col(0), arm_a, frames.r_b);
  position_ = frames.axes_a.col(0).dot(frames.separation);
}

void SliderJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  rotation_.WarmStart(bodies);
  side_[0].WarmStart(bodies);
  side_[1].WarmStart(bodies);
  free_.WarmStart(bodies);
}

void SliderJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass,
                                bool rigid_rows) {
  SetUp(bodies, pass);
  free_.Solve(bodies, pass, position_);
  if (!rigid_rows) return;
  const RowTarget target = EqualityTarget(1.0f, pass);
  rotation_.Solve(bodies, target.bias * rotation_error_, target);
  for (int k = 0; k < 2; ++k)
    side_[k].Solve(bodies, EqualityTarget(offset_[k], pass), -kUnbounded, kUnbounded);
}

int SliderJoint::RigidRowCount() const {
  return 5;
}

void SliderJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldFrames frames = Frames(bodies);
  rotation_.Prepare();
  rotation_.Rows(RotationConstraintPart::Error(bodies, RestRotation()), rows);
  const Vec3 arm_a = frames.r_a + frames.separation;
  for (int k = 0; k < 2; ++k) {
    side_[k].Prepare(bodies, arm_a, frames.r_b, frames.axes_a.col(k + 1));
    rows[3 + k] = side_[k].Row(frames.axes_a.col(k + 1).dot(frames.separation));
  }
}

int SliderJoint::FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass, JointRow* rows) {
  SetUp(bodies, pass);
  return free_.FreeRows(rows);
}

int SliderJoint::FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) {
  return free_.Passes(pass, position_, 0, rows);
}

Constraint::Impulses SliderJoint::AccumulatedImpulses() const {
  return {side_[0].LinearImpulse() + side_[1].LinearImpulse() + free_.lower().LinearImpulse() +
              free_.upper().LinearImpulse() + free_.drive().LinearImpulse(),
          rotation_.impulse()};
}

void SliderJoint::ScaleImpulses(float ratio) {
  rotation_.ScaleImpulse(ratio);
  for (AxisConstraintPart& side : side_) side.ScaleImpulse(ratio);
  free_.ScaleImpulses(ratio);
}

}  // namespace strata
