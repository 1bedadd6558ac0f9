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

/// Raises every point of `manifold` deeper than `deepest` to its depth, both ends moved half the difference
/// along the normal. Where `deepest` is exact (rounded shapes, measured on their cores), a point clipped from
/// a face to its sharp corner lies past the rounding, deeper than the shapes overlap.
void KeepNoDeeperThan(const ContactPoint& deepest, ContactManifold& manifold);

/// A clipped incident point and where it meets the reference face along `normal` (A to B), as a contact
/// point with A's side first; appended to `points` when it is within `max_separation`.
void AppendFacePoint(const Vec3& incident, const Vec3& on_reference, bool reference_is_a, const Vec3& normal,
                     float max_separation, ContactPoint* points, int& count);
/// Reduces `points` to at most four (ReduceContactPoints) and makes them the manifold's.
void SetManifoldPoints(ContactPoint* points, int count, ContactManifold& manifold);

/// Keeps at most four of `points`: the deepest, then the ones spanning the largest area.
int ReduceContactPoints(ContactPoint* points, int count, const Vec3& normal);

}  // namespace strata
