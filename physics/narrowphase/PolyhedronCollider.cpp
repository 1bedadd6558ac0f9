#include "physics/narrowphase/PolyhedronCollider.h"

#include "physics/narrowphase/ClosestPoints.h"
#include "physics/narrowphase/ManifoldBuilder.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/ConvexHullShape.h"

namespace strata {

namespace {

// An edge axis must beat the best face axis by this much to be chosen: faces give stable 4-point
// manifolds, so near-ties go to them.
constexpr float kEdgeBias = 0.005f;

struct Axis {
  enum Kind { kFaceA, kFaceB, kEdges } kind = kFaceA;
  int index_a = -1, index_b = -1;
  int edge_a = -1, edge_b = -1;  // the edges themselves, where the Gauss-map test found them
  float separation = -kLargeFloat;
  Vec3 normal = Vec3::UnitY();  // from A to B
};

Axis BestFaceAxis(const Polyhedron& reference, const Polyhedron& other, Axis::Kind kind) {
  Axis best;
  best.kind = kind;
  for (int f = 0; f < reference.face_count; ++f) {
    const Vec3& n = reference.face_normals[f];
    const float separation = other.Support(-n).dot(n) - reference.face_offsets[f];
    if (separation > best.separation) {
      best.separation = separation;
      best.index_a = f;
      best.normal = kind == Axis::kFaceA ? n : Vec3(-n);
    }
  }
  return best;
}

// Edge pairs of a closed polyhedron A and a one-sided triangle B. Only pairs whose arcs cross on the Gauss
// map (Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013) make a face of the Minkowski
// difference, so only their axes can separate. A triangle edge's arc, negated for the difference, is the
// half circle through its front and back normals on the side facing away from the edge, which lies in the
// plane normal to the edge: the test is whether A's edge arc crosses that plane on that side.
Axis BestTriangleEdgeAxis(const Polyhedron& a, const Polyhedron& triangle) {
  Axis best;
  best.kind = Axis::kEdges;
  const Vec3& front = triangle.face_normals[0];
  for (int j = 0; j < 3; ++j) {
    const Vec3& d = triangle.edge_directions[j];
    const Vec3 outward = d.cross(front);
    for (int e = 0; e < a.edge_count; ++e) {
      const Vec3& u = a.face_normals[a.edge_faces[e][0]];
      const Vec3& v = a.face_normals[a.edge_faces[e][1]];
      const float ud = u.dot(d), vd = v.dot(d);
      if (ud * vd >= 0.0f) continue;
      // Where A's arc crosses the plane, taken between u and v.
      const float crossing = (ud * v.dot(outward) - vd * u.dot(outward)) * (ud > 0.0f ? 1.0f : -1.0f);
      if (crossing >= 0.0f) continue;
      const Vec3 edge_a = a.vertices[a.edges[e][1]] - a.vertices[a.edges[e][0]];
      Vec3 axis = edge_a.cross(d);
      const float length = axis.norm();
      if (length < 1e-4f * edge_a.norm()) continue;  // parallel edges: a face axis covers them
      axis /= length;
      if (axis.dot(front) > 0.0f) axis = -axis;  // into a one-sided triangle means against its front
      const float separation = triangle.Support(-axis).dot(axis) - a.Support(axis).dot(axis);
      if (separation > best.separation) {
        best.separation = separation;
        best.edge_a = e;
        best.edge_b = j;
        best.normal = axis;
      }
    }
  }
  return best;
}

Axis BestEdgeAxis(const Polyhedron& a, const Polyhedron& b, const Vec3& center_a, const Vec3& center_b) {
  Axis best;
  best.kind = Axis::kEdges;
  for (int i = 0; i < a.direction_count; ++i) {
    for (int j = 0; j < b.direction_count; ++j) {
      Vec3 axis = a.edge_directions[i].cross(b.edge_directions[j]);
      const float length = axis.norm();
      if (length < 1e-4f) continue;  // parallel edges: a face axis covers them
      axis /= length;
      // Point from A into B: into a one-sided triangle means against its front normal.
      const float side = b.one_sided ? -axis.dot(b.face_normals[0]) : axis.dot(center_b - center_a);
      if (side < 0.0f) axis = -axis;
      const float separation = b.Support(-axis).dot(axis) - a.Support(axis).dot(axis);
      if (separation > best.separation) {
        best.separation = separation;
        best.index_a = i;
        best.index_b = j;
        best.normal = axis;
      }
    }
  }
  return best;
}

// The edge of `p` parallel to `direction` that lies farthest along `axis`.
int ExtremeEdge(const Polyhedron& p, const Vec3& direction, const Vec3& axis) {
  int best = 0;
  float best_dot = -kLargeFloat;
  for (int e = 0; e < p.edge_count; ++e) {
    const Vec3& v0 = p.vertices[p.edges[e][0]];
    const Vec3& v1 = p.vertices[p.edges[e][1]];
    if (std::abs((v1 - v0).normalized().dot(direction)) < 0.9999f) continue;
    const float d = (v0 + v1).dot(axis);
    if (d > best_dot) best_dot = d, best = e;
  }
  return best;
}

}  // namespace

int MostAlignedFace(const Polyhedron& p, const Vec3& direction) {
  int best = 0;
  for (int f = 1; f < p.face_count; ++f)
    if (p.face_normals[f].dot(direction) > p.face_normals[best].dot(direction)) best = f;
  return best;
}

namespace {

void ComputeCentroid(Polyhedron& p) {
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < p.vertex_count; ++i) sum += p.vertices[i];
  p.centroid = sum / static_cast<float>(p.vertex_count);
}

}  // namespace

Vec3 Polyhedron::Support(const Vec3& direction) const {
  if (is_box) {
    // The box's edge directions are its axes: the farthest corner has the signs of the direction along them.
    const int corner = (edge_directions[0].dot(direction) > 0.0f ? 1 : 0) |
                       (edge_directions[1].dot(direction) > 0.0f ? 2 : 0) |
                       (edge_directions[2].dot(direction) > 0.0f ? 4 : 0);
    return vertices[corner];
  }
  int best = 0;
  float best_dot = vertices[0].dot(direction);
  for (int i = 1; i < vertex_count; ++i) {
    const float d = vertices[i].dot(direction);
    if (d > best_dot) best_dot = d, best = i;
  }
  return vertices[best];
}

void Polyhedron::Face(int f, SupportingFace& face) const {
  face.count = 0;
  face.normal = face_normals[f];
  for (int i = face_start[f]; i < face_start[f + 1]; ++i) face.Add(vertices[face_loop[i]]);
}

namespace {

// Box topology: corners and faces as BoxShape numbers them.
constexpr const int (&kBoxFaces)[6][4] = BoxShape::kFaceCorners;
constexpr int kBoxEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                  {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

// The two faces (of kBoxFaces) that share each edge of kBoxEdges.
constexpr std::array<std::array<int, 2>, 12> BoxEdgeFaces() {
  std::array<std::array<int, 2>, 12> faces{};
  for (int e = 0; e < 12; ++e) {
    int found = 0;
    for (int f = 0; f < 6 && found < 2; ++f) {
      bool has_both[2] = {false, false};
      for (int k = 0; k < 4; ++k)
        for (int end = 0; end < 2; ++end) has_both[end] |= kBoxFaces[f][k] == kBoxEdges[e][end];
      if (has_both[0] && has_both[1]) faces[e][found++] = f;
    }
  }
  return faces;
}
constexpr std::array<std::array<int, 2>, 12> kBoxEdgeFaces = BoxEdgeFaces();

void MakeBox(const BoxShape& box, const Pose& pose, Polyhedron& out) {
  const Vec3& half = box.half_extents();
  const Mat3 rotation = pose.rotation.toRotationMatrix();
  for (int i = 0; i < 8; ++i)
    out.vertices[i] =
        pose.position + rotation * Vec3(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(),
                                        i & 4 ? half.z() : -half.z());
  out.vertex_count = 8;
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const float sign = f % 2 ? 1.0f : -1.0f;
    out.face_normals[f] = sign * rotation.col(axis);
    out.face_offsets[f] = out.face_normals[f].dot(pose.position) + half[axis];
    for (int k = 0; k < 4; ++k) out.face_loop[4 * f + k] = kBoxFaces[f][k];
    out.face_start[f + 1] = 4 * (f + 1);
  }
  out.face_count = 6;
  for (int e = 0; e < 12; ++e) {
    out.edges[e] = {kBoxEdges[e][0], kBoxEdges[e][1]};
    out.edge_faces[e] = kBoxEdgeFaces[e];
  }
  out.edge_count = 12;
  for (int axis = 0; axis < 3; ++axis) out.edge_directions[axis] = rotation.col(axis);
  out.direction_count = 3;
  out.is_box = true;
  out.centroid = pose.position;
}

bool MakeHull(const ConvexHullShape& hull, const Pose& pose, Polyhedron& out) {
  std::size_t loop_size = 0;
  for (const HullFace& face : hull.faces()) loop_size += face.vertices.size();
  if (hull.vertices().size() > Polyhedron::kMaxVertices || hull.faces().size() > Polyhedron::kMaxFaces ||
      hull.edges().size() > Polyhedron::kMaxEdges || loop_size > out.face_loop.size())
    return false;
  const Mat3 rotation = pose.rotation.toRotationMatrix();
  for (const Vec3& v : hull.vertices()) out.vertices[out.vertex_count++] = pose.position + rotation * v;
  for (const HullFace& face : hull.faces()) {
    const int f = out.face_count++;
    out.face_normals[f] = rotation * face.normal;
    out.face_offsets[f] = out.face_normals[f].dot(out.vertices[face.vertices[0]]);
    int cursor = out.face_start[f];
    for (int v : face.vertices) out.face_loop[cursor++] = v;
    out.face_start[f + 1] = cursor;
  }
  for (std::size_t e = 0; e < hull.edges().size(); ++e) {
    out.edges[out.edge_count] = hull.edges()[e];
    out.edge_faces[out.edge_count++] = hull.edge_faces()[e];
  }
  for (const Vec3& direction : hull.edge_directions())
    out.edge_directions[out.direction_count++] = rotation * direction;
  ComputeCentroid(out);
  return true;
}

}  // namespace

bool MakePolyhedron(const ConvexShape& shape, const Pose& pose, Polyhedron& out) {
  out.vertex_count = out.face_count = out.edge_count = out.direction_count = 0;
  out.one_sided = false;
  out.is_box = false;
  out.face_start[0] = 0;
  if (shape.type() == ShapeType::kBox) {
    MakeBox(static_cast<const BoxShape&>(shape), pose, out);
    return true;
  }
  if (shape.type() == ShapeType::kConvexHull)
    return MakeHull(static_cast<const ConvexHullShape&>(shape), pose, out);
  return false;
}

void MakeTrianglePolyhedron(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& normal,
                            Polyhedron& out) {
  out.vertex_count = 3;
  out.vertices[0] = a, out.vertices[1] = b, out.vertices[2] = c;
  out.one_sided = true;
  out.is_box = false;
  out.face_count = 1;
  out.face_normals[0] = normal;
  out.face_offsets[0] = normal.dot(a);
  out.face_start[0] = 0;
  out.face_start[1] = 3;
  out.face_loop[0] = 0, out.face_loop[1] = 1, out.face_loop[2] = 2;
  out.edges[0] = {0, 1}, out.edges[1] = {1, 2}, out.edges[2] = {2, 0};
  out.edge_count = 3;
  // A triangle's three edges are never parallel, so each is an axis direction of its own.
  out.edge_directions[0] = (b - a).normalized();
  out.edge_directions[1] = (c - b).normalized();
  out.edge_directions[2] = (a - c).normalized();
  out.direction_count = 3;
  out.centroid = (a + b + c) / 3.0f;
}

bool CollidePolyhedra(const Polyhedron& a, const Polyhedron& b, float max_separation,
                      ContactManifold& manifold) {
  const Axis face_a = BestFaceAxis(a, b, Axis::kFaceA);
  if (face_a.separation > max_separation) return false;
  const Axis face_b = BestFaceAxis(b, a, Axis::kFaceB);
  if (face_b.separation > max_separation) return false;
  const Axis edges = b.one_sided && b.vertex_count == 3 ? BestTriangleEdgeAxis(a, b)
                                                        : BestEdgeAxis(a, b, a.centroid, b.centroid);
  if (edges.separation > max_separation) return false;

  // Prefer A's face, then B's, then an edge pair, unless the later one is clearly better.
  const Axis& best_face = face_b.separation > face_a.separation + 0.001f ? face_b : face_a;
  manifold.count = 0;
  if (edges.separation > best_face.separation + kEdgeBias) {
    const Vec3 n = edges.normal;
    const int edge_a = edges.edge_a >= 0 ? edges.edge_a : ExtremeEdge(a, a.edge_directions[edges.index_a], n);
    const int edge_b =
        edges.edge_b >= 0 ? edges.edge_b : ExtremeEdge(b, b.edge_directions[edges.index_b], -n);
    Vec3 on_a, on_b;
    ClosestPointsOfSegments(a.vertices[a.edges[edge_a][0]], a.vertices[a.edges[edge_a][1]],
                            b.vertices[b.edges[edge_b][0]], b.vertices[b.edges[edge_b][1]], on_a, on_b);
    manifold.normal = n;
    manifold.points[0] = {on_a, on_b, (on_b - on_a).dot(n)};
    manifold.count = 1;
    return true;
  }
  const Vec3 n = best_face.normal;
  manifold.normal = n;
  SupportingFace reference, incident;
  if (best_face.kind == Axis::kFaceA) {
    a.Face(best_face.index_a, reference);
    b.Face(MostAlignedFace(b, -n), incident);
  } else {
    b.Face(best_face.index_a, reference);
    a.Face(MostAlignedFace(a, n), incident);
  }
  const SupportingFace& face_of_a = best_face.kind == Axis::kFaceA ? reference : incident;
  const SupportingFace& face_of_b = best_face.kind == Axis::kFaceA ? incident : reference;
  const Vec3 deepest_a = a.Support(n), deepest_b = b.Support(-n);
  BuildManifold(face_of_a, face_of_b, {deepest_a, deepest_b, (deepest_b - deepest_a).dot(n)}, max_separation,
                manifold);
  return manifold.count > 0;
}

}  // namespace strata
