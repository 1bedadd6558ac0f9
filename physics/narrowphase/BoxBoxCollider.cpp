#include "physics/narrowphase/BoxBoxCollider.h"

#include <algorithm>
#include <cmath>

#include "physics/narrowphase/ClosestPoints.h"
#include "physics/narrowphase/ManifoldBuilder.h"

namespace strata {

namespace {

// The same preferences as CollidePolyhedra: B's face must beat A's by this much, an edge pair the better
// face by kEdgeBias (faces give stable four-point manifolds).
constexpr float kFaceBBias = 0.001f;
constexpr float kEdgeBias = 0.005f;
// Faces whose alignments with the normal differ by no more than this are parallel to rounding: they touch
// over the overlap of their rectangles whichever is the reference, so the larger one is, and the smaller
// then lies inside it and needs no clipping (a box resting on a floor or a wider box).
constexpr float kParallelFaces = 1e-6f;
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
  // Face f's area over four (the product of its two half extents).
  float FaceArea(int face) const { return half[(face / 2 + 1) % 3] * half[(face / 2 + 2) % 3]; }
  // Face f (-x, +x, -y, +y, -z, +z): outward normal.
  Vec3 FaceNormal(int face) const { return (face % 2 ? 1.0f : -1.0f) * axes.col(face / 2); }
  // The face whose normal is most aligned with `direction` (the first of equals, as MostAlignedFace). Face
  // 2k+1 scores axis k's dot and face 2k its negation, which is exact, so three dots decide all six.
  int MostAlignedFace(const Vec3& direction) const {
    const Vec3 along = axes.transpose() * direction;
    int best = 0;
    float best_score = -along.x();
    for (int face = 1; face < 6; ++face) {
      const float score = face % 2 ? along[face / 2] : -along[face / 2];
      if (score > best_score) best = face, best_score = score;
    }
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
// between the other box's deepest corner and the face plane. Of an axis's two faces the one facing the other
// box's centre is the farther (the negative face on a tie, as a scan of all six in order keeps the first).
FaceAxis BestFace(const Relative& relative, const PosedBox& a, const PosedBox& b, bool of_a) {
  // The other box's centre along this box's axes (seen from B, A's centre is at -offset).
  const Vec3 centre = of_a ? relative.offset : Vec3(-(relative.rotation.transpose() * relative.offset));
  const Vec3 reach = of_a ? Vec3(relative.absolute * b.half) : Vec3(relative.absolute.transpose() * a.half);
  const Vec3& half = of_a ? a.half : b.half;
  FaceAxis best;
  for (int axis = 0; axis < 3; ++axis) {
    const float separation = std::abs(centre[axis]) - reach[axis] - half[axis];
    if (separation > best.separation) best = {2 * axis + (centre[axis] > 0.0f ? 1 : 0), separation};
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
// An edge pair matters only if it separates the boxes or beats the best face by the bias (`face_bar`): one
// whose unnormalised separation is at or below min(face_bar, 0) cannot (the axis is no longer than one, so
// normalising only deepens an overlap), and is passed over without the square root and division; resting
// boxes skip all nine.
EdgeAxis BestEdges(const Relative& relative, const PosedBox& a, const PosedBox& b, float face_bar) {
  const float cannot_matter = std::min(face_bar, 0.0f);
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
      const float centre = std::abs(local.dot(t));
      const float reach_a = a.half[i1] * abs_r(i2, j) + a.half[i2] * abs_r(i1, j);
      const float reach_b = b.half[j1] * abs_r(i, j2) + b.half[j2] * abs_r(i, j1);
      const float unnormalised = centre - reach_a - reach_b;
      if (unnormalised <= cannot_matter) continue;
      const float length = local.norm();
      if (length < kParallel) continue;
      const float separation = unnormalised / length;
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

// A point of the incident face in the reference face's frame: along its two edge axes and its normal.
struct FacePoint {
  float u, v, height;
};

// Corners this close outside a side (relative to the rectangle's half extent) count as on it: stacked boxes
// of one size meet corner to corner, and clipping at rounding level would add near-copies of a corner that
// the reduction to four points may keep instead of a real one.
constexpr float kOnSide = 1e-5f;
// A quad clipped by four sides has at most eight corners; the room beyond is for rounding.
constexpr int kMaxFacePoints = 16;

// Sutherland-Hodgman against one side of the reference rectangle: keeps sign * coordinate <= limit.
int ClipSide(const FacePoint* in, int count, bool along_u, float sign, float limit, FacePoint* out) {
  int written = 0;
  const float tolerance = kOnSide * limit;
  auto distance = [&](const FacePoint& p) {
    const float beyond = sign * (along_u ? p.u : p.v) - limit;
    return beyond <= tolerance ? std::min(beyond, 0.0f) : beyond;
  };
  FacePoint previous = in[count - 1];
  float previous_distance = distance(previous);
  for (int i = 0; i < count; ++i) {
    const FacePoint& current = in[i];
    const float current_distance = distance(current);
    // Only an edge that crosses the side makes a new point (one that ends on it has the point already).
    if ((previous_distance < 0.0f && current_distance > 0.0f) ||
        (previous_distance > 0.0f && current_distance < 0.0f)) {
      const float t = previous_distance / (previous_distance - current_distance);
      if (written < kMaxFacePoints)
        out[written++] = {previous.u + t * (current.u - previous.u),
                          previous.v + t * (current.v - previous.v),
                          previous.height + t * (current.height - previous.height)};
    }
    if (current_distance <= 0.0f && written < kMaxFacePoints) out[written++] = current;
    previous = current;
    previous_distance = current_distance;
  }
  return written;
}

// Whether every point is inside the rectangle as ClipSide judges it (within kOnSide of each side): then the
// four clips would hand the points through unchanged and in order (a box on a larger box: most contacts).
bool InsideRectangle(const FacePoint* points, int count, float half_u, float half_v) {
  for (int i = 0; i < count; ++i)
    if (std::abs(points[i].u) - half_u > kOnSide * half_u ||
        std::abs(points[i].v) - half_v > kOnSide * half_v)
      return false;
  return true;
}

// The face manifold: the incident face (a quad) clipped to the reference face's rectangle in the rectangle's
// own coordinates, each point then carried onto the reference plane along the contact normal `n` (A to B).
// The reference is the face more aligned with the normal, as BuildManifold chooses; of two faces parallel to
// rounding, the larger (A's on a tie).
void FaceManifold(const PosedBox& a, int face_a, const PosedBox& b, int face_b, const Vec3& n,
                  float max_separation, ContactManifold& manifold) {
  const float alignment_a = a.FaceNormal(face_a).dot(n), alignment_b = -b.FaceNormal(face_b).dot(n);
  const bool reference_is_a = std::abs(alignment_a - alignment_b) <= kParallelFaces
                                  ? a.FaceArea(face_a) >= b.FaceArea(face_b)
                                  : alignment_a > alignment_b;
  const PosedBox& reference = reference_is_a ? a : b;
  const PosedBox& incident = reference_is_a ? b : a;
  const int reference_face = reference_is_a ? face_a : face_b;
  const int incident_face = reference_is_a ? face_b : face_a;
  const int axis = reference_face / 2;
  const Vec3 normal = reference.FaceNormal(reference_face);
  const Vec3 centre = reference.center + reference.half[axis] * normal;
  const Vec3 u = reference.axes.col((axis + 1) % 3), v = reference.axes.col((axis + 2) % 3);
  const float half_u = reference.half[(axis + 1) % 3], half_v = reference.half[(axis + 2) % 3];
  // At most four corners, one more per side clipped.
  FacePoint buffers[2][kMaxFacePoints];
  int count = 0;
  for (const int corner : BoxShape::kFaceCorners[incident_face]) {
    const Vec3 offset = incident.Corner(corner) - centre;
    buffers[0][count++] = {u.dot(offset), v.dot(offset), normal.dot(offset)};
  }
  // The sides in the order of the reference face's loop (the edge from each corner to the next), as
  // BuildManifold clips them, so that the points come out in the same order: an edge runs along one axis,
  // its side faces along the other, by that coordinate's sign at its corners.
  int current = 0;
  const int(&loop)[4] = BoxShape::kFaceCorners[reference_face];
  const int sides = InsideRectangle(buffers[0], count, half_u, half_v) ? 0 : 4;
  for (int edge = 0; edge < sides && count > 0; ++edge) {
    const int corner = loop[edge], runs_along = loop[edge] ^ loop[(edge + 1) % 4];
    const int side_axis = (runs_along & (1 << ((axis + 1) % 3))) != 0 ? (axis + 2) % 3 : (axis + 1) % 3;
    const bool along_u = side_axis == (axis + 1) % 3;
    const float sign = (corner >> side_axis) & 1 ? 1.0f : -1.0f;
    count = ClipSide(buffers[current], count, along_u, sign, along_u ? half_u : half_v, buffers[1 - current]);
    current = 1 - current;
  }
  const float denominator = n.dot(normal);
  ContactPoint points[kMaxFacePoints];
  int point_count = 0;
  for (int i = 0; i < count; ++i) {
    const FacePoint& p = buffers[current][i];
    const Vec3 incident_point = centre + p.u * u + p.v * v + p.height * normal;
    AppendFacePoint(incident_point, incident_point - (p.height / denominator) * n, reference_is_a, n,
                    max_separation, points, point_count);
  }
  SetManifoldPoints(points, point_count, manifold);
  // All four corners, uncut and kept, on a face whose normal is the contact normal: the pair may slide.
  if (sides == 0 && manifold.count == 4 && std::abs(denominator) >= 1.0f - kParallelFaces)
    manifold.face = {true, reference_is_a, centre, u, v, normal, half_u, half_v};
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
  const bool on_b = face_b.separation > face_a.separation + kFaceBBias;
  const float face_separation = on_b ? face_b.separation : face_a.separation;
  const EdgeAxis edges = BestEdges(relative, a, b, face_separation + kEdgeBias);
  if (edges.separation > max_separation) return false;

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
  FaceManifold(a, on_b ? a.MostAlignedFace(n) : face_a.face, b, on_b ? face_b.face : b.MostAlignedFace(-n), n,
               max_separation, manifold);
  if (manifold.count == 0) {
    // Nothing of the incident face within the margin over the reference face: the deepest corners.
    const Vec3 deepest_a = a.Support(n), deepest_b = b.Support(-n);
    const float separation = (deepest_b - deepest_a).dot(n);
    if (separation > max_separation) return false;
    manifold.points[0] = {deepest_a, deepest_b, separation};
    manifold.count = 1;
  }
  return true;
}

}  // namespace strata
