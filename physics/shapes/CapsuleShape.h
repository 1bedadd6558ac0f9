// CapsuleShape: a segment along local Y swept by a sphere. Immutable; thread-safe.
#pragma once

#include "physics/core/Result.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

/// Capsule whose core segment runs from (0,-half_height,0) to (0,half_height,0), radius `radius`.
class CapsuleShape final : public ConvexShape {
 public:
  /// Fails for non-finite values, a non-positive radius or a negative half height.
  static Result<ShapeRef> Create(float half_height, float radius);
  CapsuleShape(float half_height, float radius)
      : ConvexShape(ShapeType::kCapsule, radius, true), half_height_(half_height), radius_(radius) {}

  float half_height() const { return half_height_; }
  float radius() const { return radius_; }

  AABB LocalBounds() const override {
    const Vec3 half(radius_, half_height_ + radius_, radius_);
    return {-half, half};
  }
  MassProperties ComputeMassProperties(float density) const override;
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;
  /// A capsule's bounds stay its local box turned, looser than its core's box grown by the radius: tightening
  /// them reordered the chains bench's pairs into a far more stretched outcome at Jolt's passes (87 mm
  /// against 0.57 mm at the last step), which wants its own study before it changes.
  float BoundsRounding() const override { return 0.0f; }
  Vec3 Support(const Vec3& direction) const override;
  Vec3 CoreSupport(const Vec3& direction) const override {
    return {0.0f, direction.y() < 0 ? -half_height_ : half_height_, 0.0f};
  }
  void GetSupportingFace(const Vec3& direction, SupportingFace& face) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  float half_height_;
  float radius_;
};

}  // namespace strata
