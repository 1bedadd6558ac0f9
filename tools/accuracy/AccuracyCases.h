// AccuracyCases: the analytic cases of `strata accuracy` (free fall, friction on inclines, bounces,
// collisions, rolling, spin, energy over a minute, stacks, mass ratios, fast bodies against thin walls,
// motion far from the origin) and the grid of step settings they run at. Each case builds its scene on an
// AccuracyEngine, steps it, and measures its error against the closed-form answer (or an RK4 reference).
// Pure functions over the engine they are given; one thread per engine.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tools/accuracy/AccuracyEngine.h"

namespace strata::accuracy {

/// What one run measured.
struct CaseOutcome {
  double error = 0.0;  ///< in the case's unit; +inf when the case failed outright (a body fell off)
  bool finite = true;  ///< every body's state stayed finite (no NaN or infinity)
};

struct AccuracyCase {
  std::string name;
  std::string what;  ///< the question the case asks, one line
  std::string unit;  ///< "m", "relative", ...
  double tolerance;  ///< error at or below this passes
  std::function<Result<CaseOutcome>(AccuracyEngine&, const AccuracySetting&)> run;
};

/// Every case, in report order.
std::vector<AccuracyCase> AccuracyCases();
/// The settings grid: dt 1/30, 1/60, 1/120 x substeps 1, 2, 4, 8 (one velocity and one relax pass each),
/// ten velocity passes without substeps, and linear casts off once.
std::vector<AccuracySetting> AccuracySettings();
/// The world's defaults (PhysicsSettings) at dt 1/60 with linear casts on.
AccuracySetting DefaultAccuracySetting();

/// The `energy_drift` scene: a frictionless 1 kg unit box sliding at 3 m/s on a floor between two walls, e
/// = 1.
SceneDescription SlidingBoxScene();
/// The `mass_ratio_*` scenes: a unit box of `ratio` kg resting on a 1 kg one on a floor.
SceneDescription HeavyOnLightScene(float ratio);

/// RK4 reference for the intermediate-axis flip: the first time the spin about the middle axis of a free
/// body with principal `inertia` changes sign, starting from body-frame `spin` (s; < 0 if none by `limit`).
double IntermediateAxisFlipTime(const Vec3& inertia, const Vec3& spin, double limit);

}  // namespace strata::accuracy
