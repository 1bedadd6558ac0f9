// SwingTwistJoint: a shoulder or hip for ragdolls: the anchors meet, B's twist axis stays within a cone
// around A's (the swing), the turn about the twist axis stays within [min_twist, max_twist], and optional
// friction resists any relative spin. Threading as Constraint.
#pragma once

#include <memory>

#include "physics/constraints/AngleConstraintPart.h"
#include "physics/constraints/Constraint.h"
#include "physics/constraints/PointConstraintPart.h"
#include "physics/constraints/RotationConstraintPart.h"

namespace strata {

struct SwingTwistJointSettings : JointSettingsBase {
  Vec3 anchor = Vec3::Zero();          ///< world
  Vec3 twist_axis = Vec3::UnitX();     ///< world: the limb's length
  Vec3 normal = Vec3::Zero();          ///< twist 0 direction at right angles to the axis (zero: any)
  float cone_half_angle = 0.5f * kPi;  ///< rad in (0, pi]: how far the twist axes may swing apart
  float min_twist = -kPi;              ///< rad in [-pi, 0]
  float max_twist = kPi;               ///< rad in [0, pi]
  float max_friction_torque = 0.0f;    ///< N m against any relative spin
};

class SwingTwistJoint final : public Constraint {
 public:
  static Result<std::unique_ptr<SwingTwistJoint>> Create(const SwingTwistJointSettings& settings,
                                                         const BodyFrame& a, const BodyFrame& b);

  std::string Describe() const override;
  void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;
  void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) override;
  int RigidRowCount() const override;
  void RigidRows(const ConstraintBodies& bodies, JointRow* rows) override;
  int FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass, JointRow* rows) override;
  int FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) override;
  void SolveUnreducibleRows(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;

  /// The angle between the two twist axes (rad, [0, pi]).
  float SwingAngle(const Quat& rotation_a, const Quat& rotation_b) const;
  /// B's turn about the twist axis relative to A (rad, (-pi, pi]).
  float TwistAngle(const Quat& rotation_a, const Quat& rotation_b) const;

 private:
  SwingTwistJoint(const SwingTwistJointSettings& settings, const LocalFrames& frames);
  Impulses AccumulatedImpulses() const override;
  void ScaleImpulses(float ratio) override;
  // The rows and angles at the pass's poses (see NeedsSetUp).
  void SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass);
  // Whether the passes solve the swing row: it has a direction, and the cone is narrower than all round.
  bool SwingLimited() const;
  // The limit rows a pass solves (swing, then twist lower and upper) and their parts; returns how many.
  int LimitRows(const ConstraintPassContext& pass, FreeRowPass* rows, AngleConstraintPart** parts);

  float cone_half_angle_;
  float min_twist_;
  float max_twist_;
  float max_friction_torque_;
  PointConstraintPart point_;
  AngleConstraintPart swing_row_;
  AngleConstraintPart twist_lower_;
  AngleConstraintPart twist_upper_;
  RotationConstraintPart friction_;
  bool swing_axis_valid_ = false;
  // At the set-up poses:
  Vec3 separation_ = Vec3::Zero();  // B's anchor minus A's
  float swing_ = 0.0f;              // rad
  float twist_ = 0.0f;              // rad
};

}  // namespace strata
