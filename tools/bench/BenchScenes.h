// BenchScenes: the benchmark scenes (pyramid, convex_vs_mesh, ragdolls, chains) described engine-neutrally,
// so Strata and the Bullet peer build exactly the same bodies and joints. Pure data; build on any thread.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "assets/scene/SceneDescription.h"

namespace strata::bench {

/// A benchmark scene (its bodies, joints, geometry and solver settings are SceneDescription's, which both
/// engines build from) and how it is run.
struct BenchScene : SceneDescription {
  int steps = 500;
  /// Strata's body-pair cache reuse limits (m, degrees). Jolt's, as its PerformanceTest runs these scenes
  /// (Strata's own defaults are tighter); the Bullet peer has no such cache.
  float pair_cache_max_distance = 1e-3f;
  float pair_cache_max_angle = 2.0f;
  /// Every dynamic body reports contact events (what they cost: `strata bench-gameplay`).
  bool report_contacts = false;
  /// The solver passes Jolt's PerformanceTest runs this scene with (its PhysicsSettings' mNumVelocitySteps
  /// and mNumPositionSteps, in one collision step), for the budget of that name.
  int jolt_velocity_steps = 10;
  int jolt_position_steps = 2;
};

/// Which solver passes a bench scene runs with: Strata's defaults (PhysicsSettings: substeps of a velocity
/// and a relax pass), or Jolt's own counts for the scene (one substep of Jolt's velocity steps, its position
/// steps as relax passes, one restitution pass), so both engines spend the same number of passes.
enum class SolverBudget { kStrata, kJolt };

/// `scene` with `budget`'s passes.
BenchScene WithSolverBudget(BenchScene scene, SolverBudget budget);
/// "strata" or "jolt".
const char* ToString(SolverBudget budget);

/// 1240 boxes in a stepped pyramid on a floor (sleeping off), Jolt's PerformanceTest pyramid: sharp boxes,
/// Jolt's default friction 0.2, no restitution; Jolt runs it at 10 velocity and 2 position steps.
BenchScene MakePyramid();
/// 1764 mixed convex bodies dropped on a 100 x 100 cell wavy triangle mesh, Jolt's PerformanceTest
/// ConvexVsMesh (friction 0.5, restitution 0.6, boxes and hulls rounded by 0.05 m; Jolt runs it at 4
/// velocity and 1 position steps).
BenchScene MakeConvexVsMesh();
/// 100 ragdolls of 12 parts (swing-twist and hinge joints) dropped in a heap on a height field.
BenchScene MakeRagdolls();
/// 20 chains of 40 capsule links, each with a 10 kg ball at its end, swung from 60 degrees into each other.
BenchScene MakeChains();
/// Adds one ragdoll standing with its pelvis at `pelvis`, turned by `rotation` about it.
void AddRagdoll(BenchScene& scene, const Vec3& pelvis, const Quat& rotation);
/// The scene called `name`, or an empty name when unknown.
BenchScene MakeBenchScene(const std::string& name);

}  // namespace strata::bench
