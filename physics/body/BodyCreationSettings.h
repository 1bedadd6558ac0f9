// BodyCreationSettings: everything needed to create a body, validated in one place before any state
// changes. Value type; build it on any thread.
#pragma once

#include <cstdint>
#include <optional>

#include "physics/body/MotionType.h"
#include "physics/broadphase/Layers.h"
#include "physics/core/Result.h"
#include "physics/shapes/Shape.h"

namespace strata {

/// Shape, pose, motion and material of a new body. Units: metres, kilograms, seconds, radians.
/// A dynamic body's mass (given, or from its density) must lie in [kMinMass, kMaxMass] and its shape's
/// bounds be at least kMinHalfExtent on every axis: beyond these float products in the step overflow or
/// vanish and the state turns to NaN.
struct BodyCreationSettings {
  static constexpr float kMinMass = 1e-6f;        ///< kg
  static constexpr float kMaxMass = 1e10f;        ///< kg
  static constexpr float kMinHalfExtent = 1e-3f;  ///< m, of a dynamic body's local bounds

  ShapeRef shape;
  Vec3 position = Vec3::Zero();      ///< of the shape origin, world space (m)
  Quat rotation = Quat::Identity();  ///< unit quaternion
  MotionType motion_type = MotionType::kDynamic;
  MotionQuality motion_quality = MotionQuality::kDiscrete;  ///< LinearCast: fast bodies do not tunnel
  ObjectLayer object_layer = layers::kMoving;
  std::optional<float> mass;                         ///< kg; overrides density when set
  float density = 1000.0f;                           ///< kg/m^3, used when mass is not set
  float friction = 0.2f;                             ///< Coulomb coefficient, >= 0 (pairs use sqrt(a * b))
  float restitution = 0.0f;                          ///< [0, 1] (pairs use the max)
  float linear_damping = 0.05f;                      ///< 1/s
  float angular_damping = 0.05f;                     ///< 1/s
  float gravity_factor = 1.0f;                       ///< multiplies world gravity
  float max_linear_velocity = 500.0f;                ///< m/s
  float max_angular_velocity = 0.25f * kPi * 60.0f;  ///< rad/s
  bool allow_sleeping = true;
  /// A sensor (trigger volume): the step reports the bodies that overlap it as sensor events and it takes no
  /// contact response (it never pushes, wakes or stops anything). Queries skip it unless their filter asks
  /// for sensors. Its shape must be convex. It may be static, kinematic (moved by its velocity) or dynamic.
  bool is_sensor = false;
  /// A sensor that also reports static and kinematic bodies (by default it sees dynamic bodies only). The
  /// layer pair filter still applies: give a static sensor a layer that collides with the level's.
  bool sensor_detects_static = false;
  /// Contact begin / persist / end events for this body's contacts (PhysicsSystem::events()). Off, its
  /// contacts cost nothing extra.
  bool report_contacts = false;
  /// The world's contact validator (PhysicsSystem::SetContactValidator) is asked about this body's contacts
  /// before they are solved, and may reject them (one-way platforms).
  bool validate_contacts = false;
  Vec3 linear_velocity = Vec3::Zero();   ///< m/s, of the centre of mass
  Vec3 angular_velocity = Vec3::Zero();  ///< rad/s, world space
  std::uint64_t user_data = 0;

  /// Checks every field; the message names the first bad one.
  Status Validate() const;
};

}  // namespace strata
