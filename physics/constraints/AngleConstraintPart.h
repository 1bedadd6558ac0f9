// AngleConstraintPart: one angular row, the relative spin of two bodies about an axis: hinge limits,
// motors and friction, twist and swing limits. Set up from the axis at the poses a pass sees; keeps its
// impulse accumulated over the step's passes. Owned by one constraint, used by the job solving it.
#pragma once

#include "physics/constraints/ConstraintBodies.h"

namespace strata {

/// A row on the spin of B relative to A about a unit `axis` (world).
class AngleConstraintPart {
 public:
  void Prepare(const ConstraintBodies& bodies, const Vec3& axis) {
    axis_ = axis;
    turn_a_ = InverseInertiaTimes(*bodies.a, axis);
    turn_b_ = InverseInertiaTimes(*bodies.b, axis);
    const float k = axis.dot(turn_a_) + axis.dot(turn_b_);
    effective_mass_ = k > 0.0f ? 1.0f / k : 0.0f;
  }
  /// The row the other way (an upper limit beside a lower one): `other` prepared along the negated axis,
  /// the same numbers without the products.
  void PrepareOpposite(const AngleConstraintPart& other) {
    axis_ = -other.axis_;
    turn_a_ = -other.turn_a_;
    turn_b_ = -other.turn_b_;
    effective_mass_ = other.effective_mass_;
  }
  float VelocityError(const ConstraintBodies& bodies) const {
    return axis_.dot(ToVec3(bodies.b->angular_velocity - bodies.a->angular_velocity));
  }
  void Apply(ConstraintBodies& bodies, float impulse) const {
    bodies.a->angular_velocity -= ToVec4(impulse * turn_a_);
    bodies.b->angular_velocity += ToVec4(impulse * turn_b_);
  }
  void WarmStart(ConstraintBodies& bodies) const { Apply(bodies, impulse_); }
  /// Solves the row towards `target` with its accumulated impulse in [low, high]; returns the change.
  float Solve(ConstraintBodies& bodies, const RowTarget& target, float low, float high) {
    const float change = RowImpulse(VelocityError(bodies), target, effective_mass_, impulse_, low, high);
    Apply(bodies, change);
    return change;
  }
  JointRow Row(float error) { return {Vec3::Zero(), axis_, axis_, error, &impulse_}; }
  float effective_mass() const { return effective_mass_; }
  float impulse() const { return impulse_; }
  void ScaleImpulse(float ratio) { impulse_ *= ratio; }
  void ResetImpulse() { impulse_ = 0.0f; }
  /// The angular impulse on B (world, N m s), for torques.
  Vec3 AngularImpulse() const { return impulse_ * axis_; }

 private:
  Vec3 axis_ = Vec3::UnitX();
  Vec3 turn_a_ = Vec3::Zero();
  Vec3 turn_b_ = Vec3::Zero();
  float effective_mass_ = 0.0f;
  float impulse_ = 0.0f;
};

}  // namespace strata
