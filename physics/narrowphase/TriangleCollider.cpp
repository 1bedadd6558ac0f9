#include "physics/narrowphase/TriangleCollider.h"

#include <cmath>

#include "physics/narrowphase/ClosestPoints.h"
#include "physics/narrowphase/ManifoldBuilder.h"

namespace strata {

namespace {

// As in PolyhedronCollider: an edge axis must beat the best face axis by this much, and the triangle's face
// must beat the box's by a millimetre, so near-ties go to the faces, which give stable manifolds.
constexpr float kEdgeBias = 0.005f;
constexpr float kFaceBias = 0.001f;

struct Axis {
  float separation = -kLargeFloat;
  Vec3 normal = Vec3::UnitY();  // from the box into the triangle
  int box_index = -1;           // box face (-x, +x, -y, +y, -z, +z) or box edge axis
  int triangle_index = -1;      // triangle edge
};

// Unit box axis `axis` crossed with `d`.
Vec3 AxisCross(int axis, const Vec3& d) {
  switch (axis) {
    case 0:
      return {0.0f, -d.z(), d.y()};
    case 1:
      return {d.z(), 0.0f, -d.x()};
    default:
      return {-d.y(), d.x(), 0.0f};
  }
}

float MinProjection(const Vec3 (&points)[3], const Vec3& axis) {
  return std::min(points[0].dot(axis), std::min(points[1].dot(axis), points[2].dot(axis)));
}

Axis BestBoxFace(const Vec3& half, const Vec3 (&points)[3]) {
  Axis best;
  for (int axis = 0; axis < 3; ++axis) {
    const float low = std::min(points[0][axis], std::min(points[1][axis], points[2][axis]));
    const float high = std::max(points[0][axis], std::max(points[1][axis], points[2][axis]));
    // Face -axis, then +axis: the order MakeBox lists them in, so ties resolve the same way.
    const float separations[2] = {-high - half[axis], low - half[axis]};
    for (int sign = 0; sign < 2; ++sign) {
      if (separations[sign] <= best.separation) continue;
      best.separation = separations[sign];
      best.box_index = 2 * axis + sign;
      best.normal = Vec3::Zero();
      best.normal[axis] = sign ? 1.0f : -1.0f;
    }
  }
  return best;
}

Axis BestEdgePair(const Vec3& half, const Vec3 (&points)[3], const Vec3& normal) {
  Axis best;
  for (int axis = 0; axis < 3; ++axis) {
    for (int edge = 0; edge < 3; ++edge) {
      Vec3 direction = AxisCross(axis, (points[(edge + 1) % 3] - points[edge]).normalized());
      const float length = direction.norm();
      if (length < 1e-4f) continue;  // parallel edges: a face axis covers them
      direction /= length;
      // Into a one-sided triangle means against its front normal.
      if (direction.dot(normal) > 0.0f) direction = -direction;
      const float separation = MinProjection(points, direction) - direction.cwiseAbs().dot(half);
      if (separation <= best.separation) continue;
      best.separation = separation;
      best.normal = direction;
      best.box_index = axis;
      best.triangle_index = edge;
    }
  }
  return best;
}

// The closest points of the box edge parallel to `axis` that lies farthest along `normal` and the triangle's
// edge `edge`.
ContactPoint EdgeContact(const Vec3& half, int axis, const Vec3 (&points)[3], int edge, const Vec3& normal) {
  Vec3 corner;
  for (int k = 0; k < 3; ++k) corner[k] = normal[k] > 0.0f ? half[k] : -half[k];
  Vec3 from = corner, to = corner;
  from[axis] = -half[axis];
  to[axis] = half[axis];
  ContactPoint contact;
  ClosestPointsOfSegments(from, to, points[edge], points[(edge + 1) % 3], contact.position_a,
                          contact.position_b);
  contact.separation = (contact.position_b - contact.position_a).dot(normal);
  return contact;
}

}  // namespace

bool CollideBoxTriangle(const BoxShape& box, const Mat3& rotation, const Vec3& center,
                        const MeshTriangle& triangle, float max_separation, ContactManifold& manifold) {
  const Vec3& half = box.half_extents();
  const Mat3 to_box = rotation.transpose();
  const Vec3 points[3] = {to_box * (triangle.corners[0] - center), to_box * (triangle.corners[1] - center),
                          to_box * (triangle.corners[2] - center)};
  const Vec3 front = to_box * triangle.normal;

  const Axis box_face = BestBoxFace(half, points);
  if (box_face.separation > max_separation) return false;
  Axis triangle_face;
  triangle_face.separation = -front.cwiseAbs().dot(half) - front.dot(points[0]);
  triangle_face.normal = -front;
  if (triangle_face.separation > max_separation) return false;
  const Axis edges = BestEdgePair(half, points, front);
  if (edges.separation > max_separation) return false;

  const bool triangle_reference = triangle_face.separation > box_face.separation + kFaceBias;
  const Axis& face = triangle_reference ? triangle_face : box_face;
  manifold.count = 0;
  if (edges.separation > face.separation + kEdgeBias) {
    manifold.normal = edges.normal;
    manifold.points[0] = EdgeContact(half, edges.box_index, points, edges.triangle_index, edges.normal);
    manifold.count = 1;
  } else {
    const Vec3& n = face.normal;
    manifold.normal = n;
    SupportingFace box_side, triangle_side;
    // The box's reference face is the one the axis came from; as the incident face, the one facing n.
    box.GetSupportingFace(n, box_side);
    triangle_side.count = 0;
    for (const Vec3& point : points) triangle_side.Add(point);
    triangle_side.normal = front;
    Vec3 deepest_b = points[0];
    for (const Vec3& point : points)
      if (point.dot(-n) > deepest_b.dot(-n)) deepest_b = point;
    const Vec3 deepest_a = box.Support(n);
    BuildManifold(box_side, triangle_side, {deepest_a, deepest_b, (deepest_b - deepest_a).dot(n)},
                  max_separation, manifold);
    if (manifold.count == 0) return false;
  }
  // Back to the triangle's frame.
  manifold.normal = rotation * manifold.normal;
  for (int i = 0; i < manifold.count; ++i) {
    manifold.points[i].position_a = rotation * manifold.points[i].position_a + center;
    manifold.points[i].position_b = rotation * manifold.points[i].position_b + center;
  }
  return true;
}

bool CapsuleTriangleContact(const Vec3& p0, const Vec3& p1, float radius, const MeshTriangle& triangle,
                            float max_separation, bool& within, Vec3& normal, ContactPoint& deepest) {
  Vec3 on_segment, on_triangle;
  if (!ClosestPointsOfSegmentAndTriangle(p0, p1, triangle.corners[0], triangle.corners[1],
                                         triangle.corners[2], triangle.normal, on_segment, on_triangle))
    return false;
  const Vec3 offset = on_triangle - on_segment;
  const float distance = offset.norm();
  // A core touching the triangle gives no direction; the caller's general test handles it.
  if (distance < 1e-6f) return false;
  within = distance - radius <= max_separation;
  if (!within) return true;
  normal = offset / distance;
  deepest = {on_segment + radius * normal, on_triangle, distance - radius};
  return true;
}

}  // namespace strata
