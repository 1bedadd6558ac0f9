// EPA: penetration depth, normal and deepest points of two overlapping convex support mappings
// (Expanding Polytope Algorithm), seeded by the simplex GJK ended with. Pure; safe from any thread.
#pragma once

#include <utility>
#include <vector>

#include "physics/narrowphase/Gjk.h"

namespace strata {

/// How far and along which direction B must move to separate from A.
struct PenetrationResult {
  Vec3 normal = Vec3::UnitY();  ///< unit, from A towards B
  float depth = 0.0f;           ///< >= 0
  Vec3 point_a = Vec3::Zero();  ///< deepest point of A inside B
  Vec3 point_b = Vec3::Zero();  ///< deepest point of B inside A
};

/// One triangle of the expanding polytope.
struct EpaFace {
  int a, b, c;
  Vec3 normal;
  float distance;
  bool alive;
};

/// Buffers EPA grows into; one per thread or job, reused so a warm caller allocates nothing.
struct EpaScratch {
  std::vector<SimplexVertex> vertices;
  std::vector<EpaFace> faces;
  std::vector<std::pair<int, int>> horizon;
};

/// Expands the GJK simplex into a polytope around the origin. Returns false when the shapes only touch
/// (no volume of overlap could be built) or the polytope degenerates.
bool EpaPenetration(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk,
                    PenetrationResult& out, EpaScratch& scratch);
/// The same with buffers of its own.
bool EpaPenetration(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk,
                    PenetrationResult& out);

}  // namespace strata
