// BoxBoxCollider: contact between two boxes by the separating-axis test on their 15 axes, worked out from
// the boxes' axes and half extents instead of general polyhedra (stacks, crates and walls are box pairs;
// building two polyhedra and querying their supports was most of such a pair's narrow phase). Chooses axes
// and faces as CollidePolyhedra does for two boxes and builds the manifold the same way. Pure; any thread.
#pragma once

#include "physics/narrowphase/ContactManifold.h"
#include "physics/shapes/BoxShape.h"

namespace strata {

/// Contact between box `a` at `pose_a` and box `b` at `pose_b`. Returns true and fills `manifold` (normal
/// from A to B and up to four points) when they are closer than `max_separation`.
bool CollideBoxes(const BoxShape& a, const Pose& pose_a, const BoxShape& b, const Pose& pose_b,
                  float max_separation, ContactManifold& manifold);

}  // namespace strata
