// ClosestPoints: closest points between a point, segments and triangles (Ericson, Real-Time Collision
// Detection, 5.1), the exact building blocks of the closed-form contact tests. Pure functions; any thread.
#pragma once

#include "physics/math/Math.h"

namespace strata {

/// Closest point of triangle (a, b, c) to `point`.
Vec3 ClosestPointOnTriangle(const Vec3& point, const Vec3& a, const Vec3& b, const Vec3& c);

/// Closest points between segments p0-p1 and q0-q1.
void ClosestPointsOfSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3& on_p,
                             Vec3& on_q);

/// Closest points between segment p0-p1 and triangle (a, b, c) with unit normal `normal`. Returns false when
/// the segment passes through the triangle (the distance is 0 and no direction separates them).
bool ClosestPointsOfSegmentAndTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b,
                                       const Vec3& c, const Vec3& normal, Vec3& on_segment,
                                       Vec3& on_triangle);

}  // namespace strata
