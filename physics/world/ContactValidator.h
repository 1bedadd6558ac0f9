// ContactValidator: the callback a step asks whether to solve a contact of a body created with
// validate_contacts (a one-way platform lets bodies through from below), as Box2D v3's pre-solve callback and
// Jolt's OnContactValidate do. Threading: it is called from the step's narrow-phase jobs, several threads at
// once, while the step runs; the rules for what it may touch are on the type below.
#pragma once

#include <functional>

#include "physics/body/Body.h"

namespace strata {

/// One manifold (the contact of a pair of sub-shapes: a body and one mesh triangle, say) about to be solved.
struct ContactCandidate {
  const Body& body_a;  ///< the bodies as the step began: pose, velocities, user data
  const Body& body_b;
  Vec3 normal;       ///< unit, from A towards B
  float separation;  ///< of the deepest point, m (< 0: overlapping)
  int point_count;
  Vec3 points[4];  ///< world, midway between the two surfaces
};

/// Returns false to drop the contact for this step: it is not solved, gives no contact event and wakes
/// nothing. Asked again every step the contact is found.
/// May: read the two bodies it is given and its own data (behind its own synchronisation: several jobs call
/// it at once), and run WorldQuery queries (they only take read locks, which the step does not hold here).
/// Must not: change bodies, joints or settings, or step the world (those wait for the step to end, and the
/// step waits for this call: a deadlock), nor keep the body references past the call.
using ContactValidator = std::function<bool(const ContactCandidate&)>;

}  // namespace strata
