#include "physics/narrowphase/Epa.h"

#include <vector>

namespace strata {

namespace {

using Face = EpaFace;

SimplexVertex SupportVertex(const ConvexSupport& a, const ConvexSupport& b, const Vec3& direction) {
  SimplexVertex v;
  v.a = a.Support(direction);
  v.b = b.Support(-direction);
  v.w = v.a - v.b;
  return v;
}

// Grows a GJK simplex of 1-3 vertices into a tetrahedron that has volume.
bool CompleteTetrahedron(const ConvexSupport& a, const ConvexSupport& b,
                         std::vector<SimplexVertex>& vertices) {
  static const Vec3 kDirections[] = {Vec3::UnitX(),   -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(),
                                     Vec3::UnitZ(),   -Vec3::UnitZ(), Vec3(1, 1, 1), Vec3(-1, -1, 1),
                                     Vec3(1, -1, -1), Vec3(-1, 1, -1)};
  auto spans_more = [&](const Vec3& w) {
    switch (vertices.size()) {
      case 1:
        return (w - vertices[0].w).squaredNorm() > 1e-10f;
      case 2:
        return (w - vertices[0].w).cross(vertices[1].w - vertices[0].w).squaredNorm() > 1e-12f;
      default: {
        const Vec3 normal = (vertices[1].w - vertices[0].w).cross(vertices[2].w - vertices[0].w);
        return std::abs(normal.dot(w - vertices[0].w)) > 1e-9f * std::max(1.0f, normal.norm());
      }
    }
  };
  for (const Vec3& direction : kDirections) {
    if (vertices.size() == 4) break;
    for (float sign : {1.0f, -1.0f}) {
      const SimplexVertex candidate = SupportVertex(a, b, sign * direction);
      if (spans_more(candidate.w)) {
        vertices.push_back(candidate);
        break;
      }
    }
  }
  return vertices.size() == 4;
}

// The normal, depth and witness points of `closest`, the polytope's face nearest the origin: the
// barycentric coordinates of the origin's projection on it weigh the support points of each shape.
void WitnessPoints(const Face& closest, const std::vector<SimplexVertex>& vertices, PenetrationResult& out) {
  const Vec3 projection = closest.normal * closest.distance;
  const Vec3& p0 = vertices[closest.a].w;
  const Vec3 v0 = vertices[closest.b].w - p0, v1 = vertices[closest.c].w - p0, v2 = projection - p0;
  const float d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const float denominator = d00 * d11 - d01 * d01;
  float u = 1.0f / 3.0f, v = 1.0f / 3.0f;
  if (std::abs(denominator) > 1e-20f) {
    u = (d11 * d20 - d01 * d21) / denominator;
    v = (d00 * d21 - d01 * d20) / denominator;
  }
  const float w = 1.0f - u - v;
  out.normal = closest.normal;
  out.depth = std::max(0.0f, closest.distance);
  out.point_a = w * vertices[closest.a].a + u * vertices[closest.b].a + v * vertices[closest.c].a;
  out.point_b = w * vertices[closest.a].b + u * vertices[closest.b].b + v * vertices[closest.c].b;
}

}  // namespace

bool EpaPenetration(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk,
                    PenetrationResult& out) {
  EpaScratch scratch;
  return EpaPenetration(a, b, gjk, out, scratch);
}

bool EpaPenetration(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk,
                    PenetrationResult& out, EpaScratch& scratch) {
  std::vector<SimplexVertex>& vertices = scratch.vertices;
  std::vector<Face>& faces = scratch.faces;
  std::vector<std::pair<int, int>>& horizon = scratch.horizon;
  vertices.assign(gjk.simplex, gjk.simplex + gjk.simplex_count);
  if (vertices.empty()) vertices.push_back(SupportVertex(a, b, Vec3::UnitX()));
  if (vertices.size() < 4 && !CompleteTetrahedron(a, b, vertices)) return false;

  faces.clear();
  const Vec3 interior = (vertices[0].w + vertices[1].w + vertices[2].w + vertices[3].w) * 0.25f;
  auto add_face = [&](int i, int j, int k) {
    Vec3 normal = (vertices[j].w - vertices[i].w).cross(vertices[k].w - vertices[i].w);
    const float length = normal.norm();
    if (length < 1e-12f) return false;
    normal /= length;
    // Orient outwards relative to a point known to be inside the polytope.
    if (normal.dot(vertices[i].w - interior) < 0.0f) {
      std::swap(j, k);
      normal = -normal;
    }
    faces.push_back({i, j, k, normal, normal.dot(vertices[i].w), true});
    return true;
  };
  add_face(0, 1, 2);
  add_face(0, 3, 1);
  add_face(0, 2, 3);
  add_face(1, 3, 2);
  if (faces.size() < 4) return false;

  constexpr int kMaxIterations = 64;
  const Face* closest = nullptr;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    closest = nullptr;
    for (const Face& face : faces)
      if (face.alive && (!closest || face.distance < closest->distance)) closest = &face;
    if (!closest) return false;
    const SimplexVertex support = SupportVertex(a, b, closest->normal);
    const float gain = closest->normal.dot(support.w) - closest->distance;
    if (gain < 1e-4f * std::max(1.0f, closest->distance)) break;

    const int new_index = static_cast<int>(vertices.size());
    vertices.push_back(support);
    // Remove the faces the new point sees and keep the horizon (edges with one removed side).
    horizon.clear();
    for (Face& face : faces) {
      if (!face.alive || face.normal.dot(support.w - vertices[face.a].w) <= 0.0f) continue;
      face.alive = false;
      const int edge[3][2] = {{face.a, face.b}, {face.b, face.c}, {face.c, face.a}};
      for (const auto& e : edge) {
        auto reverse = std::find(horizon.begin(), horizon.end(), std::make_pair(e[1], e[0]));
        if (reverse != horizon.end())
          horizon.erase(reverse);
        else
          horizon.emplace_back(e[0], e[1]);
      }
    }
    for (const auto& [from, to] : horizon) add_face(from, to, new_index);
    closest = nullptr;
  }
  if (!closest) {
    for (const Face& face : faces)
      if (face.alive && (!closest || face.distance < closest->distance)) closest = &face;
    if (!closest) return false;
  }

  WitnessPoints(*closest, vertices, out);
  return true;
}

}  // namespace strata
