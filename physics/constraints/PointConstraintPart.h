// PointConstraintPart: three linear rows that hold an anchor on A on an anchor on B (ball joints, and the
// point of hinges, cones and fixed joints), solved together with their 3x3 effective mass. Set up from the
// arms at the poses a pass sees; keeps its impulse accumulated over the step's passes. Owned by one
// constraint, used by the job solving it.
#pragma once

#include "physics/constraints/ConstraintBodies.h"

namespace strata {

/// Anchor on A at arm `r_a` == anchor on B at arm `r_b`.
class PointConstraintPart {
 public:
  /// Sets the arms up. The 3x3 effective mass waits for the first Solve: the rows of a joint that
  /// ExactJointSolver solves never need it.
  void Prepare(const Vec3& r_a, const Vec3& r_b) {
    r_a_ = r_a;
    r_b_ = r_b;
    effective_mass_ready_ = false;
  }
  Vec3 VelocityError(const ConstraintBodies& bodies) const {
    return PointVelocity(*bodies.b, r_b_) - PointVelocity(*bodies.a, r_a_);
  }
  void Apply(ConstraintBodies& bodies, const Vec3& impulse) const {
    ApplyImpulseAt(*bodies.a, -impulse, r_a_);
    ApplyImpulseAt(*bodies.b, impulse, r_b_);
  }
  void WarmStart(ConstraintBodies& bodies) const { Apply(bodies, impulse_); }
  /// Solves the three rows with `bias` added to their velocity error (the bias rate times the gap, B's
  /// anchor minus A's) and the mass and impulse scales of `target` (its own bias is not used).
  void Solve(ConstraintBodies& bodies, const Vec3& bias, const RowTarget& target) {
    if (!effective_mass_ready_) SetEffectiveMass(bodies);
    const Vec3 change = -target.mass_scale * (effective_mass_ * (VelocityError(bodies) + bias)) -
                        target.impulse_scale * impulse_;
    impulse_ += change;
    Apply(bodies, change);
  }
  /// Its three rows (world axes) for ExactJointSolver, with the gap `separation` (B's anchor minus A's).
  void Rows(const Vec3& separation, JointRow* rows) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = Vec3::Unit(k);
      rows[k] = {axis, r_a_.cross(axis), r_b_.cross(axis), separation[k], &impulse_[k]};
    }
  }
  const Vec3& impulse() const { return impulse_; }
  void ScaleImpulse(float ratio) { impulse_ *= ratio; }
  void ResetImpulse() { impulse_.setZero(); }

  static Mat3 Skew(const Vec3& v) {
    Mat3 m;
    m << 0.0f, -v.z(), v.y(), v.z(), 0.0f, -v.x(), -v.y(), v.x(), 0.0f;
    return m;
  }

 private:
  void SetEffectiveMass(const ConstraintBodies& bodies) {
    // K = (mA + mB) I - [rA]x IA [rA]x - [rB]x IB [rB]x.
    const Mat3 skew_a = Skew(r_a_), skew_b = Skew(r_b_);
    const Mat3 k = (bodies.a->inverse_mass + bodies.b->inverse_mass) * Mat3::Identity() -
                   skew_a * InverseInertiaOf(*bodies.a) * skew_a -
                   skew_b * InverseInertiaOf(*bodies.b) * skew_b;
    bool invertible = false;
    float determinant = 0.0f;
    k.computeInverseAndDetWithCheck(effective_mass_, determinant, invertible, 0.0f);
    if (!invertible || !(std::abs(determinant) > 0.0f)) effective_mass_.setZero();
    effective_mass_ready_ = true;
  }

  Vec3 r_a_ = Vec3::Zero();
  Vec3 r_b_ = Vec3::Zero();
  Mat3 effective_mass_ = Mat3::Zero();
  Vec3 impulse_ = Vec3::Zero();
  bool effective_mass_ready_ = false;
};

}  // namespace strata
