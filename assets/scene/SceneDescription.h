// SceneDescription: a physics scene in no engine's types: bodies by shape kind and size, pose, motion and
// material; joints by kind and world frame; the geometry of hulls, meshes and height fields; the step's
// settings. The scene loader parses files into it, and the benchmarks and accuracy cases describe their
// scenes with it so Strata and Bullet build the very same bodies; SceneBuilder makes Strata's bodies from
// it. Plain data; any thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "physics/PhysicsSettings.h"
#include "physics/math/Math.h"

namespace strata {

enum class SceneShape : std::uint8_t { kBox, kSphere, kCapsule, kHull, kMesh, kHeightField };
enum class SceneMotion : std::uint8_t { kStatic, kKinematic, kDynamic };

/// A convex hull's points (at least 4 spanning a volume).
struct HullGeometry {
  std::vector<Vec3> points;
};

/// A triangle mesh, triangles counter-clockwise seen from their solid side's outside.
struct MeshGeometry {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// A height field: row-major heights, `rows` rows of `columns` samples `cell` metres apart.
struct HeightFieldGeometry {
  std::uint32_t columns = 0;
  std::uint32_t rows = 0;
  float cell = 1.0f;
  std::vector<float> heights;
};

/// One body. The unset optional tunings are each engine's own defaults.
struct BodyDescription {
  std::string name;
  SceneShape shape = SceneShape::kBox;
  Vec3 half_extents = Vec3::Constant(0.5f);  ///< box
  float radius = 0.5f;                       ///< sphere, capsule
  float half_height = 0.5f;                  ///< capsule: half the length of its core
  /// Box, hull: how far its edges and corners are rounded, inside its extents (m; 0: sharp). Unset: the
  /// engine's default (Strata: 0.05, less for a small shape; BoxShape::DefaultConvexRadius).
  std::optional<float> convex_radius;
  /// Hull, mesh and height-field bodies: which of the scene's hulls, meshes or height fields.
  std::uint32_t geometry = 0;
  Vec3 position = Vec3::Zero();  ///< a height field's is its sample (0, 0)
  Quat rotation = Quat::Identity();
  SceneMotion motion = SceneMotion::kDynamic;
  bool linear_cast = false;  ///< swept each step and stopped at its first hit (no tunnelling)
  float friction = 0.5f;
  float restitution = 0.0f;
  float mass = 0.0f;             ///< kg; 0: from the density
  std::optional<float> density;  ///< kg/m^3; unset: Strata's default (1000)
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  std::optional<float> linear_damping;
  std::optional<float> angular_damping;
  std::optional<float> gravity_factor;
  std::optional<float> max_linear_velocity;   ///< m/s
  std::optional<float> max_angular_velocity;  ///< rad/s
  bool allow_sleeping = true;
  bool sensor = false;  ///< reports what enters and leaves it and collides with nothing
  bool sensor_detects_static = false;
  bool report_contacts = false;

  bool IsDynamic() const { return motion == SceneMotion::kDynamic; }
};

enum class JointKind : std::uint8_t { kFixed, kPoint, kDistance, kHinge, kSlider, kSwingTwist };

/// One joint, in world space where the bodies are made. Each kind reads the fields its comment names.
struct JointDescription {
  std::string name;
  JointKind kind = JointKind::kPoint;
  int body_a = -1;  ///< index into SceneDescription::bodies; -1: the world
  int body_b = 0;
  Vec3 anchor = Vec3::Zero();    ///< all but distance; distance: the anchor on body A
  Vec3 anchor_b = Vec3::Zero();  ///< distance: the anchor on body B
  Vec3 axis = Vec3::UnitY();     ///< hinge and slider axis, or swing-twist's twist axis
  /// Hinge and swing-twist: at right angles to the axis, the angle 0's direction (zero: any).
  Vec3 normal = Vec3::UnitZ();
  bool limits = false;         ///< hinge, slider: keep within [min_limit, max_limit]; swing-twist always does
  float min_limit = -kPi;      ///< hinge angle or twist (rad, [-pi, 0]), slider position (m, <= 0)
  float max_limit = kPi;       ///< hinge angle or twist (rad, [0, pi]), slider position (m, >= 0)
  float cone = 0.5f * kPi;     ///< swing-twist: the swing cone's half angle (rad)
  float max_friction = 0.0f;   ///< hinge, swing-twist: N m; slider: N
  bool motor = false;          ///< hinge, slider: driven at motor_speed with at most motor_max
  float motor_speed = 0.0f;    ///< rad/s or m/s
  float motor_max = 0.0f;      ///< N m or N
  float rest_length = -1.0f;   ///< distance: negative: the anchors' distance
  float min_distance = -1.0f;  ///< distance: negative: the rest length
  float max_distance = -1.0f;  ///< distance: negative: the rest length
  float spring_hertz = 0.0f;   ///< distance: 0: no spring
  float spring_damping_ratio = 1.0f;
  float break_force = 0.0f;   ///< N; the joint breaks past it (0: never)
  float break_torque = 0.0f;  ///< N m (0: never)
  bool collide_connected = false;
};

/// Bodies, joints and their geometry, and how a step of the scene is solved.
struct SceneDescription {
  std::string name;
  std::vector<BodyDescription> bodies;
  std::vector<JointDescription> joints;
  std::vector<HullGeometry> hulls;
  std::vector<MeshGeometry> meshes;
  std::vector<HeightFieldGeometry> height_fields;
  Vec3 gravity = PhysicsSettings().gravity;
  float dt = 1.0f / 60.0f;
  int substeps = PhysicsSettings().substeps;
  int velocity_iterations = PhysicsSettings().velocity_iterations;  ///< per substep
  int relax_iterations = PhysicsSettings().relax_iterations;        ///< per substep
  int restitution_iterations = PhysicsSettings().restitution_iterations;
  float contact_hertz = PhysicsSettings().contact_hertz;
  float contact_damping_ratio = PhysicsSettings().contact_damping_ratio;
  float contact_push_max_velocity = PhysicsSettings().contact_push_max_velocity;
  bool exact_small_islands = PhysicsSettings().exact_small_islands;
  bool gyroscopic_torque = PhysicsSettings().gyroscopic_torque;
  bool sleeping = false;
  SleepRule sleep_rule = PhysicsSettings().sleep_rule;
  float sleep_point_velocity = PhysicsSettings().sleep_point_velocity;  ///< m/s, for kPointMovement
  /// Approaches slower than this (m/s) do not bounce, in every engine (Strata's default).
  float min_velocity_for_restitution = PhysicsSettings().min_velocity_for_restitution;
};

}  // namespace strata
