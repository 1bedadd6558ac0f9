// CollideShapes: the narrow-phase entry points. Convex pairs run GJK on the shape cores (EPA on the exact
// shapes when the cores overlap), with closed forms for sphere pairs; convex vs triangle mesh collides
// with each nearby triangle and ignores internal edges. Pure functions; safe from any thread.
#pragma once

#include <vector>

#include "physics/narrowphase/ContactManifold.h"
#include "physics/narrowphase/Epa.h"
#include "physics/shapes/ConvexShape.h"
#include "physics/shapes/TriangleMeshShape.h"

namespace strata {

/// Buffers the narrow phase grows into; one per job (or thread), reused so a warm caller allocates nothing.
struct CollisionScratch {
  std::vector<std::uint32_t> triangles;
  EpaScratch epa;
};

/// Contact between two convex shapes. Returns true and fills `manifold` (normal and points; body ids are
/// left as they were) when the shapes are closer than `max_separation` (speculative contacts).
bool CollideConvexConvex(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                         float max_separation, ContactManifold& manifold, CollisionScratch& scratch);
bool CollideConvexConvex(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                         float max_separation, ContactManifold& manifold);

/// Contacts between a convex shape (A) and a triangle mesh (B): one manifold per distinct normal, keyed
/// by the first triangle that produced it. Appends to `out`; each new manifold starts as `prototype`.
void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, float max_separation, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& scratch);
void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, float max_separation, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out);

/// Dispatches on shape types (mesh vs mesh never collides; a mesh as A is swapped to B by the caller). The
/// forms without scratch use buffers of their own.
void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   float max_separation, const ContactManifold& prototype, std::vector<ContactManifold>& out,
                   CollisionScratch& scratch);
void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   float max_separation, const ContactManifold& prototype, std::vector<ContactManifold>& out);

}  // namespace strata
