#include "physics/constraints/PointJoint.h"

namespace strata {

Result<std::unique_ptr<PointJoint>> PointJoint::Create(const PointJointSettings& settings, const BodyFrame& a,
                                                       const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor, "anchor"); !valid) return valid.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, Vec3::UnitX(), Vec3::UnitY());
  return std::unique_ptr<PointJoint>(new PointJoint(settings, frames));
}

PointJoint::PointJoint(const PointJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kPoint, settings, frames) {}

std::string PointJoint::Describe() const {
  return "point joint";
}

void PointJoint::SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  if (!NeedsSetUp(pass)) return;
  const WorldArms arms = Arms(bodies);
  point_.Prepare(arms.r_a, arms.r_b);
  separation_ = arms.separation;
}

void PointJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  point_.WarmStart(bodies);
}

void PointJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) {
  if (!rigid_rows) return;
  SetUp(bodies, pass);
  const RowTarget target = EqualityTarget(1.0f, pass);
  point_.Solve(bodies, target.bias * separation_, target);
}

int PointJoint::RigidRowCount() const {
  return 3;
}

void PointJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldArms arms = Arms(bodies);
  point_.Prepare(arms.r_a, arms.r_b);
  point_.Rows(arms.separation, rows);
}

Constraint::Impulses PointJoint::AccumulatedImpulses() const {
  return {point_.impulse(), Vec3::Zero()};
}

void PointJoint::ScaleImpulses(float ratio) {
  point_.ScaleImpulse(ratio);
}

}  // namespace strata
