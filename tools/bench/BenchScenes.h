// BenchScenes: the benchmark scenes (pyramid, convex_vs_mesh, ragdolls, chains) described engine-neutrally,
// so Strata and the Bullet peer build exactly the same bodies and joints. Pure data; build on any thread.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "physics/math/Math.h"
#include "physics/PhysicsSettings.h"

namespace strata::bench {

enum class BenchShape { kBox, kSphere, kCapsule, kHull, kMesh, kHeightField };

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
  Quat rotation = Quat::Identity();
  float mass = 0.0f;  ///< kg; 0: the shape's volume at Strata's default density
};

enum class BenchJointKind { kPoint, kHinge, kSwingTwist };

/// One joint of a benchmark scene, in world space where the bodies are made.
struct BenchJoint {
  BenchJointKind kind = BenchJointKind::kPoint;
  int body_a = -1;  ///< index into BenchScene::bodies; -1: the world
  int body_b = 0;
  Vec3 anchor = Vec3::Zero();
  Vec3 axis = Vec3::UnitY();    ///< hinge axis, or twist axis
  Vec3 normal = Vec3::UnitZ();  ///< at right angles to the axis: a hinge's angle 0, a twist's reference
  float min_angle = 0.0f;       ///< hinge limits, or twist limits (rad)
  float max_angle = 0.0f;
  float cone = 0.0f;  ///< swing-twist: the swing cone's half angle (rad)
};

/// A scene plus the settings the engines run it with.
struct BenchScene {
  std::string name;
  std::vector<BenchBody> bodies;
  std::vector<Vec3> hull_points;    ///< shared by every kHull body
  std::vector<Vec3> mesh_vertices;  ///< shared by every kMesh body
  std::vector<std::array<std::uint32_t, 3>> mesh_triangles;
  /// Shared by every kHeightField body (its position is sample (0, 0)): row-major heights, z rows of x.
  std::uint32_t field_columns = 0;
  std::uint32_t field_rows = 0;
  float field_cell = 1.0f;
  std::vector<float> field_heights;
  std::vector<BenchJoint> joints;
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
  /// Every dynamic body reports contact events (what they cost: `strata bench-gameplay`).
  bool report_contacts = false;
};

/// 1240 boxes in a stepped pyramid on a floor (sleeping off, 10/2 iterations).
BenchScene MakePyramid();
/// 1764 mixed convex bodies dropped on a 100 x 100 cell wavy triangle mesh (4/1 iterations).
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
