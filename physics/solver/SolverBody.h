// SolverBody: the hot per-body data the contact solver reads and writes, copied out of Body at the start
// of the solve and written back after it, so the solver loops touch one compact array.
#pragma once

#include "physics/math/Math.h"

namespace strata {

/// Velocity state plus inverse mass of one body in the solve (inverse mass 0 = static, kinematic or asleep).
struct SolverBody {
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  Vec3 center_of_mass = Vec3::Zero();  ///< world
  Quat rotation = Quat::Identity();
  Mat3 inverse_inertia = Mat3::Zero();  ///< world
  float inverse_mass = 0.0f;
  float gravity_factor = 0.0f;  ///< 0 unless gravity moves it (dynamic and awake)
};

}  // namespace strata
