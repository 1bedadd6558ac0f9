#include "physics/shapes/TriangleMeshShape.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <unordered_map>

#include "physics/math/Overlap4.h"

namespace strata {

namespace {
constexpr std::uint32_t kMaxLeafTriangles = 4;
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
    : Shape(ShapeType::kTriangleMesh, false),
      vertices_(std::move(vertices)),
      triangles_(std::move(triangles)) {
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

namespace {

// The binary hierarchy the 4-wide one is folded from: an inner node's children are at `first` and `first +
// 1`; a leaf covers order[first, first + count).
struct BinaryNode {
  AABB bounds;
  std::uint32_t first = 0;
  std::uint32_t count = 0;  // 0 = inner node
};

void SetLane(float (&min_x)[4], float (&min_y)[4], float (&min_z)[4], float (&max_x)[4], float (&max_y)[4],
             float (&max_z)[4], int lane, const AABB& box) {
  min_x[lane] = box.min.x(), min_y[lane] = box.min.y(), min_z[lane] = box.min.z();
  max_x[lane] = box.max.x(), max_y[lane] = box.max.y(), max_z[lane] = box.max.z();
}

// A binary tree over the triangles (median split of the centres along their longest axis: O(n log n) and
// balanced); a leaf holds at most `max_leaf` triangles, a run of `order`. Node 0 is the root.
std::vector<BinaryNode> BuildBinaryTree(const std::vector<Vec3>& centers, const std::vector<AABB>& bounds,
                                        std::uint32_t max_leaf, std::vector<std::uint32_t>& order) {
  const auto count = static_cast<std::uint32_t>(bounds.size());
  std::vector<BinaryNode> binary;
  binary.reserve(2 * count / max_leaf + 1);
  binary.push_back({});
  struct Task {
    std::uint32_t node, begin, end;
  };
  std::vector<Task> stack = {{0, 0, count}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    AABB node_bounds, center_bounds;
    for (std::uint32_t i = task.begin; i < task.end; ++i) {
      node_bounds.Encapsulate(bounds[order[i]]);
      center_bounds.Encapsulate(centers[order[i]]);
    }
    binary[task.node].bounds = node_bounds;
    if (task.end - task.begin <= max_leaf) {
      binary[task.node].first = task.begin;
      binary[task.node].count = task.end - task.begin;
      continue;
    }
    int axis = 0;
    center_bounds.Size().maxCoeff(&axis);
    const std::uint32_t middle = task.begin + (task.end - task.begin) / 2;
    std::nth_element(order.begin() + task.begin, order.begin() + middle, order.begin() + task.end,
                     [&](std::uint32_t a, std::uint32_t b) { return centers[a][axis] < centers[b][axis]; });
    const auto left = static_cast<std::uint32_t>(binary.size());
    binary.push_back({});
    binary.push_back({});
    binary[task.node].first = left;
    binary[task.node].count = 0;
    stack.push_back({left, task.begin, middle});
    stack.push_back({left + 1, middle, task.end});
  }
  return binary;
}

}  // namespace

int TriangleMeshShape::Bounds4::OverlapMask(const AABB& box) const {
  return OverlapMask4(min_x, min_y, min_z, max_x, max_y, max_z, box);
}

void TriangleMeshShape::Bounds4::RayEntries(const Vec3& origin, const Vec3& inverse_direction,
                                            float max_fraction, float* entry) const {
  for (int i = 0; i < 4; ++i)
    entry[i] = AABB({min_x[i], min_y[i], min_z[i]}, {max_x[i], max_y[i], max_z[i]})
                   .RayEntry(origin, inverse_direction, max_fraction);
}

void TriangleMeshShape::BuildHierarchy() {
  const auto count = static_cast<std::uint32_t>(triangles_.size());
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<Vec3> centers(count);
  std::vector<AABB> bounds(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    for (int corner = 0; corner < 3; ++corner) bounds[t].Encapsulate(Vertex(t, corner));
    centers[t] = bounds[t].Center();
  }
  const std::vector<BinaryNode> binary = BuildBinaryTree(centers, bounds, kMaxLeafTriangles, order);
  bounds_ = binary[0].bounds;

  // Fold two binary levels into one 4-wide level: a node's children are its binary grandchildren (or its
  // children, where those are leaves).
  nodes_.clear();
  leaves_.clear();
  nodes_.reserve(binary.size() / 3 + 1);
  leaves_.reserve(binary.size() / 2 + 1);
  auto build = [&](auto&& self, std::uint32_t index) -> std::uint32_t {
    const BinaryNode& b = binary[index];
    if (b.count > 0) {
      Leaf leaf;
      for (int lane = 0; lane < 4; ++lane) {
        const bool used = lane < static_cast<int>(b.count);
        leaf.triangle[lane] = used ? order[b.first + lane] : kEmpty;
        SetLane(leaf.bounds.min_x, leaf.bounds.min_y, leaf.bounds.min_z, leaf.bounds.max_x, leaf.bounds.max_y,
                leaf.bounds.max_z, lane, used ? bounds[order[b.first + lane]] : AABB());
      }
      leaves_.push_back(leaf);
      return kLeaf | static_cast<std::uint32_t>(leaves_.size() - 1);
    }
    std::uint32_t picks[4];
    int picked = 0;
    for (const std::uint32_t child : {b.first, b.first + 1}) {
      if (binary[child].count == 0) {
        picks[picked++] = binary[child].first;
        picks[picked++] = binary[child].first + 1;
      } else {
        picks[picked++] = child;
      }
    }
    const auto node_index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    for (int slot = 0; slot < 4; ++slot) {
      const bool used = slot < picked;
      const std::uint32_t code = used ? self(self, picks[slot]) : kEmpty;
      Node& node = nodes_[node_index];  // after the recursion, which may have grown nodes_
      node.child[slot] = code;
      SetLane(node.bounds.min_x, node.bounds.min_y, node.bounds.min_z, node.bounds.max_x, node.bounds.max_y,
              node.bounds.max_z, slot, used ? binary[picks[slot]].bounds : AABB());
    }
    return node_index;
  };
  root_ = build(build, 0);
}

void TriangleMeshShape::QueryBox(const AABB& local_box, std::vector<std::uint32_t>& out) const {
  if (root_ == kEmpty) return;
  // Depth is about log4(triangles / 4), so 3 entries per level stay far below the stack size.
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = root_;
  while (top > 0) {
    const std::uint32_t code = stack[--top];
    if ((code & kLeaf) != 0) {
      const Leaf& leaf = leaves_[code & ~kLeaf];
      const int mask = leaf.bounds.OverlapMask(local_box);
      for (int lane = 0; lane < 4; ++lane)
        if ((mask >> lane) & 1) out.push_back(leaf.triangle[lane]);
      continue;
    }
    const Node& node = nodes_[code];
    const int mask = node.bounds.OverlapMask(local_box);
    // Children pushed last-first, so they are visited in slot order; each written, and kept if it overlaps
    // (a branch per child would mispredict about as often as not). Empty slots have inside-out bounds.
    for (int slot = 3; slot >= 0; --slot) {
      stack[top] = node.child[slot];
      top += (mask >> slot) & 1;
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
  if (root_ == kEmpty) return false;
  const Vec3 inverse = SafeInverse(direction);
  float best = max_fraction;
  std::uint32_t best_triangle = 0;
  bool found = false;
  struct Entry {
    std::uint32_t code;
    float entry;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {root_, 0.0f};
  while (top > 0) {
    const Entry current = stack[--top];
    if (current.entry > best) continue;  // a nearer hit was found since it was pushed
    if ((current.code & kLeaf) != 0) {
      const Leaf& leaf = leaves_[current.code & ~kLeaf];
      for (const std::uint32_t t : leaf.triangle) {
        if (t == kEmpty) continue;
        const float fraction = RayTriangle(origin, direction, Vertex(t, 0), Vertex(t, 1), Vertex(t, 2));
        if (fraction >= 0.0f && fraction <= best) {
          best = fraction;
          best_triangle = t;
          found = true;
        }
      }
      continue;
    }
    const Node& node = nodes_[current.code];
    float entry[4];
    node.bounds.RayEntries(origin, inverse, best, entry);
    // Push the farthest first so the nearest child is visited next and `best` shrinks early.
    int slots[4];
    int hits = 0;
    for (int slot = 0; slot < 4; ++slot)
      if (node.child[slot] != kEmpty && entry[slot] >= 0.0f) slots[hits++] = slot;
    std::sort(slots, slots + hits, [&](int a, int b) { return entry[a] > entry[b]; });
    for (int i = 0; i < hits; ++i) stack[top++] = {node.child[slots[i]], entry[slots[i]]};
  }
  if (!found) return false;
  hit.fraction = best;
  hit.sub_shape = best_triangle;
  hit.normal = normals_[best_triangle].dot(direction) > 0.0f ? Vec3(-normals_[best_triangle])
                                                             : normals_[best_triangle];
  return true;
}

void TriangleMeshShape::CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const {
  AppendTrianglesInBox(*this, local_box, out);
}

}  // namespace strata
