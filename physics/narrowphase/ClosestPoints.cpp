#include "physics/narrowphase/ClosestPoints.h"

#include <algorithm>

namespace strata {

Vec3 ClosestPointOnTriangle(const Vec3& point, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the vertices, then the edges, then the face.
  const Vec3 ab = b - a, ac = c - a, ap = point - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const Vec3 bp = point - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = point - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + (d2 / (d2 - d6)) * ac;
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const float denominator = 1.0f / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

void ClosestPointsOfSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3& on_p,
                             Vec3& on_q) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const float a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  float s = 0.0f, t = 0.0f;
  const float c = d1.dot(r), b = d1.dot(d2);
  if (e <= 0.0f) {
    // The second segment is a point (a sphere's core): the nearest point of the first one to it.
    s = a > 0.0f ? std::clamp(-c / a, 0.0f, 1.0f) : 0.0f;
    on_p = p0 + s * d1;
    on_q = q0;
    return;
  }
  const float denominator = a * e - b * b;
  if (denominator > 1e-12f) s = std::clamp((b * f - c * e) / denominator, 0.0f, 1.0f);
  t = (b * s + f) / e;
  if (t < 0.0f)
    t = 0.0f, s = a > 0.0f ? std::clamp(-c / a, 0.0f, 1.0f) : 0.0f;
  else if (t > 1.0f)
    t = 1.0f, s = a > 0.0f ? std::clamp((b - c) / a, 0.0f, 1.0f) : 0.0f;
  on_p = p0 + s * d1;
  on_q = q0 + t * d2;
}

bool ClosestPointsOfSegmentAndTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b,
                                       const Vec3& c, const Vec3& normal, Vec3& on_segment,
                                       Vec3& on_triangle) {
  const float h0 = normal.dot(p0 - a), h1 = normal.dot(p1 - a);
  if ((h0 <= 0.0f) != (h1 <= 0.0f) || h0 == 0.0f || h1 == 0.0f) {
    // The segment meets the triangle's plane: inside the triangle it passes through.
    const Vec3 crossing = h0 == h1 ? p0 : Vec3(p0 + (h0 / (h0 - h1)) * (p1 - p0));
    if (normal.dot((b - a).cross(crossing - a)) >= 0.0f && normal.dot((c - b).cross(crossing - b)) >= 0.0f &&
        normal.dot((a - c).cross(crossing - c)) >= 0.0f)
      return false;
  }
  // Otherwise the closest pair has an end of the segment or an edge of the triangle in it.
  float best = kLargeFloat;
  auto consider = [&](const Vec3& s, const Vec3& t) {
    const float distance = (t - s).squaredNorm();
    if (distance < best) best = distance, on_segment = s, on_triangle = t;
  };
  consider(p0, ClosestPointOnTriangle(p0, a, b, c));
  consider(p1, ClosestPointOnTriangle(p1, a, b, c));
  const Vec3* corners[3] = {&a, &b, &c};
  for (int edge = 0; edge < 3; ++edge) {
    Vec3 s, t;
    ClosestPointsOfSegments(p0, p1, *corners[edge], *corners[(edge + 1) % 3], s, t);
    consider(s, t);
  }
  return true;
}

}  // namespace strata
