#include "physics/narrowphase/CollideShapes.h"

#include <algorithm>

#include "physics/narrowphase/BoxBoxCollider.h"
#include "physics/narrowphase/ClosestPoints.h"
#include "physics/narrowphase/CollisionDispatch.h"
#include "physics/narrowphase/Epa.h"
#include "physics/narrowphase/ManifoldBuilder.h"
#include "physics/narrowphase/PolyhedronCollider.h"
#include "physics/narrowphase/TriangleCollider.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/SphereShape.h"

namespace strata {

namespace {

// Normal (A to B) and deepest point pair of two convex supports. The cores carry radii; exact supports are
// used when the cores overlap, and where `corner_slack` (CornerSlack) says the cores fall short of sharp
// exact shapes. False when they are apart beyond `max_separation`; `normal` is then a direction (not unit)
// from A towards B that the search found them apart along, or zero.
// A template over the support mappings (final classes), so that GJK calls them directly.
template <class SupportA, class SupportB>
bool FindContact(const SupportA& core_a, const SupportA& exact_a, float radius_a, const SupportB& core_b,
                 const SupportB& exact_b, float radius_b, float corner_slack, float max_separation,
                 Vec3& normal, ContactPoint& deepest, EpaScratch& scratch) {
  const float core_reach = max_separation + radius_a + radius_b + corner_slack;
  const GjkResult core = GjkClosestPointsOf(core_a, core_b, core_reach);
  normal = -core.nearest_difference;
  if (!core.overlapping && core.distance > core_reach) return false;
  if (!core.overlapping && core.distance > 1e-5f) {
    normal = (core.point_b - core.point_a) / core.distance;
    float separation = core.distance - radius_a - radius_b;
    // Exact cores (no slack) make that the shapes' gap; sharp corners can reach past it along the normal.
    if (corner_slack > 0.0f) {
      const Vec3 extreme_a = exact_a.Support(normal), extreme_b = exact_b.Support(-normal);
      separation = std::min(separation, (extreme_b - extreme_a).dot(normal));
    }
    if (separation > max_separation) return false;
    deepest = {core.point_a + radius_a * normal, core.point_b - radius_b * normal, separation};
    return true;
  }
  const GjkResult exact = GjkClosestPointsOf(exact_a, exact_b, max_separation);
  normal = -exact.nearest_difference;
  if (!exact.overlapping && exact.distance > max_separation) return false;
  if (!exact.overlapping && exact.distance > 1e-6f) {
    normal = (exact.point_b - exact.point_a) / exact.distance;
    deepest = {exact.point_a, exact.point_b, exact.distance};
    return true;
  }
  PenetrationResult penetration;
  if (!EpaPenetration(exact_a, exact_b, exact, penetration, scratch)) {
    // Touching without measurable overlap: separate along the line between the centres.
    const Vec3 between = exact_b.Center() - exact_a.Center();
    normal = between.squaredNorm() > 1e-12f ? Vec3(between.normalized()) : Vec3::UnitY();
    deepest = {exact.point_a, exact.point_a, 0.0f};
    return true;
  }
  normal = penetration.normal;
  deepest = {penetration.point_a, penetration.point_b, -penetration.depth};
  return true;
}

// A sharp shape's rounded core cuts its corners (by up to (sqrt(3) - 1) r on a box), so there the core only
// supplies the direction and the gap along it is measured on the exact shape; a shape that is its rounded
// core exactly has no corners to miss.
float CornerSlack(const ConvexShape& shape) {
  return shape.CoreIsExact() ? 0.0f : 0.75f * shape.core_radius();
}

// A box or hull rounded by a convex radius: separating axes and closed forms, which take it sharp, pass it to
// GJK on its core. (Spheres and capsules are their cores plus a radius too, and keep their closed forms.)
bool Rounded(const ConvexShape& shape) {
  return shape.CoreIsExact() && shape.type() != ShapeType::kSphere && shape.type() != ShapeType::kCapsule;
}

// Two rounded polyhedra resting face on face meet along their flat faces, but GJK on their cores finds one
// closest pair, which beside an edge of either core tilts towards it by the overhang over the gap between the
// cores (a millimetre over 10 cm is 10 mrad) and pushes the upper body off sideways, further as it goes.
// Where a supporting face's normal separates the shapes within this much of the closest pair's separation,
// that face is the contact, as separating axes would find it.
constexpr float kFaceNormalTolerance = 5e-4f;

void PreferFaceNormal(const PosedConvex& exact_a, const PosedConvex& exact_b, const SupportingFace& face_a,
                      const SupportingFace& face_b, Vec3& normal, ContactPoint& deepest) {
  float best = -kLargeFloat;
  Vec3 best_normal = normal;
  ContactPoint best_point = deepest;
  for (const Vec3& axis : {face_a.normal, Vec3(-face_b.normal)}) {
    if (axis.squaredNorm() < 0.5f) continue;  // a face without a known normal
    const Vec3 on_a = exact_a.Support(axis), on_b = exact_b.Support(-axis);
    const float separation = (on_b - on_a).dot(axis);
    if (separation > best) best = separation, best_normal = axis, best_point = {on_a, on_b, separation};
  }
  if (best < deepest.separation - kFaceNormalTolerance) return;
  normal = best_normal;
  deepest = best_point;
}

void WorldFace(const ConvexShape& shape, const Vec3& position, const Mat3& rotation,
               const Vec3& world_direction, SupportingFace& face) {
  shape.GetSupportingFace(rotation.transpose() * world_direction, face);
  for (int i = 0; i < face.count; ++i) face.vertices[i] = position + rotation * face.vertices[i];
  face.normal = rotation * face.normal;
}

bool CollideSpheres(const SphereShape& a, const Pose& pose_a, const SphereShape& b, const Pose& pose_b,
                    float max_separation, ContactManifold& manifold) {
  const Vec3 between = pose_b.position - pose_a.position;
  const float distance = between.norm();
  const float separation = distance - a.radius() - b.radius();
  if (separation > max_separation) return false;
  manifold.normal = distance > 1e-6f ? Vec3(between / distance) : Vec3::UnitY();
  manifold.count = 1;
  manifold.points[0] = {pose_a.position + a.radius() * manifold.normal,
                        pose_b.position - b.radius() * manifold.normal, separation};
  return true;
}

// Sphere A against box B in closed form: the closest point of the box to the centre.
bool CollideSphereBox(const SphereShape& a, const Pose& pose_a, const BoxShape& b, const Pose& pose_b,
                      float max_separation, ContactManifold& manifold) {
  const Vec3 center = pose_b.ToLocal(pose_a.position);
  const Vec3& half = b.half_extents();
  const Vec3 clamped = center.cwiseMax(-half).cwiseMin(half);
  Vec3 local_normal;  // from sphere towards box, box space
  float separation;
  Vec3 on_box;
  if (clamped != center) {
    const Vec3 offset = clamped - center;
    const float distance = offset.norm();
    separation = distance - a.radius();
    if (separation > max_separation) return false;
    local_normal = offset / distance;
    on_box = clamped;
  } else {
    // Centre inside the box: push out through the nearest face.
    const Vec3 depth = half - center.cwiseAbs();
    int axis = 0;
    depth.minCoeff(&axis);
    local_normal = Vec3::Zero();
    local_normal[axis] = center[axis] > 0 ? -1.0f : 1.0f;
    on_box = center;
    on_box[axis] = -local_normal[axis] * half[axis];
    separation = -depth[axis] - a.radius();
  }
  manifold.normal = pose_b.DirectionToWorld(local_normal);
  manifold.count = 1;
  manifold.points[0] = {pose_a.position + a.radius() * manifold.normal, pose_b.ToWorld(on_box), separation};
  return true;
}

// Supporting feature of a triangle against `direction`: the face when it faces that way, else an edge or
// a vertex (a steep triangle must not report its far corner as a deep contact).
void TriangleFace(const TriangleSupport& triangle, const Vec3& face_normal, const Vec3& direction,
                  SupportingFace& face) {
  face.count = 0;
  face.normal = Vec3::Zero();
  const float facing = face_normal.dot(direction) / direction.norm();
  if (std::abs(facing) > 0.5f) {
    // Keep counter-clockwise order as seen from the side the direction points to.
    face.normal = facing > 0 ? face_normal : Vec3(-face_normal);
    if (facing > 0) {
      for (int i = 0; i < 3; ++i) face.Add(triangle.vertex(i));
    } else {
      for (int i = 2; i >= 0; --i) face.Add(triangle.vertex(i));
    }
    return;
  }
  float dots[3];
  int best = 0;
  for (int i = 0; i < 3; ++i) {
    dots[i] = triangle.vertex(i).dot(direction);
    if (dots[i] > dots[best]) best = i;
  }
  face.Add(triangle.vertex(best));
  for (int i = 0; i < 3; ++i) {
    if (i == best) continue;
    const float edge = (triangle.vertex(i) - triangle.vertex(best)).norm() * direction.norm();
    if (dots[best] - dots[i] < 0.02f * edge) face.Add(triangle.vertex(i));
  }
}

// Mesh triangles have internal edges that a sliding body must not catch on: when the contact sits on
// such an edge (or in the interior), the triangle's face normal is the true normal.
// Triangles are one-sided, so the corrected normal always points from the body into the front face.
template <class TriangleShape>
Vec3 CorrectTriangleNormal(const TriangleShape& mesh, std::uint32_t triangle, const Vec3& face_normal,
                           const TriangleSupport& world, const Vec3& point_on_triangle, const Vec3& normal) {
  // Only a normal that is the face's to rounding passes unchecked: a rounded core overhanging an internal
  // corner tilts GJK's normal by a degree or two, and that tilt, opening a manifold, pushed a box sliding
  // over a flat mesh sideways and up.
  if (std::abs(normal.dot(face_normal)) > 0.999999f) return normal;
  const Vec3 v0 = world.vertex(1) - world.vertex(0), v1 = world.vertex(2) - world.vertex(0);
  const Vec3 v2 = point_on_triangle - world.vertex(0);
  const float d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const float denominator = d00 * d11 - d01 * d01;
  if (std::abs(denominator) < 1e-20f) return normal;
  const float b1 = (d11 * d20 - d01 * d21) / denominator;
  const float b2 = (d00 * d21 - d01 * d20) / denominator;
  const float b0 = 1.0f - b1 - b2;
  constexpr float kOnEdge = 1e-3f;
  // Edge k runs from vertex k to k+1; the point is on it when the opposite vertex's weight is ~0.
  std::uint8_t feature = 0;
  if (b2 < kOnEdge) feature |= 0b001;
  if (b0 < kOnEdge) feature |= 0b010;
  if (b1 < kOnEdge) feature |= 0b100;
  if ((feature & mesh.ActiveEdges(triangle)) != 0) return normal;
  return -face_normal;
}

// The core of a sphere (its centre, twice) or a capsule (its axis), in world space; false for other shapes.
bool SegmentCore(const ConvexShape& shape, const Pose& pose, Vec3 (&segment)[2]) {
  if (shape.type() == ShapeType::kSphere) {
    segment[0] = segment[1] = pose.position;
    return true;
  }
  if (shape.type() != ShapeType::kCapsule) return false;
  const Vec3 half_axis =
      pose.rotation * Vec3(0.0f, static_cast<const CapsuleShape&>(shape).half_height(), 0.0f);
  segment[0] = pose.position - half_axis;
  segment[1] = pose.position + half_axis;
  return true;
}

bool IsPolyhedron(const ConvexShape& shape) {
  return shape.type() == ShapeType::kBox || shape.type() == ShapeType::kConvexHull;
}

// Sphere against one triangle in closed form: the closest point of the triangle to the centre.
bool SphereTriangleContact(const Vec3& center, float radius, const TriangleSupport& triangle,
                           const Vec3& face_normal, float max_separation, Vec3& normal,
                           ContactPoint& deepest) {
  const Vec3 offset =  // closest triangle point relative to the centre
      ClosestPointOnTriangle(center, triangle.vertex(0), triangle.vertex(1), triangle.vertex(2)) - center;
  const float distance = offset.norm();
  if (distance - radius > max_separation) return false;
  normal = distance > 1e-6f ? Vec3(offset / distance) : Vec3(-face_normal);
  deepest = {center + radius * normal, center + offset, distance - radius};
  return true;
}

void MergeManifold(const ContactManifold& manifold, std::size_t first, std::vector<ContactManifold>& out) {
  for (std::size_t i = first; i < out.size(); ++i) {
    ContactManifold& existing = out[i];
    if (existing.normal.dot(manifold.normal) < 0.999f) continue;
    ContactPoint points[2 * ContactManifold::kMaxPoints];
    int count = 0;
    for (int k = 0; k < existing.count; ++k) points[count++] = existing.points[k];
    for (int k = 0; k < manifold.count; ++k) points[count++] = manifold.points[k];
    existing.count = ReduceContactPoints(points, count, existing.normal);
    for (int k = 0; k < existing.count; ++k) existing.points[k] = points[k];
    return;
  }
  out.push_back(manifold);
}

// Any two convex shapes by their cores and supporting faces.
bool CollideByGjk(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                  float max_separation, ContactManifold& manifold, CollisionScratch& scratch) {
  Vec3 normal;
  ContactPoint deepest;
  Vec3 segment_a[2], segment_b[2];
  bool found = false;
  if (SegmentCore(a, pose_a, segment_a) && SegmentCore(b, pose_b, segment_b)) {
    // Spheres and capsules are points and segments with a radius: the closest points of the cores give the
    // normal exactly, unless the cores themselves touch.
    Vec3 on_a, on_b;
    ClosestPointsOfSegments(segment_a[0], segment_a[1], segment_b[0], segment_b[1], on_a, on_b);
    const Vec3 offset = on_b - on_a;
    const float distance = offset.norm();
    if (distance > 1e-6f) {
      const float separation = distance - a.core_radius() - b.core_radius();
      if (separation > max_separation) {
        scratch.separating_axis = offset;
        return false;
      }
      normal = offset / distance;
      deepest = {on_a + a.core_radius() * normal, on_b - b.core_radius() * normal, separation};
      found = true;
    }
  }
  // Each pose's rotation as a matrix once, for the supports and the faces.
  const Mat3 rotation_a = pose_a.rotation.toRotationMatrix(), rotation_b = pose_b.rotation.toRotationMatrix();
  const PosedConvex exact_a(a, pose_a.position, rotation_a, false),
      exact_b(b, pose_b.position, rotation_b, false);
  if (!found) {
    const PosedConvex core_a(a, pose_a.position, rotation_a, true),
        core_b(b, pose_b.position, rotation_b, true);
    if (!FindContact(core_a, exact_a, a.core_radius(), core_b, exact_b, b.core_radius(),
                     CornerSlack(a) + CornerSlack(b), max_separation, normal, deepest, scratch.epa)) {
      scratch.separating_axis = normal;
      return false;
    }
  }
  SupportingFace face_a, face_b;
  WorldFace(a, pose_a.position, rotation_a, normal, face_a);
  WorldFace(b, pose_b.position, rotation_b, -normal, face_b);
  if (Rounded(a) || Rounded(b)) PreferFaceNormal(exact_a, exact_b, face_a, face_b, normal, deepest);
  manifold.normal = normal;
  BuildManifold(face_a, face_b, deepest, max_separation, manifold);
  // The deepest point is never shallower than the shapes' deepest overlap (exact on two exact cores, else the
  // lesser of the cores' gap and the gap along the normal): no point clipped from a rounded shape's face to
  // its sharp corner may lie deeper.
  if (Rounded(a) || Rounded(b)) KeepNoDeeperThan(deepest, manifold);
  return manifold.count > 0;
}

// CollideConvexTriangles' convex, posed once in the mesh's frame for every triangle it meets: the contact
// test for its kind (separating axes for boxes and hulls, closed forms for spheres and capsules, GJK/EPA on
// the cores for the rest) and its supporting faces.
class ConvexInMesh {
 public:
  ConvexInMesh(const ConvexShape& shape, const Pose& pose, float max_separation)
      : shape_(shape),
        pose_(pose),
        rotation_(pose.rotation.toRotationMatrix()),
        core_(shape, pose_.position, rotation_, true),
        exact_(shape, pose_.position, rotation_, false),
        reach_bounds_(shape.LocalBounds().Expanded(max_separation)) {
    use_sat_ = IsPolyhedron(shape) && !shape.CoreIsExact() && MakePolyhedron(shape, pose_, polyhedron_);
    if (shape.type() != ShapeType::kCapsule) return;
    const Vec3 half_axis = rotation_.col(1) * static_cast<const CapsuleShape&>(shape).half_height();
    capsule_core_[0] = pose_.position - half_axis;
    capsule_core_[1] = pose_.position + half_axis;
  }
  ConvexInMesh(const ConvexInMesh&) = delete;
  ConvexInMesh& operator=(const ConvexInMesh&) = delete;

  bool use_sat() const { return use_sat_; }
  /// Whether the triangle's box in the convex's own frame meets the convex's bounds there grown by the
  /// reach: if not, no point of it comes within reach (as Jolt culls a mesh's triangles). The mesh query's
  /// box is the world box of the turned convex, which takes in triangles beside a turned box's faces.
  bool NearBounds(const MeshTriangle& triangle) const {
    const Mat3 to_local = rotation_.transpose();
    Vec3 low = to_local * (triangle.corners[0] - pose_.position), high = low;
    for (int i = 1; i < 3; ++i) {
      const Vec3 corner = to_local * (triangle.corners[i] - pose_.position);
      low = low.cwiseMin(corner);
      high = high.cwiseMax(corner);
    }
    return (low.array() <= reach_bounds_.max.array()).all() &&
           (high.array() >= reach_bounds_.min.array()).all();
  }
  /// Whether the convex's deepest point below the triangle's plane comes within `max_separation` of it: if
  /// not, no feature of the triangle can come closer. Keeps that point and its height for Contact.
  bool Reaches(const Vec3& face_normal, const Vec3& corner, float max_separation) {
    // A shape that is its core plus a radius reaches the radius past its core's lowest point (no square root
    // for the rounded support's direction).
    if (shape_.CoreIsExact()) {
      lowest_ = pose_.position + rotation_ * shape_.CoreSupport(rotation_.transpose() * -face_normal);
      lowest_height_ = face_normal.dot(lowest_ - corner);
      return lowest_height_ - shape_.core_radius() <= max_separation;
    }
    lowest_ = pose_.position + rotation_ * shape_.Support(rotation_.transpose() * -face_normal);
    lowest_height_ = face_normal.dot(lowest_ - corner);
    return lowest_height_ <= max_separation;
  }
  /// The contact with one triangle (after Reaches for it): its normal and deepest point (and, by separating
  /// axes, the whole manifold). False when they are apart beyond `max_separation`.
  bool Contact(const TriangleSupport& triangle, const MeshTriangle& corners, float max_separation,
               EpaScratch& epa, ContactManifold& manifold, Vec3& normal, ContactPoint& deepest) {
    if (use_sat_) return PolyhedronContact(triangle, corners, max_separation, manifold, normal, deepest);
    if (rounded_ && OverTriangleInside(corners)) {
      // The core lies wholly above the triangle's plane, and its lowest point stands over the triangle's
      // inside: no point of the triangle is nearer the core than that point's foot on the plane, so that
      // pair is the closest, as GJK would find it (most triangles under a resting body, without GJK).
      normal = -corners.normal;
      const float radius = shape_.core_radius();
      deepest = {lowest_ + radius * normal, lowest_ - lowest_height_ * corners.normal,
                 lowest_height_ - radius};
      return deepest.separation <= max_separation;
    }
    if (shape_.type() == ShapeType::kSphere)
      return SphereTriangleContact(pose_.position, shape_.core_radius(), triangle, corners.normal,
                                   max_separation, normal, deepest);
    bool within = true;
    if (shape_.type() == ShapeType::kCapsule &&
        CapsuleTriangleContact(capsule_core_[0], capsule_core_[1], shape_.core_radius(), corners,
                               max_separation, within, normal, deepest))
      return within;
    return FindContact(core_, exact_, shape_.core_radius(), triangle, triangle, 0.0f, CornerSlack(shape_),
                       max_separation, normal, deepest, epa);
  }
  /// The convex's face most aligned with `normal`, in the mesh's frame.
  void Face(const Vec3& normal, SupportingFace& face) const {
    if (use_sat_)
      polyhedron_.Face(MostAlignedFace(polyhedron_, normal), face);
    else
      WorldFace(shape_, pose_.position, rotation_, normal, face);
  }

 private:
  bool PolyhedronContact(const TriangleSupport& triangle, const MeshTriangle& corners, float max_separation,
                         ContactManifold& manifold, Vec3& normal, ContactPoint& deepest) {
    if (shape_.type() == ShapeType::kBox) {
      if (!CollideBoxTriangle(static_cast<const BoxShape&>(shape_), rotation_, pose_.position, corners,
                              max_separation, manifold))
        return false;
    } else {
      thread_local Polyhedron triangle_polyhedron;
      MakeTrianglePolyhedron(triangle.vertex(0), triangle.vertex(1), triangle.vertex(2), corners.normal,
                             triangle_polyhedron);
      if (!CollidePolyhedra(polyhedron_, triangle_polyhedron, max_separation, manifold)) return false;
    }
    normal = manifold.normal;
    deepest = manifold.points[0];
    for (int i = 1; i < manifold.count; ++i)
      if (manifold.points[i].separation < deepest.separation) deepest = manifold.points[i];
    return true;
  }

  // Whether the core's lowest point (from Reaches) is clear of the plane and over the triangle's inside, by
  // a margin: on an edge or touching the plane, GJK decides.
  bool OverTriangleInside(const MeshTriangle& triangle) const {
    if (lowest_height_ <= kFaceContactMargin) return false;
    for (int i = 0; i < 3; ++i) {
      const Vec3& from = triangle.corners[i];
      const Vec3 edge = triangle.corners[(i + 1) % 3] - from;
      // Inward distance from the edge, scaled by its length: compare against the margin times that length.
      if (edge.cross(lowest_ - from).dot(triangle.normal) <= kFaceContactMargin * edge.norm()) return false;
    }
    return true;
  }

  static constexpr float kFaceContactMargin = 1e-4f;

  const ConvexShape& shape_;
  const Pose pose_;
  const Mat3 rotation_;
  const PosedConvex core_, exact_;
  const AABB reach_bounds_;  // local bounds grown by the pair's reach
  const bool rounded_ = Rounded(shape_);
  bool use_sat_ = false;
  Vec3 lowest_ = Vec3::Zero();
  float lowest_height_ = 0.0f;
  Vec3 capsule_core_[2];
  static thread_local Polyhedron polyhedron_;
};

thread_local Polyhedron ConvexInMesh::polyhedron_;

// Manifolds found in the mesh's frame, from `first` on, back to world space.
void ManifoldsToWorld(const Pose& pose_mesh, std::size_t first, std::vector<ContactManifold>& out) {
  if (first == out.size()) return;
  // The rotation as a matrix once: a quaternion turns each of up to 9 vectors at twice a matrix's cost.
  const Mat3 rotation = pose_mesh.rotation.toRotationMatrix();
  for (std::size_t m = first; m < out.size(); ++m) {
    ContactManifold& manifold = out[m];
    manifold.normal = rotation * manifold.normal;
    for (int i = 0; i < manifold.count; ++i) {
      manifold.points[i].position_a = rotation * manifold.points[i].position_a + pose_mesh.position;
      manifold.points[i].position_b = rotation * manifold.points[i].position_b + pose_mesh.position;
    }
  }
}

// A convex shape against anything made of triangles that TriangleMeshShape's triangle interface describes
// (QueryBox, Vertex, Normal, ActiveEdges): the mesh and the height field.
template <class TriangleShape>
void CollideConvexTriangles(const ConvexShape& a, const Pose& pose_a, const TriangleShape& mesh,
                            const Pose& pose_mesh, const ContactReach& reach,
                            const ContactManifold& prototype, std::vector<ContactManifold>& out,
                            CollisionScratch& scratch) {
  // Everything runs in the mesh's frame, so the triangles are used as stored; the convex is posed there
  // once and the manifolds go back to world space at the end.
  const Quat to_mesh = pose_mesh.rotation.conjugate();
  const Pose local_a{to_mesh * (pose_a.position - pose_mesh.position), to_mesh * pose_a.rotation};
  const ContactReach local_reach{reach.distance, to_mesh * reach.travel};
  const float max_separation = local_reach.Max();
  // The triangles all round by the whole reach: a box swept along the travel alone measured no faster (the
  // triangles' planes below cull the rest).
  const AABB local_box = a.WorldBounds(local_a).Expanded(max_separation);
  std::vector<std::uint32_t>& triangles = scratch.triangles;
  triangles.clear();
  mesh.QueryBox(local_box, triangles);
  if (triangles.empty()) return;
  // Manifolds merge in the order the triangles come, so the order is the triangles' numbers, not the walk
  // of a hierarchy: the same triangles collide the same whatever shape holds them (a mesh and its height
  // field), and on every run.
  std::sort(triangles.begin(), triangles.end());
  ConvexInMesh convex(a, local_a, max_separation);
  const std::size_t first = out.size();
  for (std::uint32_t t : triangles) {
    const Vec3 face_normal = mesh.Normal(t);
    const TriangleSupport triangle(mesh.Vertex(t, 0), mesh.Vertex(t, 1), mesh.Vertex(t, 2));
    // The contact's normal is not known yet, but no point of the triangle comes nearer than its plane.
    if (!convex.Reaches(face_normal, triangle.vertex(0), local_reach.Along(-face_normal))) continue;
    const MeshTriangle corners{{triangle.vertex(0), triangle.vertex(1), triangle.vertex(2)}, face_normal};
    if (!convex.NearBounds(corners)) continue;
    ContactManifold manifold = prototype;
    manifold.sub_shape_b = t;
    Vec3 normal;
    ContactPoint deepest;
    if (!convex.Contact(triangle, corners, max_separation, scratch.epa, manifold, normal, deepest)) continue;
    // A normal along the front face normal would pull the body through the triangle from behind.
    if (normal.dot(face_normal) > 0.0f) continue;
    const Vec3 corrected = CorrectTriangleNormal(mesh, t, face_normal, triangle, deepest.position_b, normal);
    if (convex.use_sat() && corrected == normal) {
      MergeManifold(manifold, first, out);
      continue;
    }
    if (corrected != normal) {
      normal = corrected;
      deepest.separation = (deepest.position_b - deepest.position_a).dot(normal);
    }
    manifold.normal = normal;
    if (a.type() == ShapeType::kSphere) {
      // A sphere touches in one point: clipping a face against it could only give that point back.
      if (deepest.separation > max_separation) continue;
      manifold.count = 1;
      manifold.points[0] = deepest;
      MergeManifold(manifold, first, out);
      continue;
    }
    SupportingFace face_a, face_b;
    convex.Face(normal, face_a);
    TriangleFace(triangle, face_normal, -normal, face_b);
    BuildManifold(face_a, face_b, deepest, max_separation, manifold);
    if (Rounded(a)) KeepNoDeeperThan(deepest, manifold);
    if (manifold.count > 0) MergeManifold(manifold, first, out);
  }
  ManifoldsToWorld(pose_mesh, first, out);
}

const ConvexShape& AsConvex(const Shape& shape) {
  return static_cast<const ConvexShape&>(shape);
}

// A closed form or separating-axis test of two shape types that fills one manifold, in the table's form.
template <class A, class B,
          bool (*Collide)(const A&, const Pose&, const B&, const Pose&, float, ContactManifold&)>
void AppendPair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, float max_separation,
                const ContactManifold& prototype, std::vector<ContactManifold>& out) {
  ContactManifold manifold = prototype;
  if (Collide(static_cast<const A&>(a), pose_a, static_cast<const B&>(b), pose_b, max_separation, manifold))
    out.push_back(manifold);
}

}  // namespace

void CollideConvexByGjk(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                        const ContactReach& reach, const ContactManifold& prototype,
                        std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  ContactManifold manifold = prototype;
  if (CollideByGjk(AsConvex(a), pose_a, AsConvex(b), pose_b, reach.Max(), manifold, scratch))
    out.push_back(manifold);
}

float GapAlong(const ConvexShape& a, const Vec3& position_a, const Mat3& rotation_a, const ConvexShape& b,
               const Vec3& position_b, const Mat3& rotation_b, const Vec3& axis) {
  const Vec3 along_a = rotation_a.transpose() * axis, against_b = rotation_b.transpose() * -axis;
  return axis.dot(position_b - position_a) - along_a.dot(a.Support(along_a)) -
         against_b.dot(b.Support(against_b));
}

void CollideSpherePair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                       const ContactReach& reach, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& /*scratch*/) {
  AppendPair<SphereShape, SphereShape, CollideSpheres>(a, pose_a, b, pose_b, reach.Max(), prototype, out);
}

void CollideSphereWithBox(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                          const ContactReach& reach, const ContactManifold& prototype,
                          std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  if (AsConvex(b).CoreIsExact()) {
    CollideConvexByGjk(a, pose_a, b, pose_b, reach, prototype, out, scratch);
    return;
  }
  AppendPair<SphereShape, BoxShape, CollideSphereBox>(a, pose_a, b, pose_b, reach.Max(), prototype, out);
}

void CollideBoxPair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                    const ContactReach& reach, const ContactManifold& prototype,
                    std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  if (Rounded(AsConvex(a)) || Rounded(AsConvex(b))) {
    CollideConvexByGjk(a, pose_a, b, pose_b, reach, prototype, out, scratch);
    return;
  }
  AppendPair<BoxShape, BoxShape, CollideBoxes>(a, pose_a, b, pose_b, reach.Max(), prototype, out);
}

void CollidePolyhedronPair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                           const ContactReach& reach, const ContactManifold& prototype,
                           std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  thread_local Polyhedron polyhedron_a, polyhedron_b;
  if (Rounded(AsConvex(a)) || Rounded(AsConvex(b)) || !MakePolyhedron(AsConvex(a), pose_a, polyhedron_a) ||
      !MakePolyhedron(AsConvex(b), pose_b, polyhedron_b)) {
    CollideConvexByGjk(a, pose_a, b, pose_b, reach, prototype, out, scratch);
    return;
  }
  ContactManifold manifold = prototype;
  if (CollidePolyhedra(polyhedron_a, polyhedron_b, reach.Max(), manifold)) out.push_back(manifold);
}

void CollideConvexWithMesh(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                           const ContactReach& reach, const ContactManifold& prototype,
                           std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  CollideConvexMesh(AsConvex(a), pose_a, static_cast<const TriangleMeshShape&>(b), pose_b, reach, prototype,
                    out, scratch);
}

bool CollideConvexConvex(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                         float max_separation, ContactManifold& manifold) {
  CollisionScratch scratch;
  return CollideConvexConvex(a, pose_a, b, pose_b, max_separation, manifold, scratch);
}

bool CollideConvexConvex(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b, const Pose& pose_b,
                         float max_separation, ContactManifold& manifold, CollisionScratch& scratch) {
  // Reused, so a warm caller allocates nothing; a convex pair gives one manifold at most.
  thread_local std::vector<ContactManifold> found;
  found.clear();
  CollisionDispatch::Default().Collide(a, pose_a, b, pose_b, ContactReach{max_separation}, manifold, found,
                                       scratch);
  if (found.empty()) return false;
  manifold = found.front();
  return true;
}

void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, float max_separation, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out) {
  CollisionScratch scratch;
  CollideConvexMesh(a, pose_a, mesh, pose_mesh, max_separation, prototype, out, scratch);
}

void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, const ContactReach& reach, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  CollideConvexTriangles(a, pose_a, mesh, pose_mesh, reach, prototype, out, scratch);
}

void CollideConvexMesh(const ConvexShape& a, const Pose& pose_a, const TriangleMeshShape& mesh,
                       const Pose& pose_mesh, float max_separation, const ContactManifold& prototype,
                       std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  CollideConvexTriangles(a, pose_a, mesh, pose_mesh, ContactReach{max_separation}, prototype, out, scratch);
}

void CollideConvexWithHeightField(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                                  const ContactReach& reach, const ContactManifold& prototype,
                                  std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  CollideConvexTriangles(AsConvex(a), pose_a, static_cast<const HeightFieldShape&>(b), pose_b, reach,
                         prototype, out, scratch);
}

void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   float max_separation, const ContactManifold& prototype,
                   std::vector<ContactManifold>& out) {
  CollisionScratch scratch;
  CollideShapes(a, pose_a, b, pose_b, max_separation, prototype, out, scratch);
}

void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   const ContactReach& reach, const ContactManifold& prototype,
                   std::vector<ContactManifold>& out, CollisionScratch& scratch) {
  CollisionDispatch::Default().Collide(a, pose_a, b, pose_b, reach, prototype, out, scratch);
}

void CollideShapes(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                   float max_separation, const ContactManifold& prototype, std::vector<ContactManifold>& out,
                   CollisionScratch& scratch) {
  CollisionDispatch::Default().Collide(a, pose_a, b, pose_b, ContactReach{max_separation}, prototype, out,
                                       scratch);
}

}  // namespace strata
