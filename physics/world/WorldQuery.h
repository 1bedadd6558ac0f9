// WorldQuery: ray casts, shape casts, box, shape and point overlaps and closest points against the bodies of
// a PhysicsSystem. Any number of threads may query at once, also while bodies change and the world steps.
// Each query walks the broad phase, then takes each candidate's read lock only long enough to copy its shape
// reference and pose, and does the exact test unlocked. Sensors are left out unless the filter asks for them.
#pragma once

#include <optional>
#include <vector>

#include "physics/BodyID.h"
#include "physics/body/BodyManager.h"
#include "physics/broadphase/BroadPhase.h"
#include "physics/broadphase/Layers.h"
#include "physics/core/Result.h"
#include "physics/narrowphase/ShapeSweep.h"
#include "physics/shapes/Shape.h"

namespace strata {

/// A ray hit on a body.
struct RayCastHit {
  BodyID body;
  float fraction = 1.0f;         ///< hit point = origin + fraction * direction
  Vec3 position = Vec3::Zero();  ///< world
  Vec3 normal = Vec3::UnitY();   ///< world, facing the ray
  std::uint32_t sub_shape = 0;   ///< triangle index for meshes
};

/// A body overlapping a query shape.
struct ShapeOverlap {
  BodyID body;
  Vec3 normal = Vec3::UnitY();  ///< from the query shape towards the body
  float penetration = 0.0f;     ///< >= 0 (m)
  Vec3 point = Vec3::Zero();    ///< deepest point on the body, world
};

/// A shape cast's contact with a body.
struct ShapeCastResult {
  BodyID body;
  float fraction = 1.0f;        ///< of the displacement travelled before touching; 0 for a start overlap
  Vec3 point = Vec3::Zero();    ///< on the body's surface, world
  Vec3 normal = Vec3::UnitY();  ///< unit, from the body towards the cast shape
  float penetration = 0.0f;     ///< how deep the shape overlapped the body at the start (m), else 0
  std::uint32_t sub_shape = 0;  ///< triangle index for meshes and height fields
};

/// The closest points of a query (a convex shape or a point) and a body.
struct ClosestPointResult {
  BodyID body;
  float distance = 0.0f;  ///< between the surfaces, >= 0 (0 when touching or overlapping)
  Vec3 point_on_body = Vec3::Zero();
  Vec3 point_on_query = Vec3::Zero();  ///< at distance 0 both points are the query's centre
  Vec3 normal = Vec3::UnitY();         ///< unit, from the body towards the query (meaningless at distance 0)
};

/// Read-only queries over one PhysicsSystem.
class WorldQuery {
 public:
  /// Queries `bodies` through `broad_phase` (both owned by the world, which outlives the query).
  WorldQuery(const BodyManager& bodies, BroadPhase& broad_phase)
      : bodies_(bodies), broad_phase_(broad_phase) {}

  /// Closest hit of the ray origin + t * direction, t in [0, 1]; nullopt when nothing is hit.
  Result<std::optional<RayCastHit>> CastRay(const Vec3& origin, const Vec3& direction,
                                            const QueryFilter& filter = {}) const;
  /// Every body the ray hits (first hit per body), nearest first.
  Result<std::vector<RayCastHit>> CastRayAll(const Vec3& origin, const Vec3& direction,
                                             const QueryFilter& filter = {}) const;
  /// Bodies whose world bounds overlap `box`, in ascending id order.
  Result<std::vector<BodyID>> CollideAABB(const AABB& box, const QueryFilter& filter = {}) const;
  /// Bodies that a convex `shape` at `pose` overlaps (penetration > 0), in ascending id order.
  Result<std::vector<ShapeOverlap>> CollideShape(const Shape& shape, const Pose& pose,
                                                 const QueryFilter& filter = {}) const;

  /// The first body a convex `shape` meets when swept from `start` by `displacement` (no rotation on the
  /// way): a body it overlaps at the start comes first (fraction 0, with its penetration). On a tie the lower
  /// id. Nothing when it meets none. Fails on a non-convex shape, non-finite input or bad settings.
  Result<std::optional<ShapeCastResult>> CastShape(const Shape& shape, const Pose& start,
                                                   const Vec3& displacement,
                                                   const ShapeCastSettings& settings = {},
                                                   const QueryFilter& filter = {}) const;
  /// Every body the sweep meets (its first contact with each), nearest first, then by id.
  Result<std::vector<ShapeCastResult>> CastShapeAll(const Shape& shape, const Pose& start,
                                                    const Vec3& displacement,
                                                    const ShapeCastSettings& settings = {},
                                                    const QueryFilter& filter = {}) const;
  /// Bodies whose shape holds `point` (a convex solid, surface included; the inside of a closed mesh; below
  /// a height field's surface), in ascending id order.
  Result<std::vector<BodyID>> CollidePoint(const Vec3& point, const QueryFilter& filter = {}) const;
  /// The body nearest to a convex `shape` at `pose` within `max_distance` (m), with the closest points;
  /// nothing when none is that close. On a tie the lower id.
  Result<std::optional<ClosestPointResult>> ClosestPoint(const Shape& shape, const Pose& pose,
                                                         float max_distance,
                                                         const QueryFilter& filter = {}) const;
  /// The body nearest to `point` within `max_distance` (m).
  Result<std::optional<ClosestPointResult>> ClosestPoint(const Vec3& point, float max_distance,
                                                         const QueryFilter& filter = {}) const;

 private:
  const BodyManager& bodies_;
  BroadPhase& broad_phase_;
};

}  // namespace strata
