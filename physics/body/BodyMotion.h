// BodyMotion: every change the step makes to a body's motion, in one place: at the start forces, gravity's
// first substep share, the gyroscopic step, damping and velocity limits; per substep the later shares and
// integration; at the end the velocity limits again, the write-back of the pose and the sleep timer.
// Functions of one body; the step calls them from its jobs, each body from one job at a time.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "physics/PhysicsSettings.h"
#include "physics/body/Body.h"
#include "physics/body/GyroscopicTorque.h"
#include "physics/body/SleepSpheres.h"
#include "physics/body/SolverBody.h"

namespace strata {

/// Bodies slowed to their velocity limits, counted per job.
struct MotionClamps {
  std::size_t linear = 0;
  std::size_t angular = 0;
};

/// `velocity` slowed to `limit`, counted in `clamps` if it had to be. Velocities are clamped before they are
/// stored in their body, while they are still in registers (re-reading one just stored a lane at a time
/// stalls on the stores).
inline Vec3 ClampedVelocity(const Vec3& velocity, float limit, std::size_t& clamps) {
  // Squares first: nearly every body is under its limits, and then no square root is taken.
  if (velocity.squaredNorm() <= limit * limit) return velocity;
  ++clamps;
  // stableNorm: a velocity near float's limit squares to infinity, and 1/inf would stop the body dead.
  return velocity * (limit / velocity.stableNorm());
}

/// The start of a step of `dt` seconds in substeps of `substep_dt`: copies `body` into its solver slot and,
/// for a dynamic body, adds the first substep's share of gravity and forces (the velocity half of symplectic
/// Euler; the solver adds the others after each substep's integration), damps and limits its velocities and
/// clears its forces.
inline void BeginStepMotion(Body& body, const PhysicsSettings& settings, float dt, float substep_dt,
                            SolverBody& solver, SolverPose& pose, Mat3& rotation_matrix,
                            SolverVelocityStep& step, MotionClamps& clamps) {
  pose.center_of_mass = ToVec4(body.CenterOfMass());
  pose.rotation = body.rotation();
  rotation_matrix = body.rotation().toRotationMatrix();
  solver.delta_position.setZero();
  solver.delta_rotation.setZero();
  if (!body.IsDynamic()) {
    solver.inverse_mass = 0.0f;
    for (Vec4& column : solver.inverse_inertia) column.setZero();
    step = {};
    solver.linear_velocity = ToVec4(body.linear_velocity());
    solver.angular_velocity = ToVec4(body.angular_velocity());
    return;
  }
  // The gyroscopic step goes with each substep's share too (its error shrinks with the substep).
  Vec3 spin = body.angular_velocity();
  step.gyroscopic = settings.gyroscopic_torque && body.gyroscopic() && !spin.isZero(0.0f);
  if (step.gyroscopic) {
    step.inertia = body.inertia_local();  // the substeps read it only for these bodies
    spin = SpinWithoutTorque(body.inertia_local(), body.rotation(), spin, substep_dt);
  }
  InverseInertiaColumns(rotation_matrix, body.inverse_inertia_local(), solver.inverse_inertia);
  step.linear = ToVec4(substep_dt * (settings.gravity * body.gravity_factor() +
                                     body.inverse_mass() * body.accumulated_force()));
  step.angular = substep_dt * ColumnsTimes(solver.inverse_inertia, body.accumulated_torque());
  Vec3 linear = body.linear_velocity() + ToVec3(step.linear);
  Vec3 angular = spin + ToVec3(step.angular);
  body.ClearForcesInternal();
  linear *= std::max(0.0f, 1.0f - body.linear_damping() * dt);
  angular *= std::max(0.0f, 1.0f - body.angular_damping() * dt);
  const Vec3 limited_linear = ClampedVelocity(linear, body.max_linear_velocity(), clamps.linear);
  const Vec3 limited_angular = ClampedVelocity(angular, body.max_angular_velocity(), clamps.angular);
  body.SetLinearVelocityInternal(limited_linear);
  body.SetAngularVelocityInternal(limited_angular);
  solver.inverse_mass = body.inverse_mass();
  solver.linear_velocity = ToVec4(limited_linear);
  solver.angular_velocity = ToVec4(limited_angular);
}

/// A later substep's share of gravity and forces (and its gyroscopic step) on a dynamic body's solver slot.
inline void AddSubstepForces(SolverBody& body, const SolverVelocityStep& step, const Quat& rotation,
                             float substep_dt) {
  body.linear_velocity += step.linear;
  if (step.gyroscopic)
    body.angular_velocity =
        ToVec4(SpinWithoutTorque(step.inertia, rotation, ToVec3(body.angular_velocity), substep_dt));
  body.angular_velocity += step.angular;
}

/// Moves a dynamic body's solver pose by its velocities over one substep, and its deltas with it.
inline void IntegrateSubstep(SolverBody& body, SolverPose& pose, float substep_dt) {
  const Vec4 moved = body.linear_velocity * substep_dt;
  const Vec4 turn = body.angular_velocity * substep_dt;
  pose.center_of_mass += moved;
  TurnBy(pose.rotation, turn);
  body.delta_position += moved;
  body.delta_rotation += turn;
}

/// A kinematic body follows its velocity whatever it touches: moved at once to its end-of-step pose.
inline void MoveKinematic(SolverBody& body, SolverPose& pose, float dt) {
  body.delta_position = body.linear_velocity * dt;  // what the write-back adds to the position
  pose.center_of_mass += body.delta_position;
  TurnBy(pose.rotation, body.angular_velocity * dt);
}

/// Whether the body rested this step by settings.sleep_rule; `spheres` is its record for kPointMovement.
inline bool Rested(const Body& body, const PhysicsSettings& settings, SleepSpheres* spheres) {
  if (settings.sleep_rule == SleepRule::kPointMovement && spheres != nullptr)
    return spheres->StayedWithin(SleepSpheres::TestPoints(body),
                                 settings.sleep_point_velocity * settings.time_before_sleep);
  const float sleep_speed = settings.sleep_linear_velocity, sleep_spin = settings.sleep_angular_velocity;
  return body.linear_velocity().squaredNorm() < sleep_speed * sleep_speed &&
         body.angular_velocity().squaredNorm() < sleep_spin * sleep_spin;
}

/// The end of the step: the solved velocities (limited again: the substeps after the first added forces)
/// and pose written back, and the sleep timer advanced. Returns whether the body is ready to sleep.
/// `spheres`: the body's movement record, for SleepRule::kPointMovement.
inline bool EndStepMotion(Body& body, const SolverBody& solved, const SolverPose& pose,
                          const PhysicsSettings& settings, float dt, MotionClamps& clamps,
                          SleepSpheres* spheres = nullptr) {
  const Vec3 linear =
      ClampedVelocity(ToVec3(solved.linear_velocity), body.max_linear_velocity(), clamps.linear);
  const Vec3 angular =
      ClampedVelocity(ToVec3(solved.angular_velocity), body.max_angular_velocity(), clamps.angular);
  body.SetLinearVelocityInternal(linear);
  body.SetAngularVelocityInternal(angular);
  // The position takes the step's motion (small, so exact in a float) rather than the solver's pose, which
  // far from the origin rounds a slow body's motion away.
  const Vec3& offset = body.center_of_mass_local();
  const Vec3 turned_offset =
      body.centered() ? Vec3::Zero() : Vec3(body.rotation() * offset - pose.rotation * offset);
  body.SetRotationInternal(pose.rotation);
  body.AddToPositionInternal(ToVec3(solved.delta_position) + turned_offset);
  body.UpdateWorldBoundsInternal();
  body.SetSleepTimerInternal(Rested(body, settings, spheres) ? body.sleep_timer() + dt : 0.0f);
  return settings.allow_sleeping && body.allow_sleeping() && body.sleep_timer() >= settings.time_before_sleep;
}

/// Puts a body of an island that came to rest to sleep under the island's `key`.
inline void PutToSleep(Body& body, std::uint32_t key) {
  body.SetSleepingInternal(true);
  body.SetSleepIslandInternal(key);
  body.SetLinearVelocityInternal(Vec3::Zero());
  body.SetAngularVelocityInternal(Vec3::Zero());
}

/// Wakes a sleeping body (its island is woken with it by the step).
inline void WakeUp(Body& body) {
  body.SetSleepingInternal(false);
  body.SetSleepTimerInternal(0.0f);
}

}  // namespace strata
