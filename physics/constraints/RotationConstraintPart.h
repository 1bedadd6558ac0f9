// RotationConstraintPart: three angular rows that keep B's rotation relative to A what it was when the
// constraint was made (fixed joints, sliders), solved together with their 3x3 effective mass. Keeps its
// impulse accumulated over the step's passes. Owned by one constraint, used by the job solving it.
#pragma once

#include "physics/constraints/ConstraintBodies.h"

namespace strata {

/// B's rotation == A's rotation times a fixed relative rotation.
class RotationConstraintPart {
 public:
  /// The effective mass waits for the first Solve: the rows of a joint that ExactJointSolver solves never
  /// need it.
  void Prepare() { effective_mass_ready_ = false; }
  /// How far B is turned from where A's rotation times `relative` (B in A's frame) puts it: a rotation
  /// vector (world), small while the joint holds.
  static Vec3 Error(const ConstraintBodies& bodies, const Quat& relative) {
    Quat error = bodies.rotation_b * (bodies.rotation_a * relative).conjugate();
    if (error.w() < 0.0f) error.coeffs() = -error.coeffs();
    return 2.0f * error.vec();
  }
  Vec3 VelocityError(const ConstraintBodies& bodies) const {
    return ToVec3(bodies.b->angular_velocity - bodies.a->angular_velocity);
  }
  void Apply(ConstraintBodies& bodies, const Vec3& impulse) const {
    ApplyAngularImpulse(*bodies.a, -impulse);
    ApplyAngularImpulse(*bodies.b, impulse);
  }
  void WarmStart(ConstraintBodies& bodies) const { Apply(bodies, impulse_); }
  /// As PointConstraintPart::Solve, with the bias from the turn (see Error).
  void Solve(ConstraintBodies& bodies, const Vec3& bias, const RowTarget& target) {
    if (!effective_mass_ready_) SetEffectiveMass(bodies);
    const Vec3 change = -target.mass_scale * (effective_mass_ * (VelocityError(bodies) + bias)) -
                        target.impulse_scale * impulse_;
    impulse_ += change;
    Apply(bodies, change);
  }
  /// Its three rows (world axes) for ExactJointSolver, with the turn `error` (see Error).
  void Rows(const Vec3& error, JointRow* rows) {
    for (int k = 0; k < 3; ++k)
      rows[k] = {Vec3::Zero(), Vec3::Unit(k), Vec3::Unit(k), error[k], &impulse_[k]};
  }
  /// Friction on the relative spin: stops it with an accumulated angular impulse of at most `most`.
  void SolveFriction(ConstraintBodies& bodies, float most) {
    if (!effective_mass_ready_) SetEffectiveMass(bodies);
    const Vec3 previous = impulse_;
    impulse_ -= effective_mass_ * VelocityError(bodies);
    const float size = impulse_.norm();
    if (size > most) impulse_ *= most / size;
    Apply(bodies, impulse_ - previous);
  }
  const Vec3& impulse() const { return impulse_; }
  void ScaleImpulse(float ratio) { impulse_ *= ratio; }
  void ResetImpulse() { impulse_.setZero(); }

 private:
  void SetEffectiveMass(const ConstraintBodies& bodies) {
    const Mat3 k = InverseInertiaOf(*bodies.a) + InverseInertiaOf(*bodies.b);
    bool invertible = false;
    float determinant = 0.0f;
    k.computeInverseAndDetWithCheck(effective_mass_, determinant, invertible, 0.0f);
    if (!invertible || !(std::abs(determinant) > 0.0f)) effective_mass_.setZero();
    effective_mass_ready_ = true;
  }

  Mat3 effective_mass_ = Mat3::Zero();
  Vec3 impulse_ = Vec3::Zero();
  bool effective_mass_ready_ = false;
};

}  // namespace strata
