#include "physics/shapes/BoxShape.h"

#include <cmath>
#include <string>

namespace strata {

namespace {
// A sharp box still gives GJK a core this much smaller, so touching boxes keep their cores apart.
float SharpCoreRadius(const Vec3& half_extents) {
  return BoxShape::DefaultConvexRadius(half_extents);
}

Vec3 SignedCorner(const Vec3& half, const Vec3& direction) {
  return {direction.x() < 0 ? -half.x() : half.x(), direction.y() < 0 ? -half.y() : half.y(),
          direction.z() < 0 ? -half.z() : half.z()};
}
}  // namespace

float BoxShape::DefaultConvexRadius(const Vec3& half_extents) {
  return std::min(kDefaultConvexRadius, kMaxDefaultRadiusShare * half_extents.minCoeff());
}

Result<ShapeRef> BoxShape::Create(const Vec3& half_extents) {
  if (!IsFinite(half_extents) || half_extents.minCoeff() <= 0.0f)
    return MakeError(ErrorCode::kDegenerateShape, "box half extents must be positive finite numbers");
  return ShapeRef(std::make_shared<BoxShape>(half_extents, DefaultConvexRadius(half_extents)));
}

Result<ShapeRef> BoxShape::Create(const Vec3& half_extents, float convex_radius) {
  if (!IsFinite(half_extents) || half_extents.minCoeff() <= 0.0f)
    return MakeError(ErrorCode::kDegenerateShape, "box half extents must be positive finite numbers");
  if (!std::isfinite(convex_radius) || convex_radius < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "box convex radius must be a finite number >= 0");
  if (convex_radius > half_extents.minCoeff())
    return MakeError(ErrorCode::kInvalidArgument, "box convex radius " + std::to_string(convex_radius) +
                                                      " is over its smallest half extent " +
                                                      std::to_string(half_extents.minCoeff()));
  return ShapeRef(std::make_shared<BoxShape>(half_extents, convex_radius));
}

BoxShape::BoxShape(const Vec3& half_extents, float convex_radius)
    : ConvexShape(ShapeType::kBox, convex_radius > 0.0f ? convex_radius : SharpCoreRadius(half_extents),
                  convex_radius > 0.0f),
      half_extents_(half_extents),
      core_half_extents_(half_extents.array() - core_radius()) {}

MassProperties BoxShape::ComputeMassProperties(float density) const {
  MassProperties properties;
  const Vec3 size = 2.0f * half_extents_;
  properties.mass = density * size.prod();
  const Vec3 sq = size.cwiseProduct(size);
  properties.inertia =
      (properties.mass / 12.0f * Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y())).asDiagonal();
  return properties;
}

bool BoxShape::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                       ShapeRayHit& hit) const {
  if (!CastRaySharp(origin, direction, max_fraction, hit)) return false;
  if (!CoreIsExact()) return true;
  const ShapeRayHit sharp = hit;
  const auto closest_on_core = [this](const Vec3& point) {
    return Vec3(point.cwiseMax(-core_half_extents_).cwiseMin(core_half_extents_));
  };
  return CastRayRounded(origin, direction, max_fraction, sharp, closest_on_core, hit);
}

bool BoxShape::CastRaySharp(const Vec3& origin, const Vec3& direction, float max_fraction,
                            ShapeRayHit& hit) const {
  const AABB box = LocalBounds();
  const float fraction = box.RayEntry(origin, SafeInverse(direction), max_fraction);
  if (fraction < 0.0f) return false;
  hit.fraction = fraction;
  hit.sub_shape = 0;
  if (fraction == 0.0f && box.Contains(origin)) {
    hit.normal = -direction.normalized();
    return true;
  }
  // The entry face is the one the hit point lies on, relative to the half extents.
  const Vec3 point = origin + fraction * direction;
  const Vec3 relative = point.cwiseQuotient(half_extents_);
  int axis = 0;
  relative.cwiseAbs().maxCoeff(&axis);
  hit.normal = Vec3::Zero();
  hit.normal[axis] = relative[axis] < 0 ? -1.0f : 1.0f;
  return true;
}

Vec3 BoxShape::Support(const Vec3& direction) const {
  if (!CoreIsExact()) return SignedCorner(half_extents_, direction);
  const float length = direction.norm();
  const Vec3 corner = SignedCorner(core_half_extents_, direction);
  return length > 0.0f ? Vec3(corner + (core_radius() / length) * direction) : corner;
}
Vec3 BoxShape::CoreSupport(const Vec3& direction) const {
  return SignedCorner(core_half_extents_, direction);
}

void BoxShape::GetSupportingFace(const Vec3& direction, SupportingFace& face) const {
  face.count = 0;
  int axis = 0;
  direction.cwiseAbs().maxCoeff(&axis);
  const float sign = direction[axis] < 0 ? -1.0f : 1.0f;
  face.normal = Vec3::Zero();
  face.normal[axis] = sign;
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i) {
    // Counter-clockwise seen from outside: reverse the winding on the negative face.
    const int k = sign > 0 ? i : 3 - i;
    Vec3 vertex;
    vertex[axis] = sign * half_extents_[axis];
    vertex[u] = corners[k][0] * half_extents_[u];
    vertex[v] = corners[k][1] * half_extents_[v];
    face.Add(vertex);
  }
}

void BoxShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  if (!LocalBounds().Overlaps(local_box)) return;
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      Vec3 direction = Vec3::Zero();
      direction[axis] = sign;
      SupportingFace face;
      GetSupportingFace(direction, face);
      out.push_back({{face.vertices[0], face.vertices[1], face.vertices[2]}});
      out.push_back({{face.vertices[0], face.vertices[2], face.vertices[3]}});
    }
  }
}

}  // namespace strata
