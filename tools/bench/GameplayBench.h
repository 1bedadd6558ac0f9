// GameplayBench: what game code costs on a world: shape casts on the streamed 20,000-body open world
// (bench-broadphase's, every body a box of its bounds) with Bullet's convex sweep on the same boxes beside
// them; the pyramid stepped with every body reporting contact events against none; and the virtual
// character's update walking the bundled courtyard. Prints figures only (`strata bench-gameplay`). Call from
// the main thread.
#pragma once

#include <string>
#include <vector>

#include "physics/core/Result.h"
#include "tools/bench/BroadPhaseBench.h"

namespace strata::bench {

/// The swept shapes: a sphere (0.5 m) and a standing capsule (0.3 m radius, 1.8 m tall).
enum class CastShapeKind { kSphere, kCapsule };
const char* ToString(CastShapeKind kind);

/// One engine's casts: each query origin swept 10 m along its direction, closest hit.
struct CastRun {
  double casts_per_second = -1.0;  ///< best of the repeats, one thread
  int hits = 0;
  std::vector<float> fractions;  ///< per cast, -1 for a miss
};

/// Strata's WorldQuery::CastShape over `world` as boxes; fastest of `repeats` passes.
CastRun MeasureStrataCasts(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape, int repeats);
#ifdef STRATA_HAVE_BULLET
/// Bullet's btCollisionWorld::convexSweepTest (closest hit) on the same boxes.
CastRun MeasureBulletCasts(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape, int repeats);
#endif

/// The exact fraction of every cast, the reference both engines are measured against: each box near the
/// sweep by its distance to the swept shape's core (a point, or the capsule's upright segment, both exact
/// against an axis-aligned box), which is convex along the cast, so its first touch is found by bisection to
/// double precision. -1 for a miss, 0 where the shape starts inside a box.
std::vector<float> ExactCastFractions(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape);
/// The exact gap (m, negative for an overlap) between each cast's shape at `fractions` and the nearest box;
/// NaN where a fraction is negative (a miss).
std::vector<double> ExactGapsAt(const OpenWorld& world, const QuerySet& queries, CastShapeKind shape,
                                const std::vector<float>& fractions);

/// One engine's casts against the exact ones (distances along the cast, mm).
struct CastAccuracy {
  int exact_hits = 0;               ///< casts that touch a box, starts inside included
  int starts_inside = 0;            ///< casts that start inside a box
  int within_1mm = 0;               ///< hits within 1 mm of the exact first touch
  double earliest_mm = 0.0;         ///< the hit furthest before the exact one (<= 0)
  double latest_mm = 0.0;           ///< the hit furthest past it (>= 0)
  double mean_abs_mm = 0.0;         ///< over the casts both hit
  double widest_gap_mm = 0.0;       ///< the most space left between shape and box at a reported hit
  double deepest_overlap_mm = 0.0;  ///< the deepest a reported hit overlaps a box (starts inside left out)
  int missed = 0;                   ///< exact hits the engine does not report
  int missed_inside = 0;            ///< of those, starts inside a box
  int false_hits = 0;               ///< hits where the exact cast touches nothing
};
CastAccuracy MeasureCastAccuracy(const CastRun& run, const std::vector<float>& exact,
                                 const std::vector<double>& gaps, float cast_length);

/// The pyramid's step with and without every body reporting contact events: each run's median step, the
/// median over alternated runs.
struct EventFigures {
  int threads = 1;
  double quiet_step_ms = 0.0;      ///< no body asks for events
  double reporting_step_ms = 0.0;  ///< every body reports contacts
  double events_per_step = 0.0;    ///< contact begin + persist + end, averaged over the run
};
EventFigures MeasureEventCost(int threads, int steps, int rounds);

/// Character::Update walking random routes through the courtyard (`walkers` characters, `frames` each).
struct CharacterFigures {
  int updates = 0;
  double mean_us = 0.0;
  double median_us = 0.0;
  double p99_us = 0.0;
  double max_us = 0.0;
};
/// The level's error when it does not load.
Result<CharacterFigures> MeasureCharacterUpdates(const std::string& level, int walkers, int frames);

}  // namespace strata::bench
