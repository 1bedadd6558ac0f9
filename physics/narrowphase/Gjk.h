// GJK: distance and closest points between two convex support mappings (Gilbert-Johnson-Keerthi with
// Ericson's Voronoi-region simplex solver). Pure functions; safe from any thread.
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/narrowphase/ConvexSupport.h"

namespace strata {

/// A vertex of the Minkowski difference A - B with the two support points that made it.
struct SimplexVertex {
  Vec3 w, a, b;
};

/// Outcome of a GJK distance query.
struct GjkResult {
  bool overlapping = false;  ///< the shapes intersect (distance 0); `simplex` then seeds EPA
  float distance = 0.0f;     ///< distance between the shapes when not overlapping
  Vec3 point_a = Vec3::Zero();
  Vec3 point_b = Vec3::Zero();
  /// When not overlapping: the point of A - B nearest the origin that the search reached; its opposite points
  /// from A towards B, and the shapes are apart along it (by `distance`, or more when stopped early).
  Vec3 nearest_difference = Vec3::Zero();
  SimplexVertex simplex[4];
  int simplex_count = 0;
};

/// Closest point of the simplex to the origin; shrinks the simplex to the vertices that support it and
/// writes their barycentric weights. Returns false when the origin is inside a full tetrahedron.
bool ClosestPointOnSimplex(SimplexVertex* simplex, int& count, float* weights, Vec3& closest);

/// Closest points of A and B. Stops early once the shapes are known to be farther apart than
/// `max_distance`: it then reports a lower bound above `max_distance` and no closest points.
/// A template over the two support mappings so that the narrow phase's hot pairs (a posed convex against a
/// mesh triangle, two posed convexes: final classes) call their supports directly, a dozen times a pair.
template <class SupportA, class SupportB>
GjkResult GjkClosestPointsOf(const SupportA& a, const SupportB& b, float max_distance);

/// The same through the virtual ConvexSupport interface, for any mapping.
GjkResult GjkClosestPoints(const ConvexSupport& a, const ConvexSupport& b, float max_distance);

template <class SupportA, class SupportB>
GjkResult GjkClosestPointsOf(const SupportA& a, const SupportB& b, float max_distance) {
  GjkResult result;
  Vec3 v = a.Center() - b.Center();
  if (v.squaredNorm() < 1e-12f) v = Vec3::UnitX();
  float weights[4] = {1, 0, 0, 0};
  constexpr int kMaxIterations = 48;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const Vec3 direction = -v;
    SimplexVertex vertex;
    vertex.a = a.Support(direction);
    vertex.b = b.Support(-direction);
    vertex.w = vertex.a - vertex.b;
    const float v_length2 = v.squaredNorm();
    const float progress = v.dot(vertex.w);
    // Separating axis farther than anyone cares about.
    if (progress > 0.0f && progress * progress > max_distance * max_distance * v_length2 &&
        result.simplex_count > 0) {
      result.distance = std::sqrt(progress * progress / v_length2);
      result.nearest_difference = v;
      return result;
    }
    // No more progress towards the origin: v is the closest point.
    if (result.simplex_count > 0 && v_length2 - progress <= 1e-6f * v_length2) break;
    bool duplicate = false;
    for (int i = 0; i < result.simplex_count; ++i)
      duplicate |= (result.simplex[i].w - vertex.w).squaredNorm() < 1e-14f;
    if (duplicate) break;
    // Kept to go back to: near touching, float rounding can make a new vertex pull the simplex away.
    SimplexVertex previous[4];
    float previous_weights[4];
    const int previous_count = result.simplex_count;
    std::copy_n(result.simplex, previous_count, previous);
    std::copy_n(weights, previous_count, previous_weights);
    result.simplex[result.simplex_count++] = vertex;
    Vec3 closest;
    if (!ClosestPointOnSimplex(result.simplex, result.simplex_count, weights, closest) ||
        closest.squaredNorm() < 1e-10f) {
      result.overlapping = true;
      return result;
    }
    // Guard against cycling: the distance must shrink every iteration. One that grew ends the search at the
    // simplex before it (its closest point is v), not at the worse one.
    if (closest.squaredNorm() >= v_length2 && iteration > 0) {
      std::copy_n(previous, previous_count, result.simplex);
      std::copy_n(previous_weights, previous_count, weights);
      result.simplex_count = previous_count;
      break;
    }
    v = closest;
  }
  result.distance = v.norm();
  result.nearest_difference = v;
  result.point_a = Vec3::Zero();
  result.point_b = Vec3::Zero();
  for (int i = 0; i < result.simplex_count; ++i) {
    result.point_a += weights[i] * result.simplex[i].a;
    result.point_b += weights[i] * result.simplex[i].b;
  }
  return result;
}

}  // namespace strata
