#include "physics/narrowphase/CollisionDispatch.h"

#include <algorithm>
#include <cassert>
#include <utility>

namespace strata {

namespace {

CollisionDispatch BuildDefault() {
  CollisionDispatch table;
  // The shapes, one line each.
  table.AddConvexShape(ShapeType::kSphere);
  table.AddConvexShape(ShapeType::kBox);
  table.AddConvexShape(ShapeType::kCapsule);
  table.AddConvexShape(ShapeType::kConvexHull);
  table.AddTriangleShape(ShapeType::kTriangleMesh, CollideConvexWithMesh, CastOntoTriangles,
                         SweepOntoTriangleShape<TriangleMeshShape>);
  table.AddTriangleShape(ShapeType::kHeightField, CollideConvexWithHeightField, CastOntoTriangles,
                         SweepOntoTriangleShape<HeightFieldShape>);
  // Pairs with a closed form or a separating-axis test, which beat GJK on them. A hull against a box keeps
  // its own entry: the face preferences of the polyhedron test are not symmetric.
  table.RegisterCollide(ShapeType::kSphere, ShapeType::kSphere, CollideSpherePair);
  table.RegisterCollide(ShapeType::kSphere, ShapeType::kBox, CollideSphereWithBox);
  table.RegisterCollide(ShapeType::kBox, ShapeType::kBox, CollideBoxPair);
  table.RegisterCollide(ShapeType::kBox, ShapeType::kConvexHull, CollidePolyhedronPair);
  table.RegisterCollide(ShapeType::kConvexHull, ShapeType::kBox, CollidePolyhedronPair);
  table.RegisterCollide(ShapeType::kConvexHull, ShapeType::kConvexHull, CollidePolyhedronPair);
  return table;
}

// The manifold of (b, a) as one of (a, b): the other way round in everything that has a side.
void TurnRound(ContactManifold& manifold) {
  std::swap(manifold.body_a, manifold.body_b);
  std::swap(manifold.sub_shape_a, manifold.sub_shape_b);
  manifold.normal = -manifold.normal;
  manifold.face.on_a = !manifold.face.on_a;
  for (int i = 0; i < manifold.count; ++i)
    std::swap(manifold.points[i].position_a, manifold.points[i].position_b);
}

}  // namespace

const CollisionDispatch& CollisionDispatch::Default() {
  static const CollisionDispatch table = BuildDefault();
  return table;
}

void CollisionDispatch::AddConvexShape(ShapeType type) {
  assert(Index(type) < kMaxShapeTypes);
  convex_.push_back(type);
  for (const ShapeType other : convex_) {
    // GJK takes either order as it comes, so neither entry is a swapped one.
    for (Slot* slot : {&Entry(type, other), &Entry(other, type)})
      if (slot->source == Source::kNone) *slot = {CollideConvexByGjk, Source::kKind};
  }
  for (std::size_t k = 0; k < triangle_.size(); ++k) {
    Entry(type, triangle_[k]) = {triangle_collide_[k], Source::kKind};
    Entry(triangle_[k], type) = {triangle_collide_[k], Source::kSwapped};
  }
  cast_[Index(type)] = CastOntoConvex;
  sweep_[Index(type)] = SweepOntoConvex;
}

void CollisionDispatch::AddTriangleShape(ShapeType type, CollideFunction collide_convex,
                                         CastFunction cast_onto, SweepFunction sweep_onto) {
  assert(Index(type) < kMaxShapeTypes);
  triangle_.push_back(type);
  triangle_collide_.push_back(collide_convex);
  for (const ShapeType convex : convex_) {
    Entry(convex, type) = {collide_convex, Source::kKind};
    Entry(type, convex) = {collide_convex, Source::kSwapped};
  }
  cast_[Index(type)] = cast_onto;
  sweep_[Index(type)] = sweep_onto;
}

void CollisionDispatch::RegisterCollide(ShapeType a, ShapeType b, CollideFunction collide) {
  assert(Index(a) < kMaxShapeTypes && Index(b) < kMaxShapeTypes);
  Entry(a, b) = {collide, Source::kRegistered};
  if (a != b && Entry(b, a).source != Source::kRegistered) Entry(b, a) = {collide, Source::kSwapped};
}

void CollisionDispatch::Collide(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                                const ContactReach& reach, const ContactManifold& prototype,
                                std::vector<ContactManifold>& out, CollisionScratch& scratch) const {
  scratch.separating_axis = Vec3::Zero();
  const Slot& slot = Entry(a.type(), b.type());
  if (slot.collide == nullptr) return;
  const std::size_t first = out.size();
  if (slot.source != Source::kSwapped) {
    slot.collide(a, pose_a, b, pose_b, reach, prototype, out, scratch);
  } else {
    ContactManifold swapped = prototype;
    TurnRound(swapped);
    slot.collide(b, pose_b, a, pose_a, reach.Reversed(), swapped, out, scratch);
    for (std::size_t m = first; m < out.size(); ++m) TurnRound(out[m]);
    scratch.separating_axis = -scratch.separating_axis;
  }
  if (reach.travel.isZero()) return;  // the reach is the same along every normal
  const auto beyond = [&](const ContactManifold& manifold) {
    return manifold.MinSeparation() > reach.Along(manifold.normal);
  };
  out.erase(std::remove_if(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(), beyond), out.end());
}

std::optional<ShapeCastHit> CollisionDispatch::Cast(const ConvexShape& shape, const Pose& start,
                                                    const Vec3& displacement, const Shape& target,
                                                    const Pose& target_pose, float tolerance,
                                                    std::vector<Triangle>& triangles) const {
  const CastFunction cast = cast_[Index(target.type())];
  if (cast == nullptr) return std::nullopt;
  return cast(shape, start, displacement, target, target_pose, tolerance, triangles);
}

std::optional<SweepContact> CollisionDispatch::Sweep(const ConvexShape& shape, const Pose& start,
                                                     const Vec3& displacement, const Shape& target,
                                                     const Pose& target_pose,
                                                     const ShapeCastSettings& settings,
                                                     CollisionScratch& scratch) const {
  const SweepFunction sweep = sweep_[Index(target.type())];
  if (sweep == nullptr) return std::nullopt;
  return sweep(shape, start, displacement, target, target_pose, settings, scratch);
}

}  // namespace strata
