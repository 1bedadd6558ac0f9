#include "physics/shapes/TriangleMeshShape.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <unordered_map>

namespace strata {

namespace {
constexpr std::uint32_t kMaxLeafTriangles = 4;
// Neighbours whose normals differ by less than this are treated as one surface (edge inactive).
constexpr float kCoplanarCosine = 0.996f;  // about 5 degrees
}  // namespace

Result<ShapeRef> TriangleMeshShape::Create(std::span<const Vec3> vertices,
                                           std::span<const Indices> triangles) {
  if (vertices.empty() || triangles.empty())
    return MakeError(ErrorCode::kDegenerateShape, "triangle mesh has no vertices or no triangles");
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!IsFinite(vertices[i]))
      return MakeError(ErrorCode::kInvalidArgument,
                       "triangle mesh vertex " + std::to_string(i) + " is not finite");
  std::vector<Indices> kept;
  kept.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Indices& tri = triangles[t];
    for (std::uint32_t index : tri)
      if (index >= vertices.size())
        return MakeError(ErrorCode::kInvalidArgument, "triangle " + std::to_string(t) + " uses vertex " +
                                                          std::to_string(index) + " of " +
                                                          std::to_string(vertices.size()));
    const Vec3 normal = (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]);
    if (normal.squaredNorm() > 1e-20f) kept.push_back(tri);
  }
  if (kept.empty()) return MakeError(ErrorCode::kDegenerateShape, "every triangle of the mesh is degenerate");
  return ShapeRef(std::make_shared<TriangleMeshShape>(std::vector<Vec3>(vertices.begin(), vertices.end()),
                                                      std::move(kept)));
}

TriangleMeshShape::TriangleMeshShape(std::vector<Vec3> vertices, std::vector<Indices> triangles)
    : Shape(ShapeType::kTriangleMesh), vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  normals_.reserve(triangles_.size());
  for (const Indices& tri : triangles_)
    normals_.push_back(
        (vertices_[tri[1]] - vertices_[tri[0]]).cross(vertices_[tri[2]] - vertices_[tri[0]]).normalized());
  ComputeActiveEdges();
  BuildHierarchy();
}

void TriangleMeshShape::ComputeActiveEdges() {
  // Undirected edge key -> first triangle seen with that edge and its local edge number.
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, int>> first_owner;
  first_owner.reserve(triangles_.size() * 2);
  active_edges_.assign(triangles_.size(), 0b111);
  auto key = [](std::uint32_t a, std::uint32_t b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    for (int edge = 0; edge < 3; ++edge) {
      const std::uint64_t k = key(triangles_[t][edge], triangles_[t][(edge + 1) % 3]);
      auto [it, inserted] = first_owner.emplace(k, std::make_pair(t, edge));
      if (inserted) continue;
      const auto [other, other_edge] = it->second;
      // A shared edge is real only where the surface bends outwards (convex) by more than a few degrees.
      const Vec3& opposite = vertices_[triangles_[t][(edge + 2) % 3]];
      const bool convex = normals_[other].dot(opposite - Vertex(other, 0)) < 0.0f;
      const bool flat = normals_[t].dot(normals_[other]) > kCoplanarCosine;
      if (flat || !convex) {
        active_edges_[t] &= static_cast<std::uint8_t>(~(1u << edge));
        active_edges_[other] &= static_cast<std::uint8_t>(~(1u << other_edge));
      }
    }
  }
}

void TriangleMeshShape::BuildHierarchy() {
  leaf_triangles_.resize(triangles_.size());
  std::iota(leaf_triangles_.begin(), leaf_triangles_.end(), 0u);
  std::vector<Vec3> centers(triangles_.size());
  std::vector<AABB> bounds(triangles_.size());
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) bounds[t].Encapsulate(Vertex(t, corner));
    centers[t] = bounds[t].Center();
  }
  nodes_.reserve(2 * triangles_.size() / kMaxLeafTriangles + 1);
  nodes_.push_back({});
  struct Task {
    std::uint32_t node, begin, end;
  };
  std::vector<Task> stack = {{0, 0, static_cast<std::uint32_t>(triangles_.size())}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    AABB node_bounds, center_bounds;
    for (std::uint32_t i = task.begin; i < task.end; ++i) {
      node_bounds.Encapsulate(bounds[leaf_triangles_[i]]);
      center_bounds.Encapsulate(centers[leaf_triangles_[i]]);
    }
    nodes_[task.node].bounds = node_bounds;
    if (task.end - task.begin <= kMaxLeafTriangles) {
      nodes_[task.node].first = task.begin;
      nodes_[task.node].count = task.end - task.begin;
      continue;
    }
    // Median split along the longest axis of the centres: O(n log n) overall and balanced.
    int axis = 0;
    center_bounds.Size().maxCoeff(&axis);
    const std::uint32_t middle = task.begin + (task.end - task.begin) / 2;
    std::nth_element(leaf_triangles_.begin() + task.begin, leaf_triangles_.begin() + middle,
                     leaf_triangles_.begin() + task.end,
                     [&](std::uint32_t a, std::uint32_t b) { return centers[a][axis] < centers[b][axis]; });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    stack.push_back({left, task.begin, middle});
    stack.push_back({left + 1, middle, task.end});
  }
}

void TriangleMeshShape::QueryBox(const AABB& local_box, std::vector<std::uint32_t>& out) const {
  if (nodes_.empty()) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!node.bounds.Overlaps(local_box)) continue;
    if (node.count == 0) {
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const std::uint32_t t = leaf_triangles_[i];
      AABB triangle_bounds;
      for (int corner = 0; corner < 3; ++corner) triangle_bounds.Encapsulate(Vertex(t, corner));
      if (triangle_bounds.Overlaps(local_box)) out.push_back(t);
    }
  }
}

float RayTriangle(const Vec3& origin, const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 edge1 = b - a, edge2 = c - a;
  const Vec3 p = direction.cross(edge2);
  const float determinant = edge1.dot(p);
  if (std::abs(determinant) < 1e-12f) return -1.0f;
  const float inverse = 1.0f / determinant;
  const Vec3 s = origin - a;
  const float u = s.dot(p) * inverse;
  if (u < 0.0f || u > 1.0f) return -1.0f;
  const Vec3 q = s.cross(edge1);
  const float v = direction.dot(q) * inverse;
  if (v < 0.0f || u + v > 1.0f) return -1.0f;
  const float t = edge2.dot(q) * inverse;
  return t >= 0.0f ? t : -1.0f;
}

bool TriangleMeshShape::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                                ShapeRayHit& hit) const {
  if (nodes_.empty()) return false;
  const Vec3 inverse = SafeInverse(direction);
  float best = max_fraction;
  std::uint32_t best_triangle = 0;
  bool found = false;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.bounds.RayEntry(origin, inverse, best) < 0.0f) continue;
    if (node.count == 0) {
      // Visit the nearer child first so `best` shrinks early.
      const float left = nodes_[node.first].bounds.RayEntry(origin, inverse, best);
      const float right = nodes_[node.first + 1].bounds.RayEntry(origin, inverse, best);
      const bool left_first = left >= 0.0f && (right < 0.0f || left <= right);
      stack[top++] = left_first ? node.first + 1 : node.first;
      stack[top++] = left_first ? node.first : node.first + 1;
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const std::uint32_t t = leaf_triangles_[i];
      const float fraction = RayTriangle(origin, direction, Vertex(t, 0), Vertex(t, 1), Vertex(t, 2));
      if (fraction >= 0.0f && fraction <= best) {
        best = fraction;
        best_triangle = t;
        found = true;
      }
    }
  }
  if (!found) return false;
  hit.fraction = best;
  hit.sub_shape = best_triangle;
  hit.normal = normals_[best_triangle].dot(direction) > 0.0f ? Vec3(-normals_[best_triangle])
                                                             : normals_[best_triangle];
  return true;
}

void TriangleMeshShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  std::vector<std::uint32_t> hits;
  QueryBox(local_box, hits);
  for (std::uint32_t t : hits) out.push_back({{Vertex(t, 0), Vertex(t, 1), Vertex(t, 2)}});
}

}  // namespace strata
