// BenchScenes: the benchmark scenes (pyramid, convex_vs_mesh) described engine-neutrally, so Strata and
// the Bullet peer build exactly the same bodies. Pure data; build on any thread.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "physics/math/Math.h"
#include "physics/world/PhysicsSettings.h"

namespace strata::bench {

enum class BenchShape { kBox, kSphere, kCapsule, kHull, kMesh };

/// One body of a benchmark scene.
struct BenchBody {
  BenchShape shape;
  Vec3 half_extents = Vec3::Zero();  ///< box
  float radius = 0.0f;               ///< sphere, capsule
  float half_height = 0.0f;          ///< capsule
  Vec3 position = Vec3::Zero();
  bool dynamic = true;
  float friction = 0.5f;
  float restitution = 0.0f;
};

/// A scene plus the settings the engines run it with.
struct BenchScene {
  std::string name;
  std::vector<BenchBody> bodies;
  std::vector<Vec3> hull_points;    ///< shared by every kHull body
  std::vector<Vec3> mesh_vertices;  ///< shared by every kMesh body
  std::vector<std::array<std::uint32_t, 3>> mesh_triangles;
  float dt = 1.0f / 60.0f;
  int substeps = PhysicsSettings().substeps;
  int velocity_iterations = PhysicsSettings().velocity_iterations;  ///< per substep
  int relax_iterations = PhysicsSettings().relax_iterations;        ///< per substep
  bool sleeping = false;
  int steps = 500;
  /// Strata's body-pair cache reuse limits (m, degrees). Jolt's, as its PerformanceTest runs these scenes
  /// (Strata's own defaults are tighter); the Bullet peer has no such cache.
  float pair_cache_max_distance = 1e-3f;
  float pair_cache_max_angle = 2.0f;
};

/// 1240 boxes in a stepped pyramid on a floor (sleeping off, 10/2 iterations).
BenchScene MakePyramid();
/// 1764 mixed convex bodies dropped on a 100 x 100 cell wavy triangle mesh (4/1 iterations).
BenchScene MakeConvexVsMesh();
/// The scene called `name`, or an empty name when unknown.
BenchScene MakeBenchScene(const std::string& name);

}  // namespace strata::bench
