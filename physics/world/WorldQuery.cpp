#include "physics/world/WorldQuery.h"

#include <algorithm>

#include "physics/narrowphase/CollideShapes.h"
#include "physics/narrowphase/ShapeQueries.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

namespace {

// What a query copies out of a body under its read lock.
struct LockedCopy {
  ShapeRef shape;
  Pose pose;
  AABB bounds;
};

// Nothing for a body that left the world, or a sensor the filter does not ask for.
std::optional<LockedCopy> CopyLocked(const BodyManager& manager, BodyID id, const QueryFilter& filter) {
  BodyLockRead lock(manager, id);
  if (!lock.Succeeded() || !lock.body().in_world()) return std::nullopt;
  if (lock.body().is_sensor() && !filter.sensors) return std::nullopt;
  return LockedCopy{lock.body().shape(), lock.body().pose(), lock.body().world_bounds()};
}

Status CheckPose(const Pose& pose, const char* what) {
  if (!IsFinite(pose.position) || !IsFinite(pose.rotation) || pose.rotation.norm() < 1e-6f)
    return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " must be finite, with a rotation");
  return Status::Ok();
}

Status CheckCast(const Shape& shape, const Pose& start, const Vec3& displacement,
                 const ShapeCastSettings& settings) {
  if (!shape.IsConvex()) return MakeError(ErrorCode::kInvalidArgument, "cast shape must be convex");
  if (Status pose = CheckPose(start, "cast start pose"); !pose) return pose;
  if (!IsFinite(displacement))
    return MakeError(ErrorCode::kInvalidArgument, "cast displacement must be finite");
  return settings.Validate();
}

// The order casts report contacts in: nearest first; at a start overlap the deeper first; then the lower id.
bool CastsBefore(const ShapeCastResult& a, const ShapeCastResult& b) {
  if (a.fraction != b.fraction) return a.fraction < b.fraction;
  if (a.penetration != b.penetration) return a.penetration > b.penetration;
  return a.body < b.body;
}

ShapeCastResult ToResult(BodyID id, const SweepContact& contact) {
  return {id, contact.fraction, contact.point, contact.normal, contact.penetration, contact.sub_shape};
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
    ClosestHitCollector(const BodyManager& bodies, const Vec3& origin, const Vec3& direction,
                        const QueryFilter& filter)
        : bodies_(bodies), origin_(origin), direction_(direction), filter_(filter) {
      SetEarlyOutFraction(1.0f);
    }
    void AddHit(BodyID id, float) override {
      const std::optional<LockedCopy> body = CopyLocked(bodies_, id, filter_);
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
    const QueryFilter& filter_;
  };
  ClosestHitCollector collector(bodies_, origin, direction, filter);
  broad_phase_.CastRay(broad_phase_.Pin(), origin, direction, filter, collector);
  return collector.best;
}

Result<std::vector<RayCastHit>> WorldQuery::CastRayAll(const Vec3& origin, const Vec3& direction,
                                                       const QueryFilter& filter) const {
  if (Status valid = CheckRay(origin, direction); !valid) return valid.error();
  std::vector<BroadPhaseRayHit> candidates;
  broad_phase_.CastRay(origin, direction, filter, candidates);
  std::vector<RayCastHit> hits;
  for (const BroadPhaseRayHit& candidate : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(bodies_, candidate.id, filter);
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
  broad_phase_.CollideAABB(box, filter, candidates);
  std::vector<BodyID> result;
  for (const BodyID id : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(bodies_, id, filter);
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
  broad_phase_.CollideAABB(shape.WorldBounds(query_pose), filter, candidates);
  std::sort(candidates.begin(), candidates.end());
  std::vector<ShapeOverlap> result;
  std::vector<ContactManifold> manifolds;
  for (const BodyID id : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(bodies_, id, filter);
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

Result<std::optional<ShapeCastResult>> WorldQuery::CastShape(const Shape& shape, const Pose& start,
                                                             const Vec3& displacement,
                                                             const ShapeCastSettings& settings,
                                                             const QueryFilter& filter) const {
  if (Status valid = CheckCast(shape, start, displacement, settings); !valid) return valid.error();
  const Pose pose{start.position, start.rotation.normalized()};
  const auto& convex = static_cast<const ConvexShape&>(shape);
  // The tree hands over bodies nearest bounds first; each contact lowers the early out and prunes the rest
  // (bodies entered at exactly that fraction still come: a tie goes to the deeper, then the lower id).
  class NearestCollector final : public BroadPhaseCollector {
   public:
    NearestCollector(const BodyManager& bodies, const ConvexShape& shape, const Pose& start,
                     const Vec3& displacement, const ShapeCastSettings& settings, const QueryFilter& filter)
        : bodies_(bodies),
          shape_(shape),
          start_(start),
          displacement_(displacement),
          settings_(settings),
          filter_(filter) {
      SetEarlyOutFraction(1.0f);
    }
    void AddHit(BodyID id, float) override {
      const std::optional<LockedCopy> body = CopyLocked(bodies_, id, filter_);
      if (!body) return;
      const std::optional<SweepContact> contact =
          SweepConvexShape(shape_, start_, displacement_, *body->shape, body->pose, settings_, scratch_);
      if (!contact) return;
      const ShapeCastResult result = ToResult(id, *contact);
      if (best && !CastsBefore(result, *best)) return;
      best = result;
      SetEarlyOutFraction(result.fraction);
    }
    std::optional<ShapeCastResult> best;

   private:
    const BodyManager& bodies_;
    const ConvexShape& shape_;
    const Pose& start_;
    const Vec3& displacement_;
    const ShapeCastSettings& settings_;
    const QueryFilter& filter_;
    CollisionScratch scratch_;
  };
  NearestCollector collector(bodies_, convex, pose, displacement, settings, filter);
  const AABB bounds = shape.WorldBounds(pose).Expanded(settings.tolerance);
  broad_phase_.CastAABB(broad_phase_.Pin(), bounds, displacement, filter, collector);
  return collector.best;
}

Result<std::vector<ShapeCastResult>> WorldQuery::CastShapeAll(const Shape& shape, const Pose& start,
                                                              const Vec3& displacement,
                                                              const ShapeCastSettings& settings,
                                                              const QueryFilter& filter) const {
  if (Status valid = CheckCast(shape, start, displacement, settings); !valid) return valid.error();
  const Pose pose{start.position, start.rotation.normalized()};
  std::vector<BroadPhaseRayHit> candidates;
  broad_phase_.CastAABB(shape.WorldBounds(pose).Expanded(settings.tolerance), displacement, filter,
                        candidates);
  std::vector<ShapeCastResult> hits;
  CollisionScratch scratch;
  for (const BroadPhaseRayHit& candidate : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(bodies_, candidate.id, filter);
    if (!body) continue;
    const std::optional<SweepContact> contact =
        SweepConvexShape(static_cast<const ConvexShape&>(shape), pose, displacement, *body->shape, body->pose,
                         settings, scratch);
    if (contact) hits.push_back(ToResult(candidate.id, *contact));
  }
  std::sort(hits.begin(), hits.end(), CastsBefore);
  return hits;
}

Result<std::vector<BodyID>> WorldQuery::CollidePoint(const Vec3& point, const QueryFilter& filter) const {
  if (!IsFinite(point)) return MakeError(ErrorCode::kInvalidArgument, "query point must be finite");
  std::vector<BodyID> candidates;
  broad_phase_.CollideAABB(AABB(point, point), filter, candidates);
  std::sort(candidates.begin(), candidates.end());
  std::vector<BodyID> result;
  std::vector<Triangle> triangles;
  for (const BodyID id : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(bodies_, id, filter);
    if (body && ShapeContainsPoint(*body->shape, body->pose, point, triangles)) result.push_back(id);
  }
  return result;
}

namespace {

// The nearest of the candidates within `max_distance` of the query (ties to the lower id).
std::optional<ClosestPointResult> Nearest(const BodyManager& bodies, std::vector<BodyID>& candidates,
                                          const DistanceQuery& query, float max_distance,
                                          const QueryFilter& filter) {
  std::sort(candidates.begin(), candidates.end());
  std::optional<ClosestPointResult> nearest;
  std::vector<Triangle> triangles;
  for (const BodyID id : candidates) {
    const std::optional<LockedCopy> body = CopyLocked(bodies, id, filter);
    if (!body) continue;
    const float reach = nearest ? nearest->distance : max_distance;
    const std::optional<ClosestPoints> found =
        ClosestPointsTo(query, *body->shape, body->pose, reach, triangles);
    if (!found || (nearest && found->distance >= nearest->distance)) continue;
    nearest = ClosestPointResult{id, found->distance, found->on_shape, found->on_query, found->normal};
  }
  return nearest;
}

Status CheckDistance(float max_distance) {
  if (!IsFinite(max_distance) || max_distance < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "max distance must be a finite number >= 0");
  return Status::Ok();
}

}  // namespace

Result<std::optional<ClosestPointResult>> WorldQuery::ClosestPoint(const Shape& shape, const Pose& pose,
                                                                   float max_distance,
                                                                   const QueryFilter& filter) const {
  if (!shape.IsConvex()) return MakeError(ErrorCode::kInvalidArgument, "query shape must be convex");
  if (Status valid = CheckPose(pose, "query pose"); !valid) return valid.error();
  if (Status valid = CheckDistance(max_distance); !valid) return valid.error();
  const Pose query_pose{pose.position, pose.rotation.normalized()};
  const MeasuredConvex measured(static_cast<const ConvexShape&>(shape), query_pose);
  const DistanceQuery query{measured.support, measured.radius, shape.WorldBounds(query_pose)};
  std::vector<BodyID> candidates;
  broad_phase_.CollideAABB(query.bounds.Expanded(max_distance), filter, candidates);
  return Nearest(bodies_, candidates, query, max_distance, filter);
}

Result<std::optional<ClosestPointResult>> WorldQuery::ClosestPoint(const Vec3& point, float max_distance,
                                                                   const QueryFilter& filter) const {
  if (!IsFinite(point)) return MakeError(ErrorCode::kInvalidArgument, "query point must be finite");
  if (Status valid = CheckDistance(max_distance); !valid) return valid.error();
  const PointSupport support(point);
  const DistanceQuery query{support, 0.0f, AABB(point, point)};
  std::vector<BodyID> candidates;
  broad_phase_.CollideAABB(query.bounds.Expanded(max_distance), filter, candidates);
  return Nearest(bodies_, candidates, query, max_distance, filter);
}

}  // namespace strata
