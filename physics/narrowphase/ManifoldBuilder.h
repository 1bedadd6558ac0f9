// ManifoldBuilder: turns one contact (normal + deepest point pair) into up to four contact points by
// clipping the two supporting faces against each other. Pure functions; safe from any thread.
#pragma once

#include "physics/narrowphase/ContactManifold.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

/// World-space supporting faces of A (along the normal) and B (against it) plus the single contact that
/// GJK/EPA found. Writes points into `manifold` (normal already set); points farther apart than
/// `max_separation` are dropped. Falls back to the single contact when clipping leaves nothing.
void BuildManifold(const SupportingFace& face_a, const SupportingFace& face_b, const ContactPoint& deepest,
                   float max_separation, ContactManifold& manifold);

/// Keeps at most four of `points`: the deepest, then the ones spanning the largest area.
int ReduceContactPoints(ContactPoint* points, int count, const Vec3& normal);

}  // namespace strata
