#include "physics/shapes/QuickHull.h"

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <utility>

namespace strata {

namespace {

struct WorkFace {
  int a, b, c;
  Vec3 normal;
  float offset;
  std::vector<int> outside;  // points in front of this face
  bool alive = true;
};

WorkFace MakeFace(const std::vector<Vec3>& p, int a, int b, int c) {
  WorkFace face{a, b, c, (p[b] - p[a]).cross(p[c] - p[a]), 0.0f, {}, true};
  face.normal.normalize();
  face.offset = face.normal.dot(p[a]);
  return face;
}

float Distance(const WorkFace& face, const Vec3& point) {
  return face.normal.dot(point) - face.offset;
}

// Four points spanning the largest volume we can find cheaply; fails when the cloud is flat.
Result<std::array<int, 4>> InitialTetrahedron(const std::vector<Vec3>& p, float epsilon) {
  int lo = 0, hi = 0;
  for (int axis = 0; axis < 3 && lo == hi; ++axis) {
    lo = hi = 0;
    for (int i = 1; i < static_cast<int>(p.size()); ++i) {
      if (p[i][axis] < p[lo][axis]) lo = i;
      if (p[i][axis] > p[hi][axis]) hi = i;
    }
    if ((p[hi] - p[lo]).norm() <= epsilon) hi = lo;
  }
  if (lo == hi)
    return MakeError(ErrorCode::kDegenerateShape, "convex hull points are all (nearly) coincident");
  const Vec3 axis = (p[hi] - p[lo]).normalized();
  int third = -1;
  float best = epsilon;
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    const float d = (p[i] - p[lo]).cross(axis).norm();
    if (d > best) best = d, third = i;
  }
  if (third < 0) return MakeError(ErrorCode::kDegenerateShape, "convex hull points are collinear");
  const Vec3 normal = (p[hi] - p[lo]).cross(p[third] - p[lo]).normalized();
  int fourth = -1;
  best = epsilon;
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    const float d = std::abs(normal.dot(p[i] - p[lo]));
    if (d > best) best = d, fourth = i;
  }
  if (fourth < 0)
    return MakeError(ErrorCode::kDegenerateShape, "convex hull points are coplanar (no volume)");
  return std::array<int, 4>{lo, hi, third, fourth};
}

// Merges coplanar triangles into polygons by chaining each group's boundary edges.
std::vector<HullFace> MergeCoplanar(const std::vector<Vec3>& p, const std::vector<WorkFace>& triangles) {
  std::vector<HullFace> faces;
  std::vector<bool> used(triangles.size(), false);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (used[i]) continue;
    std::vector<std::size_t> group;
    for (std::size_t j = i; j < triangles.size(); ++j) {
      if (used[j]) continue;
      if (triangles[i].normal.dot(triangles[j].normal) > 0.9999f &&
          std::abs(triangles[i].offset - triangles[j].offset) <
              1e-4f * (1.0f + std::abs(triangles[i].offset))) {
        group.push_back(j);
        used[j] = true;
      }
    }
    std::map<std::pair<int, int>, int> edges;  // directed edge -> count
    for (std::size_t t : group) {
      const int v[3] = {triangles[t].a, triangles[t].b, triangles[t].c};
      for (int k = 0; k < 3; ++k) edges[{v[k], v[(k + 1) % 3]}]++;
    }
    std::map<int, int> next;
    for (const auto& [edge, count] : edges)
      if (!edges.count({edge.second, edge.first})) next[edge.first] = edge.second;
    HullFace face;
    Vec3 normal = Vec3::Zero();
    for (std::size_t t : group) normal += triangles[t].normal;
    face.normal = normal.normalized();
    const int start = next.begin()->first;
    int current = start;
    do {
      face.vertices.push_back(current);
      current = next[current];
    } while (current != start && face.vertices.size() <= next.size());
    float offset = 0.0f;
    for (int v : face.vertices) offset += face.normal.dot(p[v]);
    face.offset = offset / static_cast<float>(face.vertices.size());
    faces.push_back(std::move(face));
  }
  return faces;
}

// Gives `point` to the first live face of `candidates` it lies outside of (by more than `epsilon`).
void AssignOutside(std::vector<WorkFace>& faces, const std::vector<Vec3>& p, int point,
                   const std::vector<int>& candidates, float epsilon) {
  for (int f : candidates)
    if (faces[f].alive && Distance(faces[f], p[point]) > epsilon) {
      faces[f].outside.push_back(point);
      return;
    }
}

// One step of QuickHull: the farthest outside point of the first face that has one becomes a vertex, the
// faces it sees are replaced by a cone from it to their horizon. False when no point is outside.
bool AddFarthestPoint(const std::vector<Vec3>& p, float epsilon, std::vector<WorkFace>& faces) {
  int face_index = -1;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
    if (faces[f].alive && !faces[f].outside.empty()) {
      face_index = f;
      break;
    }
  if (face_index < 0) return false;
  int eye = faces[face_index].outside.front();
  for (int candidate : faces[face_index].outside)
    if (Distance(faces[face_index], p[candidate]) > Distance(faces[face_index], p[eye])) eye = candidate;

  std::vector<int> visible;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
    if (faces[f].alive && Distance(faces[f], p[eye]) > epsilon) visible.push_back(f);
  std::map<std::pair<int, int>, bool> visible_edges;
  for (int f : visible) {
    const int v[3] = {faces[f].a, faces[f].b, faces[f].c};
    for (int k = 0; k < 3; ++k) visible_edges[{v[k], v[(k + 1) % 3]}] = true;
  }
  std::vector<int> orphans;
  for (int f : visible) {
    faces[f].alive = false;
    for (int point : faces[f].outside)
      if (point != eye) orphans.push_back(point);
    faces[f].outside.clear();
  }
  std::vector<int> created;
  for (const auto& [edge, unused] : visible_edges) {
    if (visible_edges.count({edge.second, edge.first})) continue;  // interior of the visible region
    faces.push_back(MakeFace(p, edge.first, edge.second, eye));
    created.push_back(static_cast<int>(faces.size()) - 1);
  }
  for (int point : orphans) AssignOutside(faces, p, point, created, epsilon);
  return true;
}

// Keeps only the points that ended up as hull vertices, renumbered.
HullData Renumbered(const std::vector<Vec3>& p, std::vector<HullFace> merged) {
  HullData hull;
  std::map<int, int> remap;
  for (HullFace& face : merged) {
    for (int& v : face.vertices) {
      auto [it, inserted] = remap.emplace(v, static_cast<int>(hull.vertices.size()));
      if (inserted) hull.vertices.push_back(p[v]);
      v = it->second;
    }
  }
  hull.faces = std::move(merged);
  return hull;
}

}  // namespace

Result<HullData> BuildConvexHull(std::span<const Vec3> input) {
  for (std::size_t i = 0; i < input.size(); ++i)
    if (!IsFinite(input[i]))
      return MakeError(ErrorCode::kInvalidArgument,
                       "convex hull point " + std::to_string(i) + " is not finite");
  if (input.size() < 4)
    return MakeError(ErrorCode::kDegenerateShape,
                     "convex hull needs at least 4 points, got " + std::to_string(input.size()));
  const std::vector<Vec3> p(input.begin(), input.end());
  AABB bounds;
  for (const Vec3& v : p) bounds.Encapsulate(v);
  const float epsilon = 1e-5f * std::max(1.0f, bounds.Size().maxCoeff());

  auto tetra = InitialTetrahedron(p, epsilon);
  if (!tetra) return tetra.error();
  auto [i0, i1, i2, i3] = *tetra;
  // Orient the base so the fourth point is behind it.
  if ((p[i1] - p[i0]).cross(p[i2] - p[i0]).dot(p[i3] - p[i0]) > 0) std::swap(i1, i2);
  std::vector<WorkFace> faces = {MakeFace(p, i0, i1, i2), MakeFace(p, i0, i3, i1), MakeFace(p, i1, i3, i2),
                                 MakeFace(p, i2, i3, i0)};
  std::vector<int> all_faces = {0, 1, 2, 3};
  for (int i = 0; i < static_cast<int>(p.size()); ++i)
    if (i != i0 && i != i1 && i != i2 && i != i3) AssignOutside(faces, p, i, all_faces, epsilon);

  for (std::size_t iteration = 0; iteration < 4 * p.size() + 16; ++iteration)
    if (!AddFarthestPoint(p, epsilon, faces)) break;

  std::vector<WorkFace> alive;
  for (const WorkFace& f : faces)
    if (f.alive) alive.push_back(f);
  std::vector<HullFace> merged = MergeCoplanar(p, alive);

  return Renumbered(p, std::move(merged));
}

}  // namespace strata
