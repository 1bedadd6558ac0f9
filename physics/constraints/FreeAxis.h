// FreeAxis: what a joint with one free degree of freedom (a hinge's angle, a slider's position) does along
// it: optional limits, friction while the motor is off, and an optional motor driving the speed along it.
// It holds the numbers and the three rows (AngleConstraintPart or AxisConstraintPart) and solves them in
// the order that keeps a motor from pushing through a limit. Threading as Constraint.
#pragma once

#include <limits>
#include <string>

#include "physics/constraints/ConstraintBodies.h"
#include "physics/core/Result.h"

namespace strata {

/// A motor that drives a joint's relative speed towards `target_speed` with at most `max_torque` (or
/// force, for a slider).
struct JointMotor {
  bool enabled = false;
  float target_speed = 0.0f;  ///< rad/s (m/s for a slider)
  float max_torque = 0.0f;    ///< N m (N for a slider), >= 0
};

/// Checks a motor's numbers.
Status ValidateMotor(const JointMotor& motor);
/// Checks a free axis's friction (`name` is its setting, for the message) and motor.
Status ValidateDrive(float max_friction, const char* name, const JointMotor& motor);

template <class Part>
class FreeAxis {
 public:
  FreeAxis(bool limits, float min, float max, float max_friction, const JointMotor& motor)
      : limits_(limits), min_(min), max_(max), max_friction_(max_friction), motor_(motor) {}

  const JointMotor& motor() const { return motor_; }
  bool limits() const { return limits_; }
  /// Fails (nothing changed) on a non-finite speed or a negative torque.
  Status SetMotor(const JointMotor& motor) {
    if (Status valid = ValidateMotor(motor); !valid) return valid;
    // The drive row switches between motor and friction: last step's impulse belongs to the other one.
    if (motor.enabled != motor_.enabled) drive_.ResetImpulse();
    motor_ = motor;
    return Status::Ok();
  }
  /// "<joint>, limits [min, max] <unit>, motor <speed> <unit>/s" for what is on.
  std::string Describe(const char* joint, const char* unit) const {
    std::string text = joint;
    if (limits_) text += ", limits [" + std::to_string(min_) + ", " + std::to_string(max_) + "] " + unit;
    if (motor_.enabled) text += ", motor " + std::to_string(motor_.target_speed) + " " + unit + "/s";
    return text;
  }

  /// The rows along `axis`; `lead` are the row part's arguments before the axis (a slider's arms).
  template <class... Lead>
  void Prepare(const ConstraintBodies& bodies, const Vec3& axis, const Lead&... lead) {
    if (limits_) {
      lower_.Prepare(bodies, lead..., axis);
      upper_.PrepareOpposite(lower_);
    }
    if (drives()) drive_.Prepare(bodies, lead..., axis);
  }
  void WarmStart(ConstraintBodies& bodies) {
    if (limits_) {
      lower_.WarmStart(bodies);
      upper_.WarmStart(bodies);
    }
    if (drives()) drive_.WarmStart(bodies);
  }
  /// The drive first and the limits after it, so a motor cannot push through a limit. `coordinate` is the
  /// angle or position now (read only when there are limits).
  void Solve(ConstraintBodies& bodies, const ConstraintPassContext& pass, float coordinate) {
    ForEachRow(pass, coordinate, [&](Part& part, float, const RowTarget& target, float low, float high) {
      part.Solve(bodies, target, low, high);
    });
  }
  /// After Prepare: the row the limits and the drive share (the upper limit's is the other way), in
  /// `rows[0]`; 0 rows when there are neither.
  int FreeRows(JointRow* rows) {
    if (!limits_ && !drives()) return 0;
    rows[0] = limits_ ? lower_.Row(0.0f) : drive_.Row(0.0f);
    return 1;
  }
  /// What Solve would solve, as rows along FreeRows' row (its direction `direction`); returns how many.
  int Passes(const ConstraintPassContext& pass, float coordinate, int direction, FreeRowPass* rows) {
    int count = 0;
    ForEachRow(pass, coordinate, [&](Part& part, float sign, const RowTarget& target, float low, float high) {
      rows[count++] = {direction, sign, target, low, high, part.Row(0.0f).impulse};
    });
    return count;
  }
  void ScaleImpulses(float ratio) {
    lower_.ScaleImpulse(ratio);
    upper_.ScaleImpulse(ratio);
    drive_.ScaleImpulse(ratio);
  }
  const Part& lower() const { return lower_; }
  const Part& upper() const { return upper_; }
  const Part& drive() const { return drive_; }

 private:
  bool drives() const { return motor_.enabled || max_friction_ > 0.0f; }
  // Calls visit(part, sign along the lower limit's row, target, low, high) for the rows a pass solves.
  template <class Visit>
  void ForEachRow(const ConstraintPassContext& pass, float coordinate, Visit&& visit) {
    constexpr float kUnbounded = std::numeric_limits<float>::infinity();
    if (motor_.enabled) {
      const float most = motor_.max_torque * pass.h;
      visit(drive_, 1.0f, RowTarget{-motor_.target_speed, 1.0f, 0.0f}, -most, most);
    } else if (max_friction_ > 0.0f) {
      const float most = max_friction_ * pass.h;
      visit(drive_, 1.0f, RowTarget{}, -most, most);
    }
    if (!limits_) return;
    visit(lower_, 1.0f, LimitTarget(coordinate - min_, pass), 0.0f, kUnbounded);
    visit(upper_, -1.0f, LimitTarget(max_ - coordinate, pass), 0.0f, kUnbounded);
  }

  bool limits_;
  float min_;
  float max_;
  float max_friction_;
  JointMotor motor_;
  Part lower_;
  Part upper_;
  Part drive_;  // the motor, or friction
};

}  // namespace strata
