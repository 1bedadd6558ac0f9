#include "physics/narrowphase/ShapeSweep.h"

#include <algorithm>

#include "physics/narrowphase/CollisionDispatch.h"
#include "physics/narrowphase/Gjk.h"
#include "physics/shapes/HeightFieldShape.h"

namespace strata {

namespace {

// Conservative advancement halves the gap at least every step, even where the shape only grazes the target
// (the gap's slope goes to zero as it touches): far more steps than any float distance needs.
constexpr int kMaxAdvances = 64;

// Float rounding grows with distance from the origin: a sweep runs with the cast's start as its origin, so a
// cast far out in a level measures small gaps as well as one at the origin.
Pose Shifted(const Pose& pose, const Vec3& origin) {
  return {pose.position - origin, pose.rotation};
}
std::optional<SweepContact> Unshifted(std::optional<SweepContact> contact, const Vec3& origin) {
  if (contact) contact->point += origin;
  return contact;
}

// The shape's deepest contact with the target at its start, as the narrow phase's contacts see it: an overlap
// (penetration > 0) or a touch within the tolerance. The contacts' own tests (separating axes for boxes and
// hulls, closed forms for round shapes) decide there, where GJK on near-touching shapes cannot tell a gap of
// a few micrometres from an overlap.
std::optional<SweepContact> StartContact(const ConvexShape& shape, const Pose& start, const Shape& target,
                                         const Pose& target_pose, const ShapeCastSettings& settings,
                                         CollisionScratch& scratch) {
  std::vector<ContactManifold>& manifolds = scratch.manifolds;
  manifolds.clear();
  CollisionDispatch::Default().Collide(shape, start, target, target_pose, ContactReach{settings.tolerance},
                                       ContactManifold{}, manifolds, scratch);
  std::optional<SweepContact> deepest;
  float deepest_separation = settings.tolerance;
  for (const ContactManifold& manifold : manifolds)
    for (int i = 0; i < manifold.count; ++i) {
      const ContactPoint& point = manifold.points[i];
      if (point.separation >= deepest_separation) continue;
      deepest_separation = point.separation;
      deepest = SweepContact{0.0f, point.position_b, -manifold.normal, std::max(0.0f, -point.separation),
                             manifold.sub_shape_b};
    }
  return deepest;
}

// The narrow phase measures a shallow contact along the normal of the rounded cores, and beside an edge of a
// box or hull that normal tilts enough to report an overlap of a few millimetres where a gap of a fraction
// of one remains. GJK on the exact shapes tells such a gap (over the tolerance) apart: no contact there.
bool ClearAtStart(const ConvexShape& shape, const Pose& start, const ConvexSupport& target,
                  float target_radius, float tolerance) {
  const MeasuredConvex measured(shape, start);
  const GjkResult closest = GjkClosestPoints(measured.support, target, kLargeFloat);
  return !closest.overlapping && closest.distance - measured.radius - target_radius > tolerance;
}

// Whether a contact at the start stops the cast: an overlap always (unless the settings let a shape that
// moves out of it go), a touch when the displacement presses into it.
bool Blocks(const SweepContact& contact, const Vec3& displacement, const ShapeCastSettings& settings) {
  const bool moving_in = displacement.dot(contact.normal) < 0.0f;
  if (contact.penetration > 0.0f) return moving_in || !settings.ignore_overlaps_moving_out;
  return moving_in;
}

// Conservative advancement against one convex support (its own `target_radius` around it): step forward by
// the gap over the closing speed. Along a straight line the gap is a convex function of the travel, so a
// step never passes the first touch. The contact at the start is StartContact's: here a touch at the start
// only counts when the shape moves into it.
std::optional<SweepContact> Advance(const ConvexShape& shape, const Pose& start, const Vec3& displacement,
                                    const ConvexSupport& target, float target_radius,
                                    const ShapeCastSettings& settings) {
  float t = 0.0f;
  Vec3 normal = Vec3::UnitY(), point = Vec3::Zero();
  for (int advance = 0; advance < kMaxAdvances; ++advance) {
    const Pose pose{start.position + t * displacement, start.rotation};
    const MeasuredConvex swept(shape, pose);
    const float radius = swept.radius + target_radius;
    const GjkResult closest = GjkClosestPoints(swept.support, target, kLargeFloat);
    if (closest.overlapping) {
      // At the start: behind a one-sided triangle, or a touch GJK cannot resolve (StartContact saw none).
      // After a step that stopped short of the touch: the touch itself, which GJK took for an overlap.
      if (advance == 0) return std::nullopt;
      return SweepContact{t, point, normal, 0.0f, 0};
    }
    const float gap = closest.distance - radius;
    normal = (closest.point_a - closest.point_b).normalized();
    point = closest.point_b + target_radius * normal;
    const float closing = -displacement.dot(normal);
    if (gap <= settings.tolerance) {
      if (advance == 0 && closing <= 0.0f) return std::nullopt;  // touching as it starts and moving away
      return SweepContact{t, point, normal, advance == 0 ? std::max(0.0f, -gap) : 0.0f, 0};
    }
    if (closing <= 0.0f) return std::nullopt;  // moving away along the closest direction: never touches
    t += (gap - 0.5f * settings.tolerance) / closing;
    if (t > 1.0f) return std::nullopt;
  }
  return std::nullopt;
}

// A convex shape swept over anything made of triangles that TriangleMeshShape's triangle interface describes
// (QueryBox, Vertex, Normal): each triangle near the sweep, the nearest hit wins (the lower triangle number
// on a tie, whatever order the query found them in).
template <class TriangleShape>
std::optional<SweepContact> SweepOntoTriangles(const ConvexShape& shape, const Pose& start,
                                               const Vec3& displacement, const TriangleShape& mesh,
                                               const Pose& mesh_pose, const ShapeCastSettings& settings,
                                               CollisionScratch& scratch) {
  if (auto contact = StartContact(shape, start, mesh, mesh_pose, settings, scratch); contact) {
    const std::uint32_t t = contact->sub_shape;
    const TriangleSupport triangle(mesh_pose.ToWorld(mesh.Vertex(t, 0)), mesh_pose.ToWorld(mesh.Vertex(t, 1)),
                                   mesh_pose.ToWorld(mesh.Vertex(t, 2)));
    // A touch the exact distance rules out leaves the triangles to the sweep below.
    if (Blocks(*contact, displacement, settings) &&
        !ClearAtStart(shape, start, triangle, 0.0f, settings.tolerance))
      return contact;
  }
  AABB swept = shape.WorldBounds(start);
  swept.Encapsulate(AABB(swept.min + displacement, swept.max + displacement));
  const Pose to_mesh{mesh_pose.rotation.conjugate() * -mesh_pose.position, mesh_pose.rotation.conjugate()};
  std::vector<std::uint32_t>& triangles = scratch.triangles;
  triangles.clear();
  mesh.QueryBox(swept.Expanded(settings.tolerance).Transformed(to_mesh), triangles);
  std::sort(triangles.begin(), triangles.end());
  std::optional<SweepContact> nearest;
  const Pose end{start.position + displacement, start.rotation};
  for (const std::uint32_t t : triangles) {
    const Vec3 normal = mesh_pose.rotation * mesh.Normal(t);
    const TriangleSupport triangle(mesh_pose.ToWorld(mesh.Vertex(t, 0)), mesh_pose.ToWorld(mesh.Vertex(t, 1)),
                                   mesh_pose.ToWorld(mesh.Vertex(t, 2)));
    // One-sided: a shape that stays behind the triangle's plane all the way can only meet its back.
    const float plane = normal.dot(triangle.vertex(0));
    const auto behind = [&](const Pose& pose) {
      return normal.dot(pose.ToWorld(shape.Support(pose.DirectionToLocal(normal)))) < plane;
    };
    if (!settings.back_faces && behind(start) && behind(end)) continue;
    std::optional<SweepContact> hit = Advance(shape, start, displacement, triangle, 0.0f, settings);
    if (!hit || (nearest && hit->fraction >= nearest->fraction)) continue;
    // Met from behind (the contact pushes towards the back): passes, as the triangle's contacts let it.
    if (!settings.back_faces && hit->normal.dot(normal) < 0.0f) continue;
    nearest = hit;
    nearest->sub_shape = t;
  }
  return nearest;
}

}  // namespace

Status ShapeCastSettings::Validate() const {
  if (!(tolerance > 0.0f && tolerance <= 1.0f))
    return MakeError(ErrorCode::kInvalidArgument, "shape cast tolerance must be in (0, 1] m");
  return Status::Ok();
}

std::optional<SweepContact> SweepOntoConvex(const ConvexShape& shape, const Pose& start,
                                            const Vec3& displacement, const Shape& target,
                                            const Pose& target_pose, const ShapeCastSettings& settings,
                                            CollisionScratch& scratch) {
  const Vec3& origin = start.position;
  const Pose local_start = Shifted(start, origin), local_target = Shifted(target_pose, origin);
  const MeasuredConvex measured(static_cast<const ConvexShape&>(target), local_target);
  if (auto contact = StartContact(shape, local_start, target, local_target, settings, scratch);
      contact && !ClearAtStart(shape, local_start, measured.support, measured.radius, settings.tolerance)) {
    // A convex target the shape leaves (or slides along) is never met again.
    if (!Blocks(*contact, displacement, settings)) return std::nullopt;
    return Unshifted(contact, origin);
  }
  return Unshifted(Advance(shape, local_start, displacement, measured.support, measured.radius, settings),
                   origin);
}

template <class TriangleShape>
std::optional<SweepContact> SweepOntoTriangleShape(const ConvexShape& shape, const Pose& start,
                                                   const Vec3& displacement, const Shape& target,
                                                   const Pose& target_pose, const ShapeCastSettings& settings,
                                                   CollisionScratch& scratch) {
  const Vec3& origin = start.position;
  return Unshifted(SweepOntoTriangles(shape, Shifted(start, origin), displacement,
                                      static_cast<const TriangleShape&>(target), Shifted(target_pose, origin),
                                      settings, scratch),
                   origin);
}

template std::optional<SweepContact> SweepOntoTriangleShape<TriangleMeshShape>(const ConvexShape&,
                                                                               const Pose&, const Vec3&,
                                                                               const Shape&, const Pose&,
                                                                               const ShapeCastSettings&,
                                                                               CollisionScratch&);
template std::optional<SweepContact> SweepOntoTriangleShape<HeightFieldShape>(const ConvexShape&, const Pose&,
                                                                              const Vec3&, const Shape&,
                                                                              const Pose&,
                                                                              const ShapeCastSettings&,
                                                                              CollisionScratch&);

std::optional<SweepContact> SweepConvexShape(const ConvexShape& shape, const Pose& start,
                                             const Vec3& displacement, const Shape& target,
                                             const Pose& target_pose, const ShapeCastSettings& settings,
                                             CollisionScratch& scratch) {
  return CollisionDispatch::Default().Sweep(shape, start, displacement, target, target_pose, settings,
                                            scratch);
}

}  // namespace strata
