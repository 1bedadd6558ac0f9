#include "physics/shapes/ConvexHullShape.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>

namespace strata {

namespace {

// A sharp hull's core keeps every face at least this share of the interior's depth in.
constexpr float kSharpCoreShare = 0.2f;
// How far past a moved-in face plane a core corner may lie (m): float rounding, not a fold.
constexpr float kCoreTolerance = 1e-5f;

// The hull with every face plane moved in by `radius`: the intersection of the moved half-spaces, found as
// the dual of the hull of the planes' dual points (each plane n . (x - c) = e maps to n / e; each face of
// their hull, m . q = k, to the vertex c + m / k where its planes meet), with its own faces. No vertices when
// either hull cannot be built.
HullData MovedInCore(const HullData& hull, const Vec3& interior, float radius) {
  std::vector<Vec3> dual;
  dual.reserve(hull.faces.size());
  for (const HullFace& face : hull.faces)
    dual.push_back(face.normal / (face.offset - face.normal.dot(interior) - radius));
  const Result<HullData> dual_hull = BuildConvexHull(dual);
  if (!dual_hull) return {};
  std::vector<Vec3> corners;
  corners.reserve(dual_hull->faces.size());
  for (const HullFace& face : dual_hull->faces) {
    if (!(face.offset > 0.0f)) return {};
    corners.push_back(interior + face.normal / face.offset);
  }
  // Nearly parallel faces put their dual points close together, where the dual hull can come out folded:
  // a corner outside a moved-in plane means it did.
  for (const Vec3& corner : corners)
    for (const HullFace& face : hull.faces)
      if (face.normal.dot(corner) > face.offset - radius + kCoreTolerance) return {};
  Result<HullData> core = BuildConvexHull(corners);
  return core ? std::move(*core) : HullData{};
}

// The hull scaled towards `interior` until every face is at least `radius` in: inside the moved-in core, so
// the rounded shape stays inside the hull, a little smaller where faces lie farther from the interior point.
HullData ScaledCore(const HullData& hull, const Vec3& interior, float scale) {
  std::vector<Vec3> corners;
  corners.reserve(hull.vertices.size());
  for (const Vec3& v : hull.vertices) corners.push_back(interior + scale * (v - interior));
  Result<HullData> core = BuildConvexHull(corners);
  return core ? std::move(*core) : HullData{};
}

// The hull of `points`, rounded by `convex_radius` or, unset, by the default for its size.
Result<ShapeRef> MakeHull(std::span<const Vec3> points, std::optional<float> convex_radius) {
  if (convex_radius && (!std::isfinite(*convex_radius) || *convex_radius < 0.0f))
    return MakeError(ErrorCode::kInvalidArgument, "hull convex radius must be a finite number >= 0");
  auto hull = BuildConvexHull(points);
  if (!hull) return hull.error();
  Vec3 interior = Vec3::Zero();
  for (const Vec3& v : hull->vertices) interior += v;
  interior /= static_cast<float>(hull->vertices.size());
  float depth = kLargeFloat;  // from the interior point to the nearest face
  for (const HullFace& face : hull->faces) depth = std::min(depth, face.offset - face.normal.dot(interior));
  if (!(depth > 1e-6f))
    return MakeError(ErrorCode::kDegenerateShape, "convex hull is too thin to have an interior");
  const float radius =
      convex_radius.value_or(std::min(kDefaultConvexRadius, ConvexShape::kMaxDefaultRadiusShare * depth));
  if (radius > 0.5f * depth)
    return MakeError(ErrorCode::kInvalidArgument, "hull convex radius " + std::to_string(radius) +
                                                      " is over half the depth of its interior " +
                                                      std::to_string(depth));
  HullData core;
  if (radius > 0.0f) core = MovedInCore(*hull, interior, radius);
  if (radius > 0.0f && core.vertices.empty()) core = ScaledCore(*hull, interior, 1.0f - radius / depth);
  // A sharp hull (or, were the scaled hull to fail too, one that cannot be rounded) scales its core.
  const float core_radius =
      core.vertices.empty() ? std::min(kDefaultConvexRadius, kSharpCoreShare * depth) : radius;
  const float core_scale = 1.0f - core_radius / depth;
  return ShapeRef(std::make_shared<ConvexHullShape>(std::move(*hull), interior, core_radius, core_scale,
                                                    std::move(core)));
}

}  // namespace

Result<ShapeRef> ConvexHullShape::Create(std::span<const Vec3> points) {
  return MakeHull(points, std::nullopt);
}

Result<ShapeRef> ConvexHullShape::Create(std::span<const Vec3> points, float convex_radius) {
  return MakeHull(points, convex_radius);
}

ConvexHullShape::ConvexHullShape(HullData hull, const Vec3& interior_point, float core_radius,
                                 float core_scale, HullData rounded_core)
    : ConvexShape(ShapeType::kConvexHull, core_radius, !rounded_core.vertices.empty()),
      hull_(std::move(hull)),
      interior_point_(interior_point),
      core_scale_(core_scale),
      core_(std::move(rounded_core)) {
  if (CoreIsExact()) {
    // The rounded shape reaches the radius past its core, short of a sharp corner that sticks out further.
    for (const Vec3& v : core_.vertices) bounds_.Encapsulate(v);
    bounds_ = bounds_.Expanded(core_radius);
  } else {
    for (const Vec3& v : hull_.vertices) bounds_.Encapsulate(v);
  }
  // Each directed edge belongs to exactly one face's loop; its reverse to the face across the edge.
  std::map<std::pair<int, int>, int> face_of_directed_edge;
  for (std::size_t f = 0; f < hull_.faces.size(); ++f) {
    const std::vector<int>& loop = hull_.faces[f].vertices;
    for (std::size_t i = 0; i < loop.size(); ++i)
      face_of_directed_edge[{loop[i], loop[(i + 1) % loop.size()]}] = static_cast<int>(f);
  }
  for (std::size_t f = 0; f < hull_.faces.size(); ++f) {
    const HullFace& face = hull_.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      const int from = face.vertices[i], to = face.vertices[(i + 1) % face.vertices.size()];
      if (from > to) continue;  // a closed hull lists every edge once in each direction
      edges_.push_back({from, to});
      const auto across = face_of_directed_edge.find({to, from});
      edge_faces_.push_back(
          {static_cast<int>(f), across != face_of_directed_edge.end() ? across->second : -1});
      const Vec3 direction = (hull_.vertices[to] - hull_.vertices[from]).normalized();
      const bool known = std::any_of(edge_directions_.begin(), edge_directions_.end(),
                                     [&](const Vec3& d) { return std::abs(d.dot(direction)) > 0.9999f; });
      if (!known) edge_directions_.push_back(direction);
    }
  }
}

MassProperties ConvexHullShape::ComputeMassProperties(float density) const {
  // Sum signed tetrahedra (interior point, triangle) using the canonical second-moment matrix.
  Mat3 canonical;
  canonical << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  canonical /= 120.0f;
  float volume = 0.0f;
  Vec3 first_moment = Vec3::Zero();
  Mat3 covariance = Mat3::Zero();
  const Vec3 origin = interior_point_;
  for (const HullFace& face : hull_.faces) {
    const Vec3 a = hull_.vertices[face.vertices[0]] - origin;
    for (std::size_t i = 1; i + 1 < face.vertices.size(); ++i) {
      Mat3 columns;
      columns.col(0) = a;
      columns.col(1) = hull_.vertices[face.vertices[i]] - origin;
      columns.col(2) = hull_.vertices[face.vertices[i + 1]] - origin;
      const float determinant = columns.determinant();
      volume += determinant / 6.0f;
      first_moment += determinant / 24.0f * (columns.col(0) + columns.col(1) + columns.col(2));
      covariance += determinant * columns * canonical * columns.transpose();
    }
  }
  MassProperties properties;
  properties.mass = density * volume;
  const Vec3 center = first_moment / volume;  // relative to origin
  // Shift the second moment to the centre of mass, then convert to an inertia tensor.
  const Mat3 central = density * covariance - properties.mass * center * center.transpose();
  properties.inertia = Mat3::Identity() * central.trace() - central;
  properties.center_of_mass = center + origin;
  return properties;
}

bool ConvexHullShape::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                              ShapeRayHit& hit) const {
  if (!CastRaySharp(origin, direction, max_fraction, hit)) return false;
  if (!CoreIsExact()) return true;
  const ShapeRayHit sharp = hit;
  const auto closest_on_core = [this](const Vec3& point) { return ClosestOnCore(point); };
  return CastRayRounded(origin, direction, max_fraction, sharp, closest_on_core, hit);
}

bool ConvexHullShape::CastRaySharp(const Vec3& origin, const Vec3& direction, float max_fraction,
                                   ShapeRayHit& hit) const {
  float enter = 0.0f, leave = max_fraction;
  Vec3 normal = -direction.normalized();
  for (const HullFace& face : hull_.faces) {
    const float distance = face.normal.dot(origin) - face.offset;
    const float speed = face.normal.dot(direction);
    if (speed == 0.0f) {
      if (distance > 0.0f) return false;
      continue;
    }
    const float t = -distance / speed;
    if (speed < 0.0f) {
      if (t > enter) enter = t, normal = face.normal;
    } else {
      leave = std::min(leave, t);
    }
    if (enter > leave) return false;
  }
  hit.fraction = enter;
  hit.normal = normal;
  hit.sub_shape = 0;
  return true;
}

Vec3 ConvexHullShape::Farthest(const std::vector<Vec3>& points, const Vec3& direction) {
  const Vec3* best = &points[0];
  float best_dot = best->dot(direction);
  for (const Vec3& v : points) {
    const float d = v.dot(direction);
    if (d > best_dot) best_dot = d, best = &v;
  }
  return *best;
}

Vec3 ConvexHullShape::ClosestOnCore(const Vec3& point) const {
  // Outside a convex polyhedron, the nearest point lies on a face the point is in front of: the nearest of
  // those faces' nearest points. A point in front of none is inside.
  Vec3 closest = point;
  float closest_distance = kLargeFloat;
  for (const HullFace& face : core_.faces) {
    const float height = face.normal.dot(point) - face.offset;
    if (height <= 0.0f) continue;
    Vec3 on_face = point - height * face.normal;
    const std::size_t count = face.vertices.size();
    bool inside = true;
    for (std::size_t i = 0; i < count && inside; ++i) {
      const Vec3& from = core_.vertices[face.vertices[i]];
      const Vec3& to = core_.vertices[face.vertices[(i + 1) % count]];
      inside = (to - from).cross(face.normal).dot(on_face - from) <= 0.0f;
    }
    if (!inside) {
      float best = kLargeFloat;
      for (std::size_t i = 0; i < count; ++i) {
        const Vec3& from = core_.vertices[face.vertices[i]];
        const Vec3 edge = core_.vertices[face.vertices[(i + 1) % count]] - from;
        const float t = std::clamp(edge.dot(point - from) / std::max(edge.squaredNorm(), 1e-20f), 0.0f, 1.0f);
        const Vec3 on_edge = from + t * edge;
        const float distance = (point - on_edge).squaredNorm();
        if (distance < best) best = distance, on_face = on_edge;
      }
    }
    const float distance = (point - on_face).squaredNorm();
    if (distance < closest_distance) closest_distance = distance, closest = on_face;
  }
  return closest;
}

Vec3 ConvexHullShape::Support(const Vec3& direction) const {
  if (!CoreIsExact()) return Farthest(hull_.vertices, direction);
  const float length = direction.norm();
  const Vec3 core = Farthest(core_.vertices, direction);
  return length > 0.0f ? Vec3(core + (core_radius() / length) * direction) : core;
}

Vec3 ConvexHullShape::CoreSupport(const Vec3& direction) const {
  if (CoreIsExact()) return Farthest(core_.vertices, direction);
  return interior_point_ + core_scale_ * (Farthest(hull_.vertices, direction) - interior_point_);
}

void ConvexHullShape::GetSupportingFace(const Vec3& direction, SupportingFace& face) const {
  const HullFace* best = &hull_.faces[0];
  float best_dot = best->normal.dot(direction);
  for (const HullFace& f : hull_.faces) {
    const float d = f.normal.dot(direction);
    if (d > best_dot) best_dot = d, best = &f;
  }
  face.count = 0;
  face.normal = best->normal;
  for (int v : best->vertices) face.Add(hull_.vertices[v]);
}

void ConvexHullShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  if (!bounds_.Overlaps(local_box)) return;
  for (const HullFace& face : hull_.faces)
    for (std::size_t i = 1; i + 1 < face.vertices.size(); ++i)
      out.push_back({{hull_.vertices[face.vertices[0]], hull_.vertices[face.vertices[i]],
                      hull_.vertices[face.vertices[i + 1]]}});
}

}  // namespace strata
