// SceneDescription: a physics scene in no engine's types: bodies by shape kind and size, pose, motion and
// material; joints by kind and world frame; the shared geometry of hulls, meshes and height fields; the
// step's settings. The benchmarks and the accuracy cases describe their scenes this way so Strata and Bullet
// build the very same bodies; SceneBuilder makes Strata's bodies from it. Plain data; any thread.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "physics/PhysicsSettings.h"
#include "physics/math/Math.h"

namespace strata {

enum class SceneShape : std::uint8_t { kBox, kSphere, kCapsule, kHull, kMesh, kHeightField };

/// One body. Hull, mesh and height-field bodies use the scene's one hull, mesh or height field.
struct BodyDescription {
  SceneShape shape = SceneShape::kBox;
  Vec3 half_extents = Vec3::Constant(0.5f);  ///< box
  float radius = 0.5f;                       ///< sphere, capsule
  float half_height = 0.5f;                  ///< capsule: half the length of its core
  Vec3 position = Vec3::Zero();              ///< a height field's is its sample (0, 0)
  bool dynamic = true;                       ///< else static
  float friction = 0.5f;
  float restitution = 0.0f;
  Quat rotation = Quat::Identity();
  float mass = 0.0f;  ///< kg; 0: the shape's volume at Strata's default density (1000 kg/m^3)
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

enum class JointKind : std::uint8_t { kPoint, kHinge, kSwingTwist };

/// One joint, in world space where the bodies are made.
struct JointDescription {
  JointKind kind = JointKind::kPoint;
  int body_a = -1;  ///< index into SceneDescription::bodies; -1: the world
  int body_b = 0;
  Vec3 anchor = Vec3::Zero();
  Vec3 axis = Vec3::UnitY();    ///< hinge axis, or twist axis
  Vec3 normal = Vec3::UnitZ();  ///< at right angles to the axis: a hinge's angle 0, a twist's reference
  float min_angle = 0.0f;       ///< hinge limits, or twist limits (rad)
  float max_angle = 0.0f;
  float cone = 0.0f;  ///< swing-twist: the swing cone's half angle (rad)
};

/// Bodies, joints and their shared geometry, and how a step of the scene is solved.
struct SceneDescription {
  std::string name;
  std::vector<BodyDescription> bodies;
  std::vector<JointDescription> joints;
  std::vector<Vec3> hull_points;    ///< the hull of every kHull body
  std::vector<Vec3> mesh_vertices;  ///< the mesh of every kMesh body
  std::vector<std::array<std::uint32_t, 3>> mesh_triangles;
  /// The height field of every kHeightField body: row-major heights, z rows of x samples.
  std::uint32_t field_columns = 0;
  std::uint32_t field_rows = 0;
  float field_cell = 1.0f;
  std::vector<float> field_heights;
  Vec3 gravity = PhysicsSettings().gravity;
  float dt = 1.0f / 60.0f;
  int substeps = PhysicsSettings().substeps;
  int velocity_iterations = PhysicsSettings().velocity_iterations;  ///< per substep
  int relax_iterations = PhysicsSettings().relax_iterations;        ///< per substep
  bool sleeping = false;
  /// Approaches slower than this (m/s) do not bounce, in every engine (Strata's default).
  float min_velocity_for_restitution = PhysicsSettings().min_velocity_for_restitution;
};

}  // namespace strata
