// BroadPhase: finds which bodies' bounds overlap (pairs for the step, candidates for queries). An
// interface so the lock-free quad tree and the brute-force oracle are interchangeable.
// Add/Remove/Update and queries may be called from any thread; implementations do their own locking.
#pragma once

#include <span>
#include <vector>

#include "physics/body/BodyID.h"
#include "physics/broadphase/Layers.h"
#include "physics/math/AABB.h"

namespace strata {

/// Two bodies whose bounds overlap; `a` is the active (moving) one.
struct BodyPair {
  BodyID a;
  BodyID b;
  friend auto operator<=>(const BodyPair&, const BodyPair&) = default;
};

/// A body whose bounds a ray enters at `fraction`.
struct BroadPhaseRayHit {
  BodyID id;
  float fraction;
};

/// Spatial index over the bounds of the bodies in the world.
class BroadPhase {
 public:
  virtual ~BroadPhase() = default;

  /// Inserts a body (not yet present) with its world bounds and object layer.
  virtual void AddBody(BodyID id, const AABB& bounds, ObjectLayer layer) = 0;
  /// Removes a present body.
  virtual void RemoveBody(BodyID id) = 0;
  /// New bounds for a present body.
  virtual void UpdateBody(BodyID id, const AABB& bounds) = 0;
  /// Number of bodies present.
  virtual std::size_t body_count() const = 0;

  /// Appends every overlapping (active body, other body) pair the layer setup allows. `active_flags`
  /// is indexed by body index; a pair of two active bodies is reported once, with the lower index as `a`.
  virtual void FindPairs(std::span<const BodyID> active, std::span<const std::uint8_t> active_flags,
                         const LayerSetup& layers, std::vector<BodyPair>& out) const = 0;
  /// Appends bodies whose bounds overlap `box`.
  virtual void CollideAABB(const AABB& box, const QueryFilter& filter, std::vector<BodyID>& out) const = 0;
  /// Appends bodies whose bounds the ray origin + t * direction (t in [0, max_fraction]) enters.
  virtual void CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                       const QueryFilter& filter, std::vector<BroadPhaseRayHit>& out) const = 0;
};

}  // namespace strata
