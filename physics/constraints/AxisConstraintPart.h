// AxisConstraintPart: one linear row, the relative motion of two anchor points along an axis: distance
// joints, a slider's sideways rows, its limits and motor. Set up from the poses a pass sees (the arms turn
// with the bodies within a step); keeps its impulse accumulated over the step's passes.
// Owned by one constraint, used by the job solving it.
#pragma once

#include "physics/constraints/ConstraintBodies.h"

namespace strata {

/// A row along `axis` between a point on A (arm `r_a` from A's centre of mass) and one on B.
class AxisConstraintPart {
 public:
  /// `r_a` is the arm from A's centre of mass to the point on B where the axis turns with A (a slider's
  /// axis does), else to A's own anchor.
  void Prepare(const ConstraintBodies& bodies, const Vec3& r_a, const Vec3& r_b, const Vec3& axis) {
    axis_ = axis;
    arm_a_ = r_a.cross(axis);
    arm_b_ = r_b.cross(axis);
    turn_a_ = InverseInertiaTimes(*bodies.a, arm_a_);
    turn_b_ = InverseInertiaTimes(*bodies.b, arm_b_);
    const float k =
        bodies.a->inverse_mass + bodies.b->inverse_mass + arm_a_.dot(turn_a_) + arm_b_.dot(turn_b_);
    effective_mass_ = k > 0.0f ? 1.0f / k : 0.0f;
  }
  /// The row the other way (an upper limit beside a lower one): `other` prepared along the negated axis,
  /// the same numbers without the products.
  void PrepareOpposite(const AxisConstraintPart& other) {
    axis_ = -other.axis_;
    arm_a_ = -other.arm_a_;
    arm_b_ = -other.arm_b_;
    turn_a_ = -other.turn_a_;
    turn_b_ = -other.turn_b_;
    effective_mass_ = other.effective_mass_;
  }
  float VelocityError(const ConstraintBodies& bodies) const {
    return axis_.dot(ToVec3(bodies.b->linear_velocity - bodies.a->linear_velocity)) +
           arm_b_.dot(ToVec3(bodies.b->angular_velocity)) - arm_a_.dot(ToVec3(bodies.a->angular_velocity));
  }
  void Apply(ConstraintBodies& bodies, float impulse) const {
    bodies.a->linear_velocity -= ToVec4((bodies.a->inverse_mass * impulse) * axis_);
    bodies.a->angular_velocity -= ToVec4(impulse * turn_a_);
    bodies.b->linear_velocity += ToVec4((bodies.b->inverse_mass * impulse) * axis_);
    bodies.b->angular_velocity += ToVec4(impulse * turn_b_);
  }
  void WarmStart(ConstraintBodies& bodies) const { Apply(bodies, impulse_); }
  /// Solves the row towards `target` with its accumulated impulse in [low, high]; returns the change.
  float Solve(ConstraintBodies& bodies, const RowTarget& target, float low, float high) {
    const float change = RowImpulse(VelocityError(bodies), target, effective_mass_, impulse_, low, high);
    Apply(bodies, change);
    return change;
  }
  /// The row for ExactJointSolver, with position error `error`.
  JointRow Row(float error) { return {axis_, arm_a_, arm_b_, error, &impulse_}; }
  /// Its effective mass (kg), 0 when neither side can move along it.
  float effective_mass() const { return effective_mass_; }
  /// Accumulated impulse of the substep (N s), B's side.
  float impulse() const { return impulse_; }
  void ScaleImpulse(float ratio) { impulse_ *= ratio; }
  void ResetImpulse() { impulse_ = 0.0f; }
  /// The impulse on B as a vector (world), for forces.
  Vec3 LinearImpulse() const { return impulse_ * axis_; }

 private:
  Vec3 axis_ = Vec3::UnitX();
  Vec3 arm_a_ = Vec3::Zero();
  Vec3 arm_b_ = Vec3::Zero();
  Vec3 turn_a_ = Vec3::Zero();  // inverse inertia times arm
  Vec3 turn_b_ = Vec3::Zero();
  float effective_mass_ = 0.0f;
  float impulse_ = 0.0f;
};

}  // namespace strata
