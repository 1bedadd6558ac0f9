#include "physics/constraints/FixedJoint.h"

namespace strata {

Result<std::unique_ptr<FixedJoint>> FixedJoint::Create(const FixedJointSettings& settings, const BodyFrame& a,
                                                       const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor, "anchor"); !valid) return valid.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, Vec3::UnitX(), Vec3::UnitY());
  return std::unique_ptr<FixedJoint>(new FixedJoint(settings, frames));
}

FixedJoint::FixedJoint(const FixedJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kFixed, settings, frames) {}

std::string FixedJoint::Describe() const {
  return "fixed joint";
}

void FixedJoint::SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  if (!NeedsSetUp(pass)) return;
  const WorldArms arms = Arms(bodies);
  point_.Prepare(arms.r_a, arms.r_b);
  separation_ = arms.separation;
  rotation_.Prepare();
  rotation_error_ = RotationConstraintPart::Error(bodies, RestRotation());
}

void FixedJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  point_.WarmStart(bodies);
  rotation_.WarmStart(bodies);
}

void FixedJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) {
  if (!rigid_rows) return;  // every row of a weld is rigid
  SetUp(bodies, pass);
  const RowTarget target = EqualityTarget(1.0f, pass);
  rotation_.Solve(bodies, target.bias * rotation_error_, target);
  point_.Solve(bodies, target.bias * separation_, target);
}

int FixedJoint::RigidRowCount() const {
  return 6;
}

void FixedJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  rotation_.Prepare();
  rotation_.Rows(RotationConstraintPart::Error(bodies, RestRotation()), rows);
  const WorldArms arms = Arms(bodies);
  point_.Prepare(arms.r_a, arms.r_b);
  point_.Rows(arms.separation, rows + 3);
}

Constraint::Impulses FixedJoint::AccumulatedImpulses() const {
  return {point_.impulse(), rotation_.impulse()};
}

void FixedJoint::ScaleImpulses(float ratio) {
  point_.ScaleImpulse(ratio);
  rotation_.ScaleImpulse(ratio);
}

}  // namespace strata
