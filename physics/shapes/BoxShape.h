// BoxShape: a box centred on the local origin with given half extents. Immutable; thread-safe.
#pragma once

#include "physics/core/Result.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

/// Box with `half_extents` (m) along the local axes, its edges and corners rounded by a convex radius that
/// stays inside those extents (Jolt's convention): the faces stay where the half extents put them. GJK runs
/// on the core, the box shrunk by the radius. A sharp box (radius 0) keeps a small core radius inside for GJK
/// and has its contacts from the separating-axis test instead.
class BoxShape final : public ConvexShape {
 public:
  /// Fails for non-finite or non-positive half extents. The box is rounded by DefaultConvexRadius.
  static Result<ShapeRef> Create(const Vec3& half_extents);
  /// Fails as above, and for a convex radius that is negative, not finite, or over the smallest half extent.
  static Result<ShapeRef> Create(const Vec3& half_extents, float convex_radius);
  /// kDefaultConvexRadius, or a quarter of the smallest half extent where that is less.
  static float DefaultConvexRadius(const Vec3& half_extents);
  /// Unchecked: the Create forms say what they need.
  BoxShape(const Vec3& half_extents, float convex_radius);

  /// Corner c of the box has the signs of its coordinates in its bits (bit 0: x, bit 1: y, bit 2: z); face f
  /// (-x, +x, -y, +y, -z, +z) lists its corners counter-clockwise seen from outside.
  static constexpr int kFaceCorners[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};

  const Vec3& half_extents() const { return half_extents_; }

  AABB LocalBounds() const override { return {-half_extents_, half_extents_}; }
  MassProperties ComputeMassProperties(float density) const override;
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;
  Vec3 Support(const Vec3& direction) const override;
  Vec3 CoreSupport(const Vec3& direction) const override;
  /// The face of the box, flat part and rounding together, as Jolt takes it for clipping manifolds.
  void GetSupportingFace(const Vec3& direction, SupportingFace& face) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  bool CastRaySharp(const Vec3& origin, const Vec3& direction, float max_fraction, ShapeRayHit& hit) const;

  Vec3 half_extents_;
  Vec3 core_half_extents_;
};

}  // namespace strata
