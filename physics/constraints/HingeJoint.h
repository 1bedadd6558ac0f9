// HingeJoint: a door hinge: the anchors meet and B turns relative to A only about the hinge axis, within
// optional angle limits, against optional friction, driven by an optional motor towards a target speed
// with at most a given torque. Threading as Constraint (change the motor between steps).
#pragma once

#include <memory>

#include "physics/constraints/AngleConstraintPart.h"
#include "physics/constraints/Constraint.h"
#include "physics/constraints/FreeAxis.h"
#include "physics/constraints/HingeRotationConstraintPart.h"
#include "physics/constraints/PointConstraintPart.h"

namespace strata {

struct HingeJointSettings : JointSettingsBase {
  Vec3 anchor = Vec3::Zero();        ///< world
  Vec3 axis = Vec3::UnitY();         ///< world, turning B about it counter-clockwise is a positive angle
  Vec3 normal = Vec3::Zero();        ///< angle 0 direction at right angles to the axis (zero: any)
  bool limits = false;               ///< keep the angle within [min_angle, max_angle]
  float min_angle = -kPi;            ///< rad, in [-pi, 0]
  float max_angle = kPi;             ///< rad, in [0, pi]
  float max_friction_torque = 0.0f;  ///< N m against turning (while the motor is off)
  JointMotor motor;
};

class HingeJoint final : public Constraint {
 public:
  static Result<std::unique_ptr<HingeJoint>> Create(const HingeJointSettings& settings, const BodyFrame& a,
                                                    const BodyFrame& b);

  std::string Describe() const override;
  void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;
  void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) override;
  int RigidRowCount() const override;
  void RigidRows(const ConstraintBodies& bodies, JointRow* rows) override;
  int FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass, JointRow* rows) override;
  int FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) override;

  /// B's angle about the axis relative to A (rad, (-pi, pi]), from the two bodies' poses.
  float Angle(const Quat& rotation_a, const Quat& rotation_b) const;
  const JointMotor& motor() const { return free_.motor(); }
  /// Fails (nothing changed) on a non-finite speed or a negative torque.
  Status SetMotor(const JointMotor& motor) { return free_.SetMotor(motor); }

 private:
  HingeJoint(const HingeJointSettings& settings, const LocalFrames& frames);
  Impulses AccumulatedImpulses() const override;
  void ScaleImpulses(float ratio) override;
  // The rows and the angle at the pass's poses (see NeedsSetUp).
  void SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass);

  PointConstraintPart point_;
  HingeRotationConstraintPart rotation_;
  FreeAxis<AngleConstraintPart> free_;  // the angle about the axis
  // At the set-up poses:
  Vec3 separation_ = Vec3::Zero();  // B's anchor minus A's
  float angle_ = 0.0f;              // rad, about the axis (taken only with limits)
};

}  // namespace strata
