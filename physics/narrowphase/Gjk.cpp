#include "physics/narrowphase/Gjk.h"

#include <algorithm>
#include <utility>

namespace strata {

namespace {

// The simplex solver works in double precision: a large box (a level floor) against a small one makes
// Minkowski vertices ~100 m apart while the answer is ~1 mm, which float Voronoi tests cannot resolve.
using Vec3d = Eigen::Vector3d;

// Closest point to the origin on triangle abc with barycentric weights (Ericson, Real-Time Collision
// Detection 5.1.5). Returns the bit mask of the vertices that support it.
int ClosestOnTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c, double weights[3]) {
  const Vec3d ab = b - a, ac = c - a;
  const double d1 = ab.dot(-a), d2 = ac.dot(-a);
  if (d1 <= 0.0f && d2 <= 0.0f) {
    weights[0] = 1;
    return 0b001;
  }
  const double d3 = ab.dot(-b), d4 = ac.dot(-b);
  if (d3 >= 0.0f && d4 <= d3) {
    weights[1] = 1;
    return 0b010;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
    const double v = d1 / (d1 - d3);
    weights[0] = 1 - v, weights[1] = v;
    return 0b011;
  }
  const double d5 = ab.dot(-c), d6 = ac.dot(-c);
  if (d6 >= 0.0f && d5 <= d6) {
    weights[2] = 1;
    return 0b100;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
    const double w = d2 / (d2 - d6);
    weights[0] = 1 - w, weights[2] = w;
    return 0b101;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    weights[1] = 1 - w, weights[2] = w;
    return 0b110;
  }
  const double sum = va + vb + vc;
  if (sum == 0.0f) {  // degenerate triangle: fall back to its best edge
    weights[0] = 1;
    return 0b001;
  }
  const double denominator = 1.0 / sum;
  weights[1] = vb * denominator, weights[2] = vc * denominator;
  weights[0] = 1 - weights[1] - weights[2];
  return 0b111;
}

// True when the origin and `opposite` lie on different sides of plane abc.
bool OriginOutsideFace(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& opposite) {
  const Vec3d normal = (b - a).cross(c - a);
  const double side_origin = normal.dot(-a);
  const double side_opposite = normal.dot(opposite - a);
  return side_origin * side_opposite < 0.0;
}

void Keep(SimplexVertex* simplex, int& count, float* weights, const double* all_weights, int mask) {
  // In place: the kept vertices keep their order, so each moves down or stays. Most calls keep the whole
  // simplex or drop its last vertices, and move nothing.
  int n = 0;
  for (int i = 0; i < count; ++i) {
    if ((mask & (1 << i)) == 0) continue;
    if (n != i) simplex[n] = simplex[i];
    weights[n++] = static_cast<float>(all_weights[i]);
  }
  count = n;
}

}  // namespace

bool ClosestPointOnSimplex(SimplexVertex* simplex, int& count, float* weights, Vec3& closest) {
  double all[4] = {0, 0, 0, 0};
  Vec3d w[4];
  for (int i = 0; i < count; ++i) w[i] = simplex[i].w.cast<double>();
  int mask = 0;
  switch (count) {
    case 1:
      all[0] = 1, mask = 1;
      break;
    case 2: {
      const Vec3d edge = w[1] - w[0];
      const double length2 = edge.squaredNorm();
      const double t = length2 > 0.0 ? std::clamp(-w[0].dot(edge) / length2, 0.0, 1.0) : 0.0;
      if (t <= 0.0)
        all[0] = 1, mask = 0b01;
      else if (t >= 1.0)
        all[1] = 1, mask = 0b10;
      else
        all[0] = 1 - t, all[1] = t, mask = 0b11;
      break;
    }
    case 3:
      mask = ClosestOnTriangle(w[0], w[1], w[2], all);
      break;
    default: {
      // Test each face the origin lies outside of; keep the closest result. A flat tetrahedron (the new
      // vertex on the plane of the other three: a tie between two support points of one face) encloses
      // nothing, but its faces' side tests cannot say so: every face is a candidate then.
      static constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
      const double size = std::max({(w[1] - w[0]).norm(), (w[2] - w[0]).norm(), (w[3] - w[0]).norm()});
      const bool flat =
          std::abs((w[1] - w[0]).dot((w[2] - w[0]).cross(w[3] - w[0]))) <= 1e-6 * size * size * size;
      double best = 1e300;
      bool any_outside = false;
      for (const auto& f : kFaces) {
        if (!flat && !OriginOutsideFace(w[f[0]], w[f[1]], w[f[2]], w[f[3]])) continue;
        any_outside = true;
        double face_weights[3] = {0, 0, 0};
        const int face_mask = ClosestOnTriangle(w[f[0]], w[f[1]], w[f[2]], face_weights);
        Vec3d point = Vec3d::Zero();
        for (int k = 0; k < 3; ++k) point += face_weights[k] * w[f[k]];
        if (point.squaredNorm() < best) {
          best = point.squaredNorm();
          mask = 0;
          for (int i = 0; i < 4; ++i) all[i] = 0;
          for (int k = 0; k < 3; ++k)
            if (face_mask & (1 << k)) mask |= 1 << f[k], all[f[k]] = face_weights[k];
        }
      }
      if (!any_outside) {
        closest = Vec3::Zero();
        return false;
      }
      break;
    }
  }
  Keep(simplex, count, weights, all, mask);
  Vec3d closest_double = Vec3d::Zero();
  for (int i = 0; i < 4; ++i)
    if (mask & (1 << i)) closest_double += all[i] * w[i];
  closest = closest_double.cast<float>();
  return true;
}

GjkResult GjkClosestPoints(const ConvexSupport& a, const ConvexSupport& b, float max_distance) {
  return GjkClosestPointsOf(a, b, max_distance);
}

}  // namespace strata
