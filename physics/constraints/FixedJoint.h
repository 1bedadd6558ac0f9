// FixedJoint: welds B to A (or to the world) as they are when it is added: the anchor points meet and the
// relative rotation stays. Threading as Constraint.
#pragma once

#include <memory>

#include "physics/constraints/Constraint.h"
#include "physics/constraints/PointConstraintPart.h"
#include "physics/constraints/RotationConstraintPart.h"

namespace strata {

struct FixedJointSettings : JointSettingsBase {
  Vec3 anchor = Vec3::Zero();  ///< world
};

class FixedJoint final : public Constraint {
 public:
  /// Fails on bad settings; `a` and `b` are where the bodies are now.
  static Result<std::unique_ptr<FixedJoint>> Create(const FixedJointSettings& settings, const BodyFrame& a,
                                                    const BodyFrame& b);

  std::string Describe() const override;
  void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;
  void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) override;
  int RigidRowCount() const override;
  bool OnlyRigidRows() const override { return true; }
  void RigidRows(const ConstraintBodies& bodies, JointRow* rows) override;

 private:
  FixedJoint(const FixedJointSettings& settings, const LocalFrames& frames);
  Impulses AccumulatedImpulses() const override;
  void ScaleImpulses(float ratio) override;

  // The rows at the pass's poses (see NeedsSetUp).
  void SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass);

  PointConstraintPart point_;
  RotationConstraintPart rotation_;
  // At the set-up poses:
  Vec3 separation_ = Vec3::Zero();      // B's anchor minus A's
  Vec3 rotation_error_ = Vec3::Zero();  // RotationConstraintPart::Error
};

}  // namespace strata
