#include "physics/narrowphase/BoxBoxCollider.h"

#include <cmath>

#include "physics/narrowphase/ClosestPoints.h"
#include "physics/narrowphase/ManifoldBuilder.h"

namespace strata {

namespace {

// The same preferences as CollidePolyhedra: B's face must beat A's by this much, an edge pair the better
// face by kEdgeBias (faces give stable four-point manifolds).
constexpr float kFaceBBias = 0.001f;
constexpr float kEdgeBias = 0.005f;
// Edge pairs closer to parallel than this (length of the cross product of unit axes) are covered by faces.
constexpr float kParallel = 1e-4f;

struct PosedBox {
  Vec3 center;
  Mat3 axes;  // columns: the box's unit axes in world space
  Vec3 half;

  PosedBox(const BoxShape& box, const Pose& pose)
      : center(pose.position), axes(pose.rotation.toRotationMatrix()), half(box.half_extents()) {}

  Vec3 Corner(int corner) const {
    return center + axes * Vec3(corner & 1 ? half.x() : -half.x(), corner & 2 ? half.y() : -half.y(),
                                corner & 4 ? half.z() : -half.z());
  }
  // Farthest corner along `direction` (the signs of the direction along the axes).
  Vec3 Support(const Vec3& direction) const {
    const Vec3 along = axes.transpose() * direction;
    return Corner((along.x() > 0.0f ? 1 : 0) | (along.y() > 0.0f ? 2 : 0) | (along.z() > 0.0f ? 4 : 0));
  }
  // Face f (-x, +x, -y, +y, -z, +z): outward normal.
  Vec3 FaceNormal(int face) const { return (face % 2 ? 1.0f : -1.0f) * axes.col(face / 2); }
  void Face(int face, SupportingFace& out) const {
    out.count = 0;
    out.normal = FaceNormal(face);
    for (const int corner : BoxShape::kFaceCorners[face]) out.Add(Corner(corner));
  }
  // The face whose normal is most aligned with `direction` (the first of equals, as MostAlignedFace).
  int MostAlignedFace(const Vec3& direction) const {
    int best = 0;
    for (int face = 1; face < 6; ++face)
      if (FaceNormal(face).dot(direction) > FaceNormal(best).dot(direction)) best = face;
    return best;
  }
  // The edge along axis `axis` farthest along `direction`, as its two ends.
  void ExtremeEdge(int axis, const Vec3& direction, Vec3& from, Vec3& to) const {
    Vec3 middle = center;
    for (int k = 0; k < 3; ++k)
      if (k != axis) middle += (axes.col(k).dot(direction) > 0.0f ? half[k] : -half[k]) * axes.col(k);
    from = middle - half[axis] * axes.col(axis);
    to = middle + half[axis] * axes.col(axis);
  }
};

// The boxes' relative placement in A's frame: the separating-axis test then needs only scalars (Gottschalk's
// OBB test). rotation(k, j) = a_k . b_j.
struct Relative {
  Mat3 rotation;
  Mat3 absolute;  // |rotation|
  Vec3 offset;    // B's centre minus A's, along A's axes
  Relative(const PosedBox& a, const PosedBox& b)
      : rotation(a.axes.transpose() * b.axes),
        absolute(rotation.cwiseAbs()),
        offset(a.axes.transpose() * (b.center - a.center)) {}
};

struct FaceAxis {
  int face = -1;
  float separation = -kLargeFloat;
};

// The face of A (`of_a`) or of B that the other box is farthest beyond: each face's separation is the gap
// between the other box's deepest corner and the face plane.
FaceAxis BestFace(const Relative& relative, const PosedBox& a, const PosedBox& b, bool of_a) {
  FaceAxis best;
  const Vec3 along = of_a ? relative.offset : Vec3(relative.rotation.transpose() * relative.offset);
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const float sign = face % 2 ? 1.0f : -1.0f;
    // Seen from B, A's centre is at -offset.
    const float centre = of_a ? sign * along[axis] : -sign * along[axis];
    const float reach =
        of_a ? relative.absolute.row(axis).dot(b.half) : relative.absolute.col(axis).dot(a.half);
    const float separation = centre - reach - (of_a ? a.half[axis] : b.half[axis]);
    if (separation > best.separation) best = {face, separation};
  }
  return best;
}

struct EdgeAxis {
  int axis_a = -1, axis_b = -1;
  float separation = -kLargeFloat;
  Vec3 normal = Vec3::UnitY();
};

// Axes a_i x b_j. In A's frame a_i x b_j has the components of rotation's column j crossed into the plane
// of the other two axes, and its dot with b_m (m != j) is +-rotation(i, the third): all from the table.
EdgeAxis BestEdges(const Relative& relative, const PosedBox& a, const PosedBox& b) {
  EdgeAxis best;
  const Mat3& r = relative.rotation;
  const Mat3& abs_r = relative.absolute;
  const Vec3& t = relative.offset;
  int best_i = -1, best_j = -1;
  Vec3 best_local = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      Vec3 local = Vec3::Zero();  // a_i x b_j along A's axes
      local[i1] = -r(i2, j);
      local[i2] = r(i1, j);
      const float length = local.norm();
      if (length < kParallel) continue;
      const float centre = std::abs(local.dot(t));
      const float reach_a = a.half[i1] * abs_r(i2, j) + a.half[i2] * abs_r(i1, j);
      const float reach_b = b.half[j1] * abs_r(i, j2) + b.half[j2] * abs_r(i, j1);
      const float separation = (centre - reach_a - reach_b) / length;
      if (separation > best.separation) {
        best.separation = separation;
        best_i = i, best_j = j;
        // Pointing from A to B.
        best_local = (local.dot(t) < 0.0f ? -1.0f : 1.0f) / length * local;
      }
    }
  }
  if (best_i >= 0) best = {best_i, best_j, best.separation, a.axes * best_local};
  return best;
}

}  // namespace

bool CollideBoxes(const BoxShape& box_a, const Pose& pose_a, const BoxShape& box_b, const Pose& pose_b,
                  float max_separation, ContactManifold& manifold) {
  const PosedBox a(box_a, pose_a), b(box_b, pose_b);
  const Relative relative(a, b);
  const FaceAxis face_a = BestFace(relative, a, b, true);
  if (face_a.separation > max_separation) return false;
  const FaceAxis face_b = BestFace(relative, a, b, false);
  if (face_b.separation > max_separation) return false;
  const EdgeAxis edges = BestEdges(relative, a, b);
  if (edges.separation > max_separation) return false;

  const bool on_b = face_b.separation > face_a.separation + kFaceBBias;
  const float face_separation = on_b ? face_b.separation : face_a.separation;
  manifold.count = 0;
  if (edges.separation > face_separation + kEdgeBias) {
    const Vec3& n = edges.normal;
    Vec3 a0, a1, b0, b1, point_a, point_b;
    a.ExtremeEdge(edges.axis_a, n, a0, a1);
    b.ExtremeEdge(edges.axis_b, -n, b0, b1);
    ClosestPointsOfSegments(a0, a1, b0, b1, point_a, point_b);
    manifold.normal = n;
    manifold.points[0] = {point_a, point_b, (point_b - point_a).dot(n)};
    manifold.count = 1;
    return true;
  }
  // The normal from A to B: A's face normal, or B's negated.
  const Vec3 n = on_b ? Vec3(-b.FaceNormal(face_b.face)) : a.FaceNormal(face_a.face);
  manifold.normal = n;
  SupportingFace face_of_a, face_of_b;
  a.Face(on_b ? a.MostAlignedFace(n) : face_a.face, face_of_a);
  b.Face(on_b ? face_b.face : b.MostAlignedFace(-n), face_of_b);
  const Vec3 deepest_a = a.Support(n), deepest_b = b.Support(-n);
  BuildManifold(face_of_a, face_of_b, {deepest_a, deepest_b, (deepest_b - deepest_a).dot(n)}, max_separation,
                manifold);
  return manifold.count > 0;
}

}  // namespace strata
