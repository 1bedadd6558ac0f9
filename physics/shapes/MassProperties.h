// MassProperties: mass, inertia tensor and centre of mass of a shape or body. Value type.
#pragma once

#include "physics/math/Math.h"

namespace strata {

/// Mass (kg), inertia tensor about the centre of mass (kg m^2, shape axes) and the centre of mass
/// relative to the shape origin (m).
struct MassProperties {
  float mass = 0.0f;
  Mat3 inertia = Mat3::Zero();
  Vec3 center_of_mass = Vec3::Zero();

  /// The same distribution scaled to a different total mass.
  MassProperties WithMass(float new_mass) const {
    MassProperties scaled = *this;
    if (mass > 0.0f) scaled.inertia *= new_mass / mass;
    scaled.mass = new_mass;
    return scaled;
  }
};

}  // namespace strata
