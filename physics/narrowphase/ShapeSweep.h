// ShapeSweep: the shape cast of queries (WorldQuery::CastShape and the character): a convex shape swept along
// a straight line (no rotation) against one target, reporting where it first touches, or how deep it already
// overlaps the target at the start. Any shape pair the narrow phase collides: convex targets by conservative
// advancement on GJK distances (spheres and capsules as their core plus radius, so GJK meets them exactly),
// meshes and height fields triangle by triangle, one-sided as their contacts are. Pure functions; any thread.
#pragma once

#include <cstdint>
#include <optional>

#include "physics/narrowphase/CollideShapes.h"

namespace strata {

class HeightFieldShape;
class TriangleMeshShape;

/// How a shape cast runs.
struct ShapeCastSettings {
  /// A hit is reported when the gap has closed to this (m): how exact its fraction is.
  float tolerance = 1e-4f;
  /// Triangles (meshes, height fields) stop a cast that comes from behind them too. By default a cast passes
  /// through a triangle's back, as a body's contacts do.
  bool back_faces = false;
  /// A target the shape overlaps at the start is reported (fraction 0, with its penetration) only when the
  /// displacement goes deeper into it: a character resting in slight overlap can still move away.
  bool ignore_overlaps_moving_out = false;

  /// Fails for a tolerance that is not in (0, 1] m.
  Status Validate() const;
};

/// Where a cast shape meets one target.
struct SweepContact {
  float fraction = 1.0f;        ///< of the displacement travelled before touching; 0 for a start overlap
  Vec3 point = Vec3::Zero();    ///< on the target's surface, world
  Vec3 normal = Vec3::UnitY();  ///< unit, from the target towards the cast shape
  float penetration = 0.0f;     ///< how deep the shape overlapped the target at the start (m), else 0
  std::uint32_t sub_shape = 0;  ///< the target's triangle for meshes and height fields, else 0
};

/// Sweeps `shape` from `start` by `displacement` against `target` at `target_pose`, by the sweep
/// CollisionDispatch::Default() holds for the target's type. Nothing when it does not touch within the sweep.
std::optional<SweepContact> SweepConvexShape(const ConvexShape& shape, const Pose& start,
                                             const Vec3& displacement, const Shape& target,
                                             const Pose& target_pose, const ShapeCastSettings& settings,
                                             CollisionScratch& scratch);

// The sweeps CollisionDispatch::Default() registers (arguments as SweepConvexShape).

/// Onto any convex target.
std::optional<SweepContact> SweepOntoConvex(const ConvexShape& shape, const Pose& start,
                                            const Vec3& displacement, const Shape& target,
                                            const Pose& target_pose, const ShapeCastSettings& settings,
                                            CollisionScratch& scratch);
/// Onto a TriangleMeshShape or a HeightFieldShape (the type the table registers it for).
template <class TriangleShape>
std::optional<SweepContact> SweepOntoTriangleShape(const ConvexShape& shape, const Pose& start,
                                                   const Vec3& displacement, const Shape& target,
                                                   const Pose& target_pose, const ShapeCastSettings& settings,
                                                   CollisionScratch& scratch);
extern template std::optional<SweepContact> SweepOntoTriangleShape<TriangleMeshShape>(
    const ConvexShape&, const Pose&, const Vec3&, const Shape&, const Pose&, const ShapeCastSettings&,
    CollisionScratch&);
extern template std::optional<SweepContact> SweepOntoTriangleShape<HeightFieldShape>(
    const ConvexShape&, const Pose&, const Vec3&, const Shape&, const Pose&, const ShapeCastSettings&,
    CollisionScratch&);

}  // namespace strata
