// GyroscopicTorque: how a spinning body's angular velocity turns in free flight (Euler's equations: a body
// spinning about a non-principal axis precesses; one spinning about its intermediate axis flips). Pure
// functions; call from any thread.
#pragma once

#include "physics/math/Math.h"

namespace strata {

/// Whether `inertia` (any frame) differs enough from a multiple of the identity for spin to precess; a
/// sphere or a cube never does, so the step leaves it out.
bool HasGyroscopicTorque(const Mat3& inertia);

/// The angular velocity (world) of a body with local `inertia` and `rotation` after `dt` seconds without
/// torque: Euler's equations I dw/dt + w x I w = 0 in the body frame, by the implicit midpoint rule (Newton
/// to convergence; fast spin in pieces of half a radian). The rule keeps both the kinetic energy and |L| of
/// the exact motion and stays stable at any spin, where an explicit step gains energy.
Vec3 SpinWithoutTorque(const Mat3& inertia, const Quat& rotation, const Vec3& angular_velocity, float dt);

/// How many midpoint pieces SpinWithoutTorque takes for a spin of `spin_speed` rad/s over `dt`: one per half
/// radian, at most kMaxSpinPieces, so a spin no body reaches (from a solver that blew up, or not finite)
/// costs bounded work, not billions of pieces.
inline constexpr int kMaxSpinPieces = 64;  // 32 radians a step: 1,920 rad/s at 60 Hz
int SpinPieces(float spin_speed, float dt);

}  // namespace strata
