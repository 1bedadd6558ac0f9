#include "physics/shapes/CapsuleShape.h"

#include <string>

#include "physics/shapes/SphereShape.h"

namespace strata {

Result<ShapeRef> CapsuleShape::Create(float half_height, float radius) {
  if (!IsFinite(radius) || !IsFinite(half_height) || radius <= 0.0f || half_height < 0.0f)
    return MakeError(ErrorCode::kDegenerateShape,
                     "capsule needs a positive radius and a non-negative half height, got radius " +
                         std::to_string(radius) + ", half height " + std::to_string(half_height));
  return ShapeRef(std::make_shared<CapsuleShape>(half_height, radius));
}

MassProperties CapsuleShape::ComputeMassProperties(float density) const {
  const float r2 = radius_ * radius_;
  const float height = 2.0f * half_height_;
  const float cylinder_mass = density * kPi * r2 * height;
  const float hemispheres_mass = density * 4.0f / 3.0f * kPi * r2 * radius_;
  const float axial = cylinder_mass * r2 * 0.5f + hemispheres_mass * 0.4f * r2;
  // Each hemisphere's own transverse inertia plus the parallel-axis term for its offset from the centre.
  const float transverse =
      cylinder_mass * (r2 / 4.0f + height * height / 12.0f) +
      hemispheres_mass * (0.4f * r2 + height * height / 4.0f + 3.0f * height * radius_ / 8.0f);
  MassProperties properties;
  properties.mass = cylinder_mass + hemispheres_mass;
  properties.inertia = Vec3(transverse, axial, transverse).asDiagonal();
  return properties;
}

bool CapsuleShape::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                           ShapeRayHit& hit) const {
  float best = -1.0f;
  Vec3 best_center = Vec3::Zero();
  // Infinite cylinder around Y, clipped to the segment.
  const float a = direction.x() * direction.x() + direction.z() * direction.z();
  const float b = origin.x() * direction.x() + origin.z() * direction.z();
  const float c = origin.x() * origin.x() + origin.z() * origin.z() - radius_ * radius_;
  if (c <= 0.0f && std::abs(origin.y()) <= half_height_) {
    best = 0.0f;
  } else if (a > 0.0f && b * b - a * c >= 0.0f) {
    const float t = (-b - std::sqrt(b * b - a * c)) / a;
    const float y = origin.y() + t * direction.y();
    if (t >= 0.0f && std::abs(y) <= half_height_) {
      best = t;
      best_center = Vec3(0, y, 0);
    }
  }
  for (float end : {-half_height_, half_height_}) {
    const float t = RaySphere(origin, direction, Vec3(0, end, 0), radius_);
    if (t >= 0.0f && (best < 0.0f || t < best)) {
      best = t;
      best_center = Vec3(0, end, 0);
    }
  }
  if (best < 0.0f || best > max_fraction) return false;
  hit.fraction = best;
  hit.sub_shape = 0;
  const Vec3 offset = origin + best * direction - best_center;
  hit.normal = offset.squaredNorm() > 1e-12f ? offset.normalized() : Vec3(-direction.normalized());
  return true;
}

Vec3 CapsuleShape::Support(const Vec3& direction) const {
  const float length = direction.norm();
  const Vec3 round = length > 0.0f ? Vec3(direction * (radius_ / length)) : Vec3(radius_, 0, 0);
  return CoreSupport(direction) + round;
}

void CapsuleShape::GetSupportingFace(const Vec3& direction, SupportingFace& face) const {
  face.count = 0;
  face.normal = Vec3::Zero();
  const float length = direction.norm();
  if (length == 0.0f) return;
  const Vec3 unit = direction / length;
  // Lying (nearly) flat against the direction: the whole side line touches, which keeps a capsule on a
  // floor from rolling around a single contact point.
  if (std::abs(unit.y()) < 0.05f) {
    face.Add(Vec3(0, -half_height_, 0) + unit * radius_);
    face.Add(Vec3(0, half_height_, 0) + unit * radius_);
    return;
  }
  face.Add(Support(direction));
}

void CapsuleShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  if (!LocalBounds().Overlaps(local_box)) return;
  TessellateRoundShape(radius_, half_height_, out);
}

}  // namespace strata
