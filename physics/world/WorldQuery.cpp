#include "physics/world/WorldQuery.h"

#include <algorithm>

#include "physics/narrowphase/CollideShapes.h"
#include "physics/world/PhysicsSystem.h"

namespace strata {

namespace {

// What a query copies out of a body under its read lock.
struct LockedCopy {
  ShapeRef shape;
  Pose pose;
  AABB bounds;
};

std::optional<LockedCopy> CopyLocked(const BodyManager& manager, BodyID id) {
  BodyLockRead lock(manager, id);
  if (!lock.Succeeded() || !lock.body().in_world()) return std::nullopt;
  return LockedCopy{lock.body().shape(), lock.body().pose(), lock.body().world_bounds()};
}

Status CheckRay(const Vec3& origin, const Vec3& direction) {
  if (!IsFinite(origin) || !IsFinite(direction))
    return MakeError(ErrorCode::kInvalidArgument, "ray origin and direction must be finite");
  if (direction.squaredNorm() == 0.0f) return MakeError(ErrorCode::kInvalidArgument, "ray direction is zero");
  return Status::Ok();
}

std::optional<RayCastHit> CastAgainst(const LockedCopy& body, BodyID id, const Vec3& origin,
                                      const Vec3& direction, float max_fraction) {
  ShapeRayHit local;
  if (!body.shape->CastRay(body.pose.ToLocal(origin), body.pose.DirectionToLocal(direction), max_fraction,
                           local))
    return std::nullopt;
  RayCastHit hit;
  hit.body = id;
  hit.fraction = local.fraction;
  hit.position = origin + local.fraction * direction;
  hit.normal = body.pose.DirectionToWorld(local.normal);
  hit.sub_shape = local.sub_shape;
  return hit;
}

}  // namespace

Result<std::optional<RayCastHit>> WorldQuery::CastRay(const Vec3& origin, const Vec3& direction,
                                                      const QueryFilter& filter) const {
  if (Status valid = CheckRay(origin, direction); !valid) return valid.error();
  // The tree hands over bodies nearest bounds first; each exact hit lowers the early out and prunes the rest.
  class ClosestHitCollector final : public BroadPhaseCollector {
   public:
    ClosestHitCollector(const BodyManager& bodies, const Vec3& origin, const Vec3& direction)
        : bodies_(bodies), origin_(origin), direction_(direction) {
      SetEarlyOutFraction(1.0f);
    }
    void AddHit(BodyID id, float) override {
      const std::optional<LockedCopy> body = CopyLocked(bodies_, id);
      if (!body) return;
      const auto hit = CastAgainst(*body, id, origin_, direction_, early_out_fraction());
      if (!hit || (best && (hit->fraction > best->fraction ||
                            (hit->fraction == best->fraction && hit->body > best->body))))
        return;
      best = hit;
      SetEarlyOutFraction(hit->fraction);
    }
    std::optional<RayCastHit> best;

   private:
    const BodyManager& bodies_;
    const Vec3& origin_;
    const Vec3& direction_;
  };
  ClosestHitCollector collector(system_.body_manager_, origin, direction);
  system_.broad_phase_->CastRay(system_.broad_phase_->Pin(), origin, direction, filter, collector);
  return collector.best;
}

Result<std::vector<RayCastHit>> WorldQuery::CastRayAll(const Vec3& origin, const Vec3& direction,
                                                       const QueryFilter& filter) const {
  if (Status valid = CheckRay(origin, direction); !valid) return valid.error();
  std::vector<BroadPhaseRayHit> candidates;
  system_.broad_phase_->CastRay(origin, direction, filter, candidates);
  std::vector<RayCastHit> hits;
  for (const BroadPhaseRayHit& candidate : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(system_.body_manager_, candidate.id);
    if (!body) continue;
    if (auto hit = CastAgainst(*body, candidate.id, origin, direction, 1.0f)) hits.push_back(*hit);
  }
  std::sort(hits.begin(), hits.end(), [](const RayCastHit& a, const RayCastHit& b) {
    return a.fraction < b.fraction || (a.fraction == b.fraction && a.body < b.body);
  });
  return hits;
}

Result<std::vector<BodyID>> WorldQuery::CollideAABB(const AABB& box, const QueryFilter& filter) const {
  if (!box.IsValid())
    return MakeError(ErrorCode::kInvalidArgument, "query box must be finite with min <= max");
  std::vector<BodyID> candidates;
  system_.broad_phase_->CollideAABB(box, filter, candidates);
  std::vector<BodyID> result;
  for (const BodyID id : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(system_.body_manager_, id);
    if (body && body->bounds.Overlaps(box)) result.push_back(id);
  }
  std::sort(result.begin(), result.end());
  return result;
}

Result<std::vector<ShapeOverlap>> WorldQuery::CollideShape(const Shape& shape, const Pose& pose,
                                                           const QueryFilter& filter) const {
  if (!shape.IsConvex()) return MakeError(ErrorCode::kInvalidArgument, "query shape must be convex");
  if (!IsFinite(pose.position) || !IsFinite(pose.rotation))
    return MakeError(ErrorCode::kInvalidArgument, "query pose must be finite");
  const Pose query_pose{pose.position, pose.rotation.normalized()};
  std::vector<BodyID> candidates;
  system_.broad_phase_->CollideAABB(shape.WorldBounds(query_pose), filter, candidates);
  std::sort(candidates.begin(), candidates.end());
  std::vector<ShapeOverlap> result;
  std::vector<ContactManifold> manifolds;
  for (const BodyID id : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(system_.body_manager_, id);
    if (!body) continue;
    manifolds.clear();
    CollideShapes(shape, query_pose, *body->shape, body->pose, 0.0f, ContactManifold{}, manifolds);
    ShapeOverlap overlap;
    overlap.body = id;
    for (const ContactManifold& manifold : manifolds) {
      for (int i = 0; i < manifold.count; ++i) {
        if (-manifold.points[i].separation > overlap.penetration) {
          overlap.penetration = -manifold.points[i].separation;
          overlap.normal = manifold.normal;
          overlap.point = manifold.points[i].position_b;
        }
      }
    }
    if (overlap.penetration > 0.0f) result.push_back(overlap);
  }
  return result;
}

}  // namespace strata
