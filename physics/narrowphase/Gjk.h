// GJK: distance and closest points between two convex support mappings (Gilbert-Johnson-Keerthi with
// Ericson's Voronoi-region simplex solver). Pure functions; safe from any thread.
#pragma once

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
  SimplexVertex simplex[4];
  int simplex_count = 0;
};

/// Closest points of A and B. Stops early once the shapes are known to be farther apart than
/// `max_distance`: it then reports a lower bound above `max_distance` and no closest points.
GjkResult GjkClosestPoints(const ConvexSupport& a, const ConvexSupport& b, float max_distance);

/// Closest point of the simplex to the origin; shrinks the simplex to the vertices that support it and
/// writes their barycentric weights. Returns false when the origin is inside a full tetrahedron.
bool ClosestPointOnSimplex(SimplexVertex* simplex, int& count, float* weights, Vec3& closest);

}  // namespace strata
