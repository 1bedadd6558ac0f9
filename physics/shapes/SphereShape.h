// SphereShape: a sphere around the local origin. Immutable; thread-safe.
#pragma once

#include "physics/core/Result.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

/// Sphere of `radius` metres centred on the local origin.
class SphereShape final : public ConvexShape {
 public:
  /// Fails for a non-finite or non-positive radius.
  static Result<ShapeRef> Create(float radius);
  explicit SphereShape(float radius) : ConvexShape(ShapeType::kSphere, radius, true), radius_(radius) {}

  float radius() const { return radius_; }

  AABB LocalBounds() const override { return {Vec3::Constant(-radius_), Vec3::Constant(radius_)}; }
  bool BoundsTurnWithBody() const override { return false; }
  MassProperties ComputeMassProperties(float density) const override;
  bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
               ShapeRayHit& hit) const override;
  Vec3 Support(const Vec3& direction) const override;
  Vec3 CoreSupport(const Vec3&) const override { return Vec3::Zero(); }
  void GetSupportingFace(const Vec3& direction, SupportingFace& face) const override;

 protected:
  void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const override;

 private:
  float radius_;
};

/// Ray against a sphere at `center`; shared by sphere and capsule casts. Returns fraction or -1.
float RaySphere(const Vec3& origin, const Vec3& direction, const Vec3& center, float radius);

/// Appends a UV-sphere (or capsule when half_height > 0, along Y) tessellation for navmesh gathering.
void TessellateRoundShape(float radius, float half_height, std::vector<Triangle>& out);

}  // namespace strata
