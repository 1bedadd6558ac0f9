// GameplayBench: what game code costs on a world: shape casts on the streamed 20,000-body open world
// (bench-broadphase's, every body a box of its bounds) with Bullet's convex sweep on the same boxes beside
// them; the pyramid stepped with every body reporting contact events against none; and the virtual
// character's update walking the bundled courtyard. Prints figures only (`strata bench-gameplay`). Call from
// the main thread.
#pragma once

#include <string>
#include <vector>

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

/// How two engines' casts compare: hits within `tolerance` of the same fraction, hits one of them places
/// earlier, and casts only one of them hits (at the start: a shape that starts inside a box).
struct CastAgreement {
  int both_hit = 0;
  int same_place = 0;
  int a_earlier = 0;
  int b_earlier = 0;
  int only_a_at_start = 0;
  int only_a = 0;
  int only_b = 0;
};
CastAgreement CompareCasts(const CastRun& a, const CastRun& b, float tolerance);

/// The pyramid's step with and without every body reporting contact events (medians of alternated runs).
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
CharacterFigures MeasureCharacterUpdates(const std::string& level, int walkers, int frames);

}  // namespace strata::bench
