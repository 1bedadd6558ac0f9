// CollideShapes: the narrow-phase entry points and the collide functions behind them. Convex pairs run GJK
// on the shape cores (EPA on the exact shapes when the cores overlap), with closed forms and separating-axis
// tests where they are faster; convex vs triangle mesh collides with each nearby triangle and ignores
// internal edges. Which function serves which pair is CollisionDispatch's table. Pure functions; any thread.
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
  std::vector<ContactManifold>
      manifolds;  ///< for callers that collide on their way to something else (sweeps)
  /// Left by a convex pair's test that found the shapes apart beyond the reach: a direction (not unit) from A
  /// towards B that they are apart along; zero when the last test left none. The narrow phase keeps it in
  /// the body-pair cache to pass the pair over next step while it still separates them (GapAlong).
  Vec3 separating_axis = Vec3::Zero();
};

/// How far apart two convex shapes at their poses lie along the unit world `axis` (from A towards B): the
/// least extent of B along it minus the greatest of A, negative where their shadows on it overlap. Never
/// more than their distance: a gap beyond the reach along any axis rules out every contact.
float GapAlong(const ConvexShape& a, const Vec3& position_a, const Mat3& rotation_a, const ConvexShape& b,
               const Vec3& position_b, const Mat3& rotation_b, const Vec3& axis);

/// Contact between two convex shapes, by the form CollisionDispatch holds for the pair. Returns true and
/// fills `manifold` (normal and points; body ids are left as they were) when the shapes are closer than
/// `max_separation` (speculative contacts).
bool CollideConvexConvex(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                         float max_separation, ContactManifold& manifold, CollisionScratch& scratch);
bool CollideConvexConvex(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                         float max_separation, ContactManifold& manifold);

/// Contacts between a convex shape (A) and a triangle mesh (B): one manifold per distinct normal, keyed
/// by the first triangle that produced it. Appends to `out`; each new manifold starts as `prototype`. A
/// triangle whose plane the convex cannot reach along `reach`'s travel is passed over.
void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, const ContactReach& reach, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& scratch);
void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, float max_separation, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& scratch);
void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, float max_separation, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out);

/// Contacts between any two shapes, through CollisionDispatch::Default() (either order; two triangle shapes
/// give nothing): those within `reach` (the step's), or within `max_separation` whatever the normal (a
/// query's). The forms without scratch use buffers of their own.
void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   const ContactReach& reach, const ContactManifold& prototype,
                   std::vector<ContactManifold>& out, CollisionScratch& scratch);
void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   float max_separation, const ContactManifold& prototype, std::vector<ContactManifold>& out,
                   CollisionScratch& scratch);
void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   float max_separation, const ContactManifold& prototype, std::vector<ContactManifold>& out);

// The collide functions CollisionDispatch::Default() registers (the CollideFunction form: each appends what
// it finds to `out`, every manifold starting as `prototype`). The shapes must be of the named types.

/// Any two convex shapes: GJK on the cores (EPA on the exact shapes when the cores overlap), the closed form
/// for two sphere or capsule cores.
void CollideConvexByGjk(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                        const ContactReach& reach, const ContactManifold& prototype,
                        std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// Two spheres in closed form.
void CollideSpherePair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                       const ContactReach& reach, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// A sphere (A) and a box (B) in closed form.
void CollideSphereWithBox(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                          const ContactReach& reach, const ContactManifold& prototype,
                          std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// Two boxes by the separating-axis test (CollideBoxes).
void CollideBoxPair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                    const ContactReach& reach, const ContactManifold& prototype,
                    std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// Two polyhedra (boxes, hulls) by the separating-axis test; GJK for a hull too large to take part.
void CollidePolyhedronPair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                           const ContactReach& reach, const ContactManifold& prototype,
                           std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// A convex shape (A) and a height field (B): as a mesh of the same triangles.
void CollideConvexWithHeightField(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                                  const ContactReach& reach, const ContactManifold& prototype,
                                  std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// A convex shape (A) and a triangle mesh (B): CollideConvexMesh.
void CollideConvexWithMesh(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                           const ContactReach& reach, const ContactManifold& prototype,
                           std::vector<ContactManifold>& out, CollisionScratch& scratch);

}  // namespace strata
