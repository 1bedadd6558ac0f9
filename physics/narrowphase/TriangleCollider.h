// TriangleCollider: the contact tests for the shapes that meet mesh triangles most often, without building a
// polyhedron or running GJK per triangle. A box is tested in its own frame, where its face axes are the
// coordinate axes and its edge axes are component swaps of the triangle's edges; a capsule's core is a
// segment, whose closest points to a triangle have a closed form. Triangles are one-sided, as
// PolyhedronCollider treats them. Pure functions; any thread.
#pragma once

#include "physics/narrowphase/ContactManifold.h"
#include "physics/shapes/BoxShape.h"

namespace strata {

/// A mesh triangle: corners counter-clockwise seen from the front, unit front normal.
struct MeshTriangle {
  Vec3 corners[3];
  Vec3 normal;
};

/// Separating-axis test of `box` (rotation and centre in the triangle's frame) against a one-sided
/// triangle, with the same axes, preferences and face clipping as CollidePolyhedra. Returns true and fills
/// `manifold` (normal from the box into the triangle, points in the triangle's frame) when they are closer
/// than `max_separation`.
bool CollideBoxTriangle(const BoxShape& box, const Mat3& rotation, const Vec3& center,
                        const MeshTriangle& triangle, float max_separation, ContactManifold& manifold);

/// Contact of a capsule (core segment p0-p1, radius) with a triangle: the normal (capsule to triangle) and
/// the deepest point pair. Returns false when the core passes through the triangle (the caller falls back to
/// the general test); sets `within` to whether they are closer than `max_separation`.
bool CapsuleTriangleContact(const Vec3& p0, const Vec3& p1, float radius, const MeshTriangle& triangle,
                            float max_separation, bool& within, Vec3& normal, ContactPoint& deepest);

}  // namespace strata
