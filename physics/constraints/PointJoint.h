// PointJoint: a ball joint: an anchor point on A and on B stay together, any rotation is free. Threading as
// Constraint.
#pragma once

#include <memory>

#include "physics/constraints/Constraint.h"
#include "physics/constraints/PointConstraintPart.h"

namespace strata {

struct PointJointSettings : JointSettingsBase {
  Vec3 anchor = Vec3::Zero();  ///< world
};

class PointJoint final : public Constraint {
 public:
  static Result<std::unique_ptr<PointJoint>> Create(const PointJointSettings& settings, const BodyFrame& a,
                                                    const BodyFrame& b);

  std::string Describe() const override;
  void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;
  void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) override;
  int RigidRowCount() const override;
  bool OnlyRigidRows() const override { return true; }
  void RigidRows(const ConstraintBodies& bodies, JointRow* rows) override;

 private:
  PointJoint(const PointJointSettings& settings, const LocalFrames& frames);
  Impulses AccumulatedImpulses() const override;
  void ScaleImpulses(float ratio) override;

  // The rows at the pass's poses (see NeedsSetUp).
  void SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass);

  PointConstraintPart point_;
  Vec3 separation_ = Vec3::Zero();  // B's anchor minus A's at the set-up poses
};

}  // namespace strata
