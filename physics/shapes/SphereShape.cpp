#include "physics/shapes/SphereShape.h"

namespace strata {

Result<ShapeRef> SphereShape::Create(float radius) {
  if (!IsFinite(radius) || radius <= 0.0f)
    return MakeError(ErrorCode::kDegenerateShape,
                     "sphere radius must be a positive finite number, got " + std::to_string(radius));
  return ShapeRef(std::make_shared<SphereShape>(radius));
}

MassProperties SphereShape::ComputeMassProperties(float density) const {
  MassProperties properties;
  properties.mass = density * 4.0f / 3.0f * kPi * radius_ * radius_ * radius_;
  properties.inertia = Mat3::Identity() * (0.4f * properties.mass * radius_ * radius_);
  return properties;
}

float RaySphere(const Vec3& origin, const Vec3& direction, const Vec3& center, float radius) {
  const Vec3 offset = origin - center;
  const float c = offset.squaredNorm() - radius * radius;
  if (c <= 0.0f) return 0.0f;  // starts inside
  const float a = direction.squaredNorm();
  const float b = offset.dot(direction);
  if (b >= 0.0f || a == 0.0f) return -1.0f;
  const float discriminant = b * b - a * c;
  if (discriminant < 0.0f) return -1.0f;
  return (-b - std::sqrt(discriminant)) / a;
}

bool SphereShape::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                          ShapeRayHit& hit) const {
  const float fraction = RaySphere(origin, direction, Vec3::Zero(), radius_);
  if (fraction < 0.0f || fraction > max_fraction) return false;
  hit.fraction = fraction;
  const Vec3 point = origin + fraction * direction;
  hit.normal = point.squaredNorm() > 0.0f ? point.normalized() : Vec3(-direction.normalized());
  hit.sub_shape = 0;
  return true;
}

Vec3 SphereShape::Support(const Vec3& direction) const {
  const float length = direction.norm();
  return length > 0.0f ? Vec3(direction * (radius_ / length)) : Vec3(radius_, 0, 0);
}

void SphereShape::GetSupportingFace(const Vec3& direction, SupportingFace& face) const {
  face.count = 0;
  face.normal = Vec3::Zero();
  face.Add(Support(direction));
}

void TessellateRoundShape(float radius, float half_height, std::vector<Triangle>& out) {
  constexpr int kSlices = 12;
  constexpr int kStacks = 6;  // per hemisphere
  auto point = [&](int stack, int slice) {
    // stack 0 = top pole, 2*kStacks = bottom pole; the equator is duplicated to make the cylinder.
    const bool upper = stack <= kStacks;
    const float polar = kPi * 0.5f * static_cast<float>(upper ? stack : stack - 1) / kStacks;
    const float azimuth = 2.0f * kPi * static_cast<float>(slice) / kSlices;
    const float ring = radius * std::sin(polar);
    const float y = radius * std::cos(polar) + (upper ? half_height : -half_height);
    return Vec3(ring * std::cos(azimuth), y, ring * std::sin(azimuth));
  };
  const int rows = 2 * kStacks + 1;
  for (int stack = 0; stack < rows; ++stack) {
    for (int slice = 0; slice < kSlices; ++slice) {
      const Vec3 a = point(stack, slice), b = point(stack, slice + 1);
      const Vec3 c = point(stack + 1, slice), d = point(stack + 1, slice + 1);
      if ((a - b).squaredNorm() > 1e-12f) out.push_back({{a, b, c}});
      if ((c - d).squaredNorm() > 1e-12f) out.push_back({{b, d, c}});
    }
  }
}

void SphereShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  if (!LocalBounds().Overlaps(local_box)) return;
  TessellateRoundShape(radius_, 0.0f, out);
}

}  // namespace strata
