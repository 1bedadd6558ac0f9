// HingeRotationConstraintPart: two angular rows that keep B's hinge axis on A's, leaving the spin about
// it free (hinges). Rows: a_A . b_B = 0 and a_A . c_B = 0 for b_B, c_B perpendicular to B's axis; their
// rate is (w_B - w_A) . (b_B x a_A). Keeps its impulse accumulated over the step's passes. Owned by one
// constraint, used by the job solving it.
#pragma once

#include "physics/constraints/ConstraintBodies.h"

namespace strata {

/// Axis on A (`axis_a`, world) parallel to axis on B.
class HingeRotationConstraintPart {
 public:
  /// `perpendicular_b1`, `perpendicular_b2`: unit vectors at right angles to B's axis and each other.
  void Prepare(const ConstraintBodies& bodies, const Vec3& axis_a, const Vec3& perpendicular_b1,
               const Vec3& perpendicular_b2) {
    row_[0] = perpendicular_b1.cross(axis_a);
    row_[1] = perpendicular_b2.cross(axis_a);
    error_ = {axis_a.dot(perpendicular_b1), axis_a.dot(perpendicular_b2)};
    const Mat3 inverse_inertia = InverseInertiaOf(*bodies.a) + InverseInertiaOf(*bodies.b);
    Eigen::Matrix2f k;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) k(i, j) = row_[i].dot(inverse_inertia * row_[j]);
    bool invertible = false;
    float determinant = 0.0f;
    k.computeInverseAndDetWithCheck(effective_mass_, determinant, invertible, 0.0f);
    if (!invertible || !(std::abs(determinant) > 0.0f)) effective_mass_.setZero();
  }
  Eigen::Vector2f VelocityError(const ConstraintBodies& bodies) const {
    const Vec3 relative = ToVec3(bodies.b->angular_velocity - bodies.a->angular_velocity);
    return {row_[0].dot(relative), row_[1].dot(relative)};
  }
  void Apply(ConstraintBodies& bodies, const Eigen::Vector2f& impulse) const {
    const Vec3 angular = impulse.x() * row_[0] + impulse.y() * row_[1];
    ApplyAngularImpulse(*bodies.a, -angular);
    ApplyAngularImpulse(*bodies.b, angular);
  }
  void WarmStart(ConstraintBodies& bodies) const { Apply(bodies, impulse_); }
  /// Solves with the softness of `target`'s scales; the bias comes from the axes' misalignment.
  void Solve(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
    const RowTarget target = EqualityTarget(1.0f, pass);  // bias per unit of error
    const Eigen::Vector2f bias = target.bias * error_;
    const Eigen::Vector2f change = -target.mass_scale * (effective_mass_ * (VelocityError(bodies) + bias)) -
                                   target.impulse_scale * impulse_;
    impulse_ += change;
    Apply(bodies, change);
  }
  /// Its two rows for ExactJointSolver (after Prepare).
  void Rows(JointRow* rows) {
    for (int k = 0; k < 2; ++k) rows[k] = {Vec3::Zero(), row_[k], row_[k], error_[k], &impulse_[k]};
  }
  Vec3 AngularImpulse() const { return impulse_.x() * row_[0] + impulse_.y() * row_[1]; }
  void ScaleImpulse(float ratio) { impulse_ *= ratio; }
  void ResetImpulse() { impulse_.setZero(); }

 private:
  Vec3 row_[2] = {Vec3::UnitY(), Vec3::UnitZ()};
  Eigen::Vector2f error_ = Eigen::Vector2f::Zero();
  Eigen::Matrix2f effective_mass_ = Eigen::Matrix2f::Zero();
  Eigen::Vector2f impulse_ = Eigen::Vector2f::Zero();
};

}  // namespace strata
