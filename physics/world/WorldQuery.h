// WorldQuery: ray casts, box overlap and shape overlap against the bodies of a PhysicsSystem.
// Any number of threads may query at once. Each query walks the broad phase, then takes each candidate's
// read lock only long enough to copy its shape reference and pose, and does the exact test unlocked.
#pragma once

#include <optional>
#include <vector>

#include "physics/body/BodyID.h"
#include "physics/broadphase/Layers.h"
#include "physics/core/Result.h"
#include "physics/shapes/Shape.h"

namespace strata {

class PhysicsSystem;

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

/// Read-only queries over one PhysicsSystem.
class WorldQuery {
 public:
  explicit WorldQuery(const PhysicsSystem& system) : system_(system) {}

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

 private:
  const PhysicsSystem& system_;
};

}  // namespace strata
