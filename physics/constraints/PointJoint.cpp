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

void PointJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext&) {
  const WorldFrames frames = Frames(bodies);
  point_.Prepare(bodies, frames.r_a, frames.r_b);
  point_.WarmStart(bodies);
}

void PointJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) {
  if (!rigid_rows) return;
  const WorldFrames frames = Frames(bodies);
  point_.Prepare(bodies, frames.r_a, frames.r_b);
  const RowTarget target = EqualityTarget(1.0f, pass);
  point_.Solve(bodies, target.bias * frames.separation, target);
}

int PointJoint::RigidRowCount() const {
  return 3;
}

void PointJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldFrames frames = Frames(bodies);
  point_.Prepare(bodies, frames.r_a, frames.r_b);
  point_.Rows(frames.separation, rows);
}

Constraint::Impulses PointJoint::AccumulatedImpulses() const {
  return {point_.impulse(), Vec3::Zero()};
}

void PointJoint::ScaleImpulses(float ratio) {
  point_.ScaleImpulse(ratio);
}

}  // namespace strata
