#include "physics/shapes/ConvexHullShape.h"

#include <algorithm>
#include <map>

namespace strata {

Result<ShapeRef> ConvexHullShape::Create(std::span<const Vec3> points) {
  auto hull = BuildConvexHull(points);
  if (!hull) return hull.error();
  Vec3 interior = Vec3::Zero();
  for (const Vec3& v : hull->vertices) interior += v;
  interior /= static_cast<float>(hull->vertices.size());
  float min_face_distance = kLargeFloat;
  for (const HullFace& face : hull->faces)
    min_face_distance = std::min(min_face_distance, face.offset - face.normal.dot(interior));
  if (!(min_face_distance > 1e-6f))
    return MakeError(ErrorCode::kDegenerateShape, "convex hull is too thin to have an interior");
  const float core_radius = std::min(0.05f, 0.2f * min_face_distance);
  const float core_scale = 1.0f - core_radius / min_face_distance;
  return ShapeRef(std::make_shared<ConvexHullShape>(std::move(*hull), interior, core_radius, core_scale));
}

ConvexHullShape::ConvexHullShape(HullData hull, const Vec3& interior_point, float core_radius,
                                 float core_scale)
    : ConvexShape(ShapeType::kConvexHull, core_radius),
      hull_(std::move(hull)),
      interior_point_(interior_point),
      core_scale_(core_scale) {
  for (const Vec3& v : hull_.vertices) bounds_.Encapsulate(v);
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

Vec3 ConvexHullShape::Support(const Vec3& direction) const {
  const Vec3* best = &hull_.vertices[0];
  float best_dot = best->dot(direction);
  for (const Vec3& v : hull_.vertices) {
    const float d = v.dot(direction);
    if (d > best_dot) best_dot = d, best = &v;
  }
  return *best;
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
