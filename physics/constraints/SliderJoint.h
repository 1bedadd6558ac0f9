// SliderJoint: a prismatic joint: B keeps its rotation relative to A and moves relative to it only along
// the slider axis, within optional limits, against optional friction, driven by an optional motor.
// Threading as Constraint (change the motor between steps).
#pragma once

#include <memory>

#include "physics/constraints/AxisConstraintPart.h"
#include "physics/constraints/Constraint.h"
#include "physics/constraints/FreeAxis.h"
#include "physics/constraints/RotationConstraintPart.h"

namespace strata {

struct SliderJointSettings : JointSettingsBase {
  Vec3 anchor = Vec3::Zero();       ///< world; position 0 along the axis
  Vec3 axis = Vec3::UnitX();        ///< world
  bool limits = false;              ///< keep the position along the axis within [min_position, max_position]
  float min_position = 0.0f;        ///< m, <= 0
  float max_position = 0.0f;        ///< m, >= 0
  float max_friction_force = 0.0f;  ///< N against sliding (while the motor is off)
  JointMotor motor;                 ///< target speed in m/s, max_torque read as a force in N
};

class SliderJoint final : public Constraint {
 public:
  static Result<std::unique_ptr<SliderJoint>> Create(const SliderJointSettings& settings, const BodyFrame& a,
                                                     const BodyFrame& b);

  std::string Describe() const override;
  void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;
  void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) override;
  int RigidRowCount() const override;
  void RigidRows(const ConstraintBodies& bodies, JointRow* rows) override;
  int FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass, JointRow* rows) override;
  int FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) override;

  /// B's anchor along the axis from A's (m).
  float Position(const BodyFrame& a, const BodyFrame& b) const;
  const JointMotor& motor() const { return free_.motor(); }
  /// Fails (nothing changed) on a non-finite speed or a negative force.
  Status SetMotor(const JointMotor& motor) { return free_.SetMotor(motor); }

 private:
  SliderJoint(const SliderJointSettings& settings, const LocalFrames& frames);
  Impulses AccumulatedImpulses() const override;
  void ScaleImpulses(float ratio) override;
  // The rows and the position at the pass's poses (see NeedsSetUp).
  void SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass);

  RotationConstraintPart rotation_;
  AxisConstraintPart side_[2];         // along the frame's y and z: no sideways motion
  FreeAxis<AxisConstraintPart> free_;  // the position along the axis
  // At the set-up poses:
  Vec3 rotation_error_ = Vec3::Zero();  // RotationConstraintPart::Error
  float offset_[2] = {0.0f, 0.0f};      // m, B's anchor off the axis along the frame's y and z
  float position_ = 0.0f;               // m, along the axis
};

}  // namespace strata
