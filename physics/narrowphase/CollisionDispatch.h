// CollisionDispatch: the narrow phase's functions by shape type (collide by pair, cast and sweep by target),
// so a new shape is its own files plus one line in BuildDefault (see physics/README.md, "Extending").
// Built once, on first use, and read-only after that: any thread may look up without a lock.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "physics/narrowphase/CollideShapes.h"
#include "physics/narrowphase/ShapeCast.h"
#include "physics/narrowphase/ShapeSweep.h"

namespace strata {

/// Appends the contacts between `a` and `b` (each new manifold starts as `prototype`) to `out`.
using CollideFunction = void (*)(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                                 const ContactReach& reach, const ContactManifold& prototype,
                                 std::vector<ContactManifold>& out, CollisionScratch& scratch);
/// Where `shape` swept from `start` by `displacement` first touches `target` (see CastConvexShape).
using CastFunction = std::optional<ShapeCastHit> (*)(const ConvexShape& shape, const Pose& start,
                                                     const Vec3& displacement, const Shape& target,
                                                     const Pose& target_pose, float tolerance,
                                                     std::vector<Triangle>& triangles);
/// Where a query's `shape` swept from `start` by `displacement` meets `target` (see SweepConvexShape).
using SweepFunction = std::optional<SweepContact> (*)(const ConvexShape& shape, const Pose& start,
                                                      const Vec3& displacement, const Shape& target,
                                                      const Pose& target_pose,
                                                      const ShapeCastSettings& settings,
                                                      CollisionScratch& scratch);

/// Shape-type pair -> collide function, target type -> cast function. A shape joins by kind (convex, or made
/// of triangles) and gets every pair at once; faster forms for a pair are registered on top.
class CollisionDispatch {
 public:
  static constexpr std::size_t kMaxShapeTypes = 16;

  /// The engine's table: every built-in shape and its fast pairs.
  static const CollisionDispatch& Default();

  /// A convex shape: collides with every convex shape added so far by GJK (EPA when the cores overlap),
  /// with every triangle shape through that shape's function, and is a target for conservative advancement.
  void AddConvexShape(ShapeType type);
  /// A shape made of triangles (it never moves, so it never collides with another of its kind):
  /// `collide_convex` takes a convex shape as A and this shape as B; `cast_onto` sweeps against it for the
  /// step's linear casts, `sweep_onto` for shape cast queries.
  void AddTriangleShape(ShapeType type, CollideFunction collide_convex, CastFunction cast_onto,
                        SweepFunction sweep_onto);
  /// A faster form for the pair (a, b) than the kinds give. The pair (b, a) gets it too, with the shapes
  /// swapped and the manifolds turned round, unless a form was registered for (b, a) itself.
  void RegisterCollide(ShapeType a, ShapeType b, CollideFunction collide);

  /// Contacts between `a` and `b` within `reach` along their normals (a function tests within its Max and
  /// this drops what lies beyond the reach along the normal found); nothing for a pair no shape registered
  /// (two triangle shapes).
  void Collide(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
               const ContactReach& reach, const ContactManifold& prototype, std::vector<ContactManifold>& out,
               CollisionScratch& scratch) const;
  /// First touch of `shape` swept against `target`; nullopt when none, or when the target type has no cast.
  std::optional<ShapeCastHit> Cast(const ConvexShape& shape, const Pose& start, const Vec3& displacement,
                                   const Shape& target, const Pose& target_pose, float tolerance,
                                   std::vector<Triangle>& triangles) const;

  /// A shape cast query's contact with `target`; nothing when none, or when the target type has no sweep.
  std::optional<SweepContact> Sweep(const ConvexShape& shape, const Pose& start, const Vec3& displacement,
                                    const Shape& target, const Pose& target_pose,
                                    const ShapeCastSettings& settings, CollisionScratch& scratch) const;

  /// Whether the pair has a collide function (in either order of the arguments it was registered in).
  bool Collides(ShapeType a, ShapeType b) const { return Entry(a, b).collide != nullptr; }

 private:
  enum class Source : std::uint8_t { kNone, kKind, kRegistered, kSwapped };
  struct Slot {
    CollideFunction collide = nullptr;
    Source source = Source::kNone;
  };
  static std::size_t Index(ShapeType type) { return static_cast<std::size_t>(type); }
  const Slot& Entry(ShapeType a, ShapeType b) const { return collide_[Index(a)][Index(b)]; }
  Slot& Entry(ShapeType a, ShapeType b) { return collide_[Index(a)][Index(b)]; }

  std::array<std::array<Slot, kMaxShapeTypes>, kMaxShapeTypes> collide_{};
  std::array<CastFunction, kMaxShapeTypes> cast_{};
  std::array<SweepFunction, kMaxShapeTypes> sweep_{};
  std::vector<ShapeType> convex_;
  std::vector<ShapeType> triangle_;
  std::vector<CollideFunction> triangle_collide_;  // parallel to triangle_
};

}  // namespace strata
