#include "physics/narrowphase/ManifoldBuilder.h"

#include <array>

namespace strata {

namespace {

using Polygon = std::array<Vec3, 64>;

// Sutherland-Hodgman: keeps the part of `polygon` on the inner side (plane_normal . (p - plane_point) <= 0).
int ClipAgainstPlane(const Polygon& in, int count, const Vec3& plane_point, const Vec3& plane_normal,
                     Polygon& out) {
  int written = 0;
  if (count == 0) return 0;
  Vec3 previous = in[count - 1];
  float previous_distance = plane_normal.dot(previous - plane_point);
  for (int i = 0; i < count; ++i) {
    const Vec3& current = in[i];
    const float distance = plane_normal.dot(current - plane_point);
    if ((previous_distance <= 0.0f) != (distance <= 0.0f) && written < 63) {
      const float t = previous_distance / (previous_distance - distance);
      out[written++] = previous + t * (current - previous);
    }
    if (distance <= 0.0f && written < 63) out[written++] = current;
    previous = current;
    previous_distance = distance;
  }
  return written;
}

Vec3 FaceNormal(const SupportingFace& face) {
  if (face.normal != Vec3::Zero()) return face.normal;
  Vec3 normal = Vec3::Zero();
  // Newell's method: robust for any planar polygon.
  for (int i = 0; i < face.count; ++i) {
    const Vec3& p = face.vertices[i];
    const Vec3& q = face.vertices[(i + 1) % face.count];
    normal += (p - q).cross(p + q) * 0.5f;
  }
  const float length = normal.norm();
  return length > 1e-12f ? Vec3(normal / length) : Vec3::Zero();
}

}  // namespace

int ReduceContactPoints(ContactPoint* points, int count, const Vec3& normal) {
  if (count <= ContactManifold::kMaxPoints) return count;
  // 1: deepest. 2: farthest from it. 3: largest triangle. 4: largest area added on the other side.
  int chosen[4];
  chosen[0] = 0;
  for (int i = 1; i < count; ++i)
    if (points[i].separation < points[chosen[0]].separation) chosen[0] = i;
  auto position = [&](int i) { return points[i].position_b; };
  float best = -1.0f;
  chosen[1] = chosen[0];
  for (int i = 0; i < count; ++i) {
    const float d = (position(i) - position(chosen[0])).squaredNorm();
    if (d > best) best = d, chosen[1] = i;
  }
  best = -1.0f;
  chosen[2] = chosen[0];
  float signed_area = 0.0f;
  for (int i = 0; i < count; ++i) {
    const float area =
        (position(chosen[0]) - position(i)).cross(position(chosen[1]) - position(i)).dot(normal);
    if (std::abs(area) > best) best = std::abs(area), chosen[2] = i, signed_area = area;
  }
  best = -1.0f;
  chosen[3] = chosen[0];
  for (int i = 0; i < count; ++i) {
    // The fourth point should lie on the opposite side of edge (chosen[0], chosen[1]) from chosen[2].
    const float area =
        (position(chosen[0]) - position(i)).cross(position(chosen[1]) - position(i)).dot(normal);
    const float gain = signed_area > 0 ? -area : area;
    if (gain > best) best = gain, chosen[3] = i;
  }
  ContactPoint kept[4];
  int kept_count = 0;
  for (int c : chosen) {
    bool duplicate = false;
    for (int k = 0; k < kept_count; ++k)
      duplicate |= (kept[k].position_b - points[c].position_b).squaredNorm() < 1e-10f;
    if (!duplicate) kept[kept_count++] = points[c];
  }
  for (int i = 0; i < kept_count; ++i) points[i] = kept[i];
  return kept_count;
}

void AppendFacePoint(const Vec3& incident, const Vec3& on_reference, bool reference_is_a, const Vec3& normal,
                     float max_separation, ContactPoint* points, int& count) {
  ContactPoint point;
  point.position_a = reference_is_a ? on_reference : incident;
  point.position_b = reference_is_a ? incident : on_reference;
  point.separation = (point.position_b - point.position_a).dot(normal);
  if (point.separation <= max_separation) points[count++] = point;
}

void SetManifoldPoints(ContactPoint* points, int count, ContactManifold& manifold) {
  count = ReduceContactPoints(points, count, manifold.normal);
  for (int i = 0; i < count; ++i) manifold.points[i] = points[i];
  manifold.count = count;
}

void BuildManifold(const SupportingFace& face_a, const SupportingFace& face_b, const ContactPoint& deepest,
                   float max_separation, ContactManifold& manifold) {
  const Vec3& n = manifold.normal;
  manifold.count = 0;
  // The reference face is the flatter-facing polygon; the other one (incident) is clipped against it.
  const Vec3 normal_a = face_a.count >= 3 ? FaceNormal(face_a) : Vec3::Zero();
  const Vec3 normal_b = face_b.count >= 3 ? FaceNormal(face_b) : Vec3::Zero();
  const float alignment_a = normal_a.dot(n);
  const float alignment_b = -normal_b.dot(n);
  const bool reference_is_a = alignment_a >= alignment_b;
  const SupportingFace& reference = reference_is_a ? face_a : face_b;
  const SupportingFace& incident = reference_is_a ? face_b : face_a;
  const Vec3 reference_normal = reference_is_a ? normal_a : normal_b;
  const float alignment = reference_is_a ? alignment_a : alignment_b;

  if (reference.count >= 3 && alignment > 0.1f && incident.count >= 1) {
    // Two buffers that trade roles each clipping plane (swapping pointers, not 64 vertices).
    Polygon buffers[2];
    Polygon* polygon = &buffers[0];
    Polygon* clipped = &buffers[1];
    int count = 0;
    for (int i = 0; i < incident.count; ++i) (*polygon)[count++] = incident.vertices[i];
    for (int i = 0; i < reference.count && count > 0; ++i) {
      const Vec3& p = reference.vertices[i];
      const Vec3& q = reference.vertices[(i + 1) % reference.count];
      const Vec3 side = (q - p).cross(reference_normal);  // outward for counter-clockwise faces
      if (count == 1) {
        if (side.dot((*polygon)[0] - p) > 1e-6f) count = 0;
        continue;
      }
      if (count == 2) {
        // Clip a segment.
        Polygon& segment = *polygon;
        const float d0 = side.dot(segment[0] - p), d1 = side.dot(segment[1] - p);
        if (d0 > 0 && d1 > 0) {
          count = 0;
        } else if (d0 > 0) {
          segment[0] = segment[0] + d0 / (d0 - d1) * (segment[1] - segment[0]);
        } else if (d1 > 0) {
          segment[1] = segment[0] + d0 / (d0 - d1) * (segment[1] - segment[0]);
        }
        continue;
      }
      count = ClipAgainstPlane(*polygon, count, p, side, *clipped);
      std::swap(polygon, clipped);
    }
    const Vec3& plane_point = reference.vertices[0];
    const float denominator = n.dot(reference_normal);
    ContactPoint points[64];
    int point_count = 0;
    for (int i = 0; i < count; ++i) {
      // Project the incident point onto the reference plane along the contact normal.
      const Vec3& incident_point = (*polygon)[i];
      const float t = (plane_point - incident_point).dot(reference_normal) / denominator;
      AppendFacePoint(incident_point, incident_point + t * n, reference_is_a, n, max_separation, points,
                      point_count);
    }
    SetManifoldPoints(points, point_count, manifold);
  }
  if (manifold.count == 0 && deepest.separation <= max_separation) {
    manifold.points[0] = deepest;
    manifold.count = 1;
  }
}

void KeepNoDeeperThan(const ContactPoint& deepest, ContactManifold& manifold) {
  for (int i = 0; i < manifold.count; ++i) {
    ContactPoint& point = manifold.points[i];
    const float excess = deepest.separation - point.separation;
    if (excess <= 0.0f) continue;
    point.position_a -= (0.5f * excess) * manifold.normal;
    point.position_b += (0.5f * excess) * manifold.normal;
    point.separation = deepest.separation;
  }
}

}  // namespace strata
