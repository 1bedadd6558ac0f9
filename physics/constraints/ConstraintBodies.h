// ConstraintBodies: the two bodies of a constraint as one solver pass sees them: their velocities (the
// solver bodies for a side that moves, a private copy for one that does not, so a pass never writes a
// shared slot it must not), their poses now, and the row softness of the pass. Built on the stack by the
// job that solves the constraint; nothing in it is shared.
#pragma once

#include <algorithm>

#include "physics/body/SolverBody.h"
#include "physics/constraints/ContactConstraint.h"

namespace strata {

/// The two sides of a constraint during one pass.
struct ConstraintBodies {
  SolverBody* a = nullptr;
  SolverBody* b = nullptr;
  Vec3 center_a = Vec3::Zero();  ///< centre of mass now, world
  Vec3 center_b = Vec3::Zero();
  Quat rotation_a = Quat::Identity();
  Quat rotation_b = Quat::Identity();
};

/// What a pass asks of the constraints it solves.
struct ConstraintPassContext {
  float h = 0.0f;          ///< substep (s)
  float inverse_h = 0.0f;  ///< 1 / h
  /// Rigid rows are soft springs while they push drift out (Box2D v3's joint softness); relax passes
  /// remove velocity error only.
  SoftSpring rigid_spring;
  bool use_bias = true;
  /// SolverPass::pose_version: a joint whose rows were set up at the same version this step keeps them.
  /// -1 (unknown) sets them up every pass.
  int pose_version = -1;
};

inline Mat3 InverseInertiaOf(const SolverBody& body) {
  Mat3 inverse;
  for (int column = 0; column < 3; ++column) inverse.col(column) = body.inverse_inertia[column].head<3>();
  return inverse;
}
inline Vec3 InverseInertiaTimes(const SolverBody& body, const Vec3& v) {
  return ToVec3(body.InverseInertiaTimes(ToVec4(v)));
}
/// Velocity of the point at arm `r` from the body's centre of mass.
inline Vec3 PointVelocity(const SolverBody& body, const Vec3& r) {
  return ToVec3(body.linear_velocity) + ToVec3(body.angular_velocity).cross(r);
}
/// Applies `impulse` at arm `r`.
inline void ApplyImpulseAt(SolverBody& body, const Vec3& impulse, const Vec3& r) {
  body.linear_velocity += ToVec4(body.inverse_mass * impulse);
  body.angular_velocity += body.InverseInertiaTimes(ToVec4(r.cross(impulse)));
}
inline void ApplyAngularImpulse(SolverBody& body, const Vec3& impulse) {
  body.angular_velocity += body.InverseInertiaTimes(ToVec4(impulse));
}

/// Moves a solver body by `move` and turns it by rotation vector `turn` (a position step): its pose and its
/// motion since the step began, which the write-back applies; its velocity is left as the passes made it.
inline void MoveSolverBody(SolverBody& body, SolverPose& pose, const Vec3& move, const Vec3& turn) {
  pose.center_of_mass += ToVec4(move);
  body.delta_position += ToVec4(move);
  TurnBy(pose.rotation, ToVec4(turn));
  body.delta_rotation += ToVec4(turn);
}

/// One row that always holds (a point, an axis, a rotation), as ExactJointSolver takes it: its rate is
/// linear . (v_B - v_A) + angular_b . w_B - angular_a . w_A, and an impulse moves B along it, A against.
struct JointRow {
  Vec3 linear = Vec3::Zero();
  Vec3 angular_a = Vec3::Zero();
  Vec3 angular_b = Vec3::Zero();
  float error = 0.0f;        ///< position error along the row now (m or rad)
  float* impulse = nullptr;  ///< the part's accumulated impulse for the row
};

/// How one row solves in a pass: the velocity it aims for and its softness.
struct RowTarget {
  float bias = 0.0f;  ///< added to the row's velocity error (1/s times the position error)
  float mass_scale = 1.0f;
  float impulse_scale = 0.0f;
};

/// An equality row with position error `error`: soft while pushing drift out, rigid in relax passes.
inline RowTarget EqualityTarget(float error, const ConstraintPassContext& pass) {
  if (!pass.use_bias) return {};
  const SoftSpring& spring = pass.rigid_spring;
  const float denominator = 1.0f + spring.stiffness;
  return {spring.bias_rate * error, spring.stiffness / denominator, 1.0f / denominator};
}
/// A limit row whose `error` >= 0 is allowed: a gap closes within the substep and no further (as a
/// speculative contact), a violation is pushed out like drift.
inline RowTarget LimitTarget(float error, const ConstraintPassContext& pass) {
  if (error > 0.0f) return {error * pass.inverse_h, 1.0f, 0.0f};
  return EqualityTarget(error, pass);
}
/// A spring row of its own stiffness (distance springs): soft in every pass.
inline RowTarget SpringTarget(float error, const SoftSpring& spring) {
  const float denominator = 1.0f + spring.stiffness;
  return {spring.bias_rate * error, spring.stiffness / denominator, 1.0f / denominator};
}

/// One row a joint solves along a direction it shares with others (a hinge's drive and both limits act on
/// its angle), as ExactJointSolver takes it to solve against an island's rigid rows.
struct FreeRowPass {
  int direction = 0;  ///< which of the joint's directions (Constraint::FreeRows)
  float sign = 1.0f;  ///< -1: the row acts against the direction (an upper limit)
  RowTarget target;
  float low = 0.0f;  ///< bounds of the accumulated impulse
  float high = 0.0f;
  float* impulse = nullptr;  ///< the part's accumulated impulse
};

/// The impulse change of a row: Box2D's soft update, with the accumulated impulse kept in [low, high].
inline float RowImpulse(float velocity_error, const RowTarget& target, float effective_mass,
                        float& accumulated, float low, float high) {
  const float change = -effective_mass * target.mass_scale * (velocity_error + target.bias) -
                       target.impulse_scale * accumulated;
  const float previous = accumulated;
  accumulated = std::clamp(previous + change, low, high);
  return accumulated - previous;
}

}  // namespace strata
