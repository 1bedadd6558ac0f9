// Body: the state of one rigid body. Lives in the BodyManager's slot array; read it under the body's read
// lock (BodyLockRead) and change it under its write lock (BodyLockWrite) or from inside the step.
#pragma once

#include "physics/BodyID.h"
#include "physics/body/BodyCreationSettings.h"
#include "physics/core/RelaxedAtomic.h"

namespace strata {

/// One rigid body. The pose is that of the shape origin; velocities are those of the centre of mass.
class Body {
 public:
  BodyID id() const { return id_; }
  const ShapeRef& shape() const { return shape_; }
  MotionType motion_type() const { return motion_type_; }
  MotionQuality motion_quality() const { return motion_quality_; }
  ObjectLayer object_layer() const { return object_layer_; }
  bool IsDynamic() const { return motion_type_ == MotionType::kDynamic; }
  bool IsStatic() const { return motion_type_ == MotionType::kStatic; }
  bool in_world() const { return in_world_; }
  /// Also safe to read without the body's lock, as a hint (see BodyInterface::ActivateBodiesInBox).
  bool sleeping() const { return sleeping_; }
  /// Dynamic or kinematic and awake: the step moves it.
  bool IsActive() const { return in_world_ && !sleeping_ && motion_type_ != MotionType::kStatic; }

  const Pose& pose() const { return pose_; }
  const Vec3& position() const { return pose_.position; }
  /// The shape origin with what a float cannot hold there: 10 km out a float moves in steps of about 1 mm,
  /// so the step adds each body's motion to a float and a float remainder (compensated summation) and a
  /// slow body far from the origin moves as it would at the origin. Contacts see position().
  Vec3d precise_position() const {
    return pose_.position.cast<double>() + position_remainder_.cast<double>();
  }
  Vec3d PreciseCenterOfMass() const {
    return precise_position() + (pose_.rotation * center_of_mass_local_).cast<double>();
  }
  const Quat& rotation() const { return pose_.rotation; }
  /// Most shapes (boxes, spheres, capsules) have theirs at the shape origin: no rotation then.
  Vec3 CenterOfMass() const { return centered_ ? pose_.position : pose_.ToWorld(center_of_mass_local_); }
  const Vec3& center_of_mass_local() const { return center_of_mass_local_; }
  const Vec3& linear_velocity() const { return linear_velocity_; }
  const Vec3& angular_velocity() const { return angular_velocity_; }
  /// Velocity of a world-space point attached to the body.
  Vec3 PointVelocity(const Vec3& point) const {
    return linear_velocity_ + angular_velocity_.cross(point - CenterOfMass());
  }

  float inverse_mass() const { return inverse_mass_; }
  float mass() const { return inverse_mass_ > 0.0f ? 1.0f / inverse_mass_ : 0.0f; }
  /// Inverse inertia in world space (zero for static and kinematic bodies).
  Mat3 InverseInertiaWorld() const {
    const Mat3 rotation = pose_.rotation.toRotationMatrix();
    return rotation * inverse_inertia_local_ * rotation.transpose();
  }
  const Mat3& inverse_inertia_local() const { return inverse_inertia_local_; }
  /// Inertia about the centre of mass in the shape's axes (zero unless dynamic).
  const Mat3& inertia_local() const { return inertia_local_; }

  float friction() const { return friction_; }
  float restitution() const { return restitution_; }
  float linear_damping() const { return linear_damping_; }
  float angular_damping() const { return angular_damping_; }
  float gravity_factor() const { return gravity_factor_; }
  float max_linear_velocity() const { return max_linear_velocity_; }
  float max_angular_velocity() const { return max_angular_velocity_; }
  bool allow_sleeping() const { return allow_sleeping_; }
  /// A trigger volume: reports overlaps as sensor events, never collides (BodyCreationSettings::is_sensor).
  bool is_sensor() const { return (event_flags_ & kSensor) != 0; }
  /// A sensor that also sees static and kinematic bodies.
  bool sensor_detects_static() const { return (event_flags_ & kSensorDetectsStatic) != 0; }
  /// Its contacts give contact events.
  bool reports_contacts() const { return (event_flags_ & kReportContacts) != 0; }
  /// The world's contact validator is asked about its contacts.
  bool validates_contacts() const { return (event_flags_ & kValidateContacts) != 0; }
  /// The event and sensor bits above together: a pair tests both bodies' bits with one OR.
  std::uint8_t event_flags() const { return event_flags_; }
  static constexpr std::uint8_t kSensor = 1, kSensorDetectsStatic = 2, kReportContacts = 4,
                                kValidateContacts = 8;
  /// Key shared by the bodies of a sleeping island (meaningful only while sleeping).
  std::uint32_t sleep_island() const { return sleep_island_; }
  /// How far the centre of mass moves in `dt` at the current velocity (zero unless active).
  Vec3 LinearTravel(float dt) const { return IsActive() ? Vec3(linear_velocity_ * dt) : Vec3::Zero(); }
  /// How far any point of the body may move in `dt` by its current spin alone (0 unless active).
  float TurnBound(float dt) const {
    if (!IsActive()) return 0.0f;
    const float radius = local_bounds_.HalfExtents().norm() + center_of_mass_local_.norm();
    return angular_velocity_.norm() * radius * dt;
  }
  const AABB& world_bounds() const { return world_bounds_; }
  std::uint64_t user_data() const { return user_data_; }
  const Vec3& accumulated_force() const { return force_; }
  const Vec3& accumulated_torque() const { return torque_; }

  float sleep_timer() const { return sleep_timer_; }
  /// Whether its spin can precess (the inertia is not a multiple of the identity).
  bool gyroscopic() const { return gyroscopic_; }
  /// Whether the centre of mass is at the shape origin (then CenterOfMass() needs no rotation).
  bool centered() const { return centered_; }
  /// The shape's bounds in its own frame (kept here so that moving a body does not read its shape).
  const AABB& local_bounds() const { return local_bounds_; }

  // Internal mutators, for the engine's code that holds the body's write lock (BodyManager, BodyInterface)
  // or runs inside the step (BodyMotion, PhysicsSystem). They check nothing: game code changes a body
  // through BodyInterface, which validates first.
  void ResetInternal(const BodyCreationSettings& settings, BodyID id);
  void SetInWorldInternal(bool in_world) { in_world_ = in_world; }
  void SetSleepingInternal(bool sleeping) { sleeping_ = sleeping; }
  void SetSleepIslandInternal(std::uint32_t island) { sleep_island_ = island; }
  void SetSleepTimerInternal(float seconds) { sleep_timer_ = seconds; }
  /// Teleports the shape origin (the far-from-origin remainder starts again from zero).
  void SetPositionInternal(const Vec3& position) {
    pose_.position = position;
    position_remainder_.setZero();
  }
  void SetRotationInternal(const Quat& rotation) { pose_.rotation = rotation; }
  void SetLinearVelocityInternal(const Vec3& velocity) { linear_velocity_ = velocity; }
  void SetAngularVelocityInternal(const Vec3& velocity) { angular_velocity_ = velocity; }
  void AddForceInternal(const Vec3& force) { force_ += force; }
  void AddTorqueInternal(const Vec3& torque) { torque_ += torque; }
  void ClearForcesInternal() {
    force_.setZero();
    torque_.setZero();
  }
  void UpdateWorldBoundsInternal() {
    world_bounds_ = Shape::WorldBoundsOf(local_bounds_, bounds_turn_, bounds_rounding_, pose_);
  }
  /// Moves the shape origin by `motion` (small) without rounding it away where position() is large. Inline:
  /// the step's write-back passes `motion` in registers, not through a just-stored temporary.
  void AddToPositionInternal(const Vec3& motion) {
    // Two-sum (Knuth): the float sum plus the exact rounding error it made.
    const Vec3 addend = position_remainder_ + motion;
    const Vec3 sum = pose_.position + addend;
    const Vec3 taken = sum - pose_.position;
    position_remainder_ = (pose_.position - (sum - taken)) + (addend - taken);
    pose_.position = sum;
  }

 private:
  BodyID id_;
  ShapeRef shape_;
  Pose pose_;
  Vec3 position_remainder_ = Vec3::Zero();  // precise_position() - position(), below half a float step
  Vec3 center_of_mass_local_ = Vec3::Zero();
  bool centered_ = true;  // center_of_mass_local_ is zero
  Vec3 linear_velocity_ = Vec3::Zero();
  Vec3 angular_velocity_ = Vec3::Zero();
  Vec3 force_ = Vec3::Zero();
  Vec3 torque_ = Vec3::Zero();
  Mat3 inverse_inertia_local_ = Mat3::Zero();
  Mat3 inertia_local_ = Mat3::Zero();
  AABB world_bounds_;
  AABB local_bounds_;             // the shape's, kept here so that moving a body does not read its shape
  bool bounds_turn_ = true;       // the shape's BoundsTurnWithBody()
  float bounds_rounding_ = 0.0f;  // the shape's BoundsRounding()
  float inverse_mass_ = 0.0f;
  float friction_ = 0.2f;
  float restitution_ = 0.0f;
  float linear_damping_ = 0.0f;
  float angular_damping_ = 0.0f;
  float gravity_factor_ = 1.0f;
  float max_linear_velocity_ = 500.0f;
  float max_angular_velocity_ = 0.0f;
  float sleep_timer_ = 0.0f;
  std::uint32_t sleep_island_ = 0;  // island key shared by bodies that fell asleep together
  std::uint64_t user_data_ = 0;
  MotionType motion_type_ = MotionType::kStatic;
  MotionQuality motion_quality_ = MotionQuality::kDiscrete;
  ObjectLayer object_layer_ = layers::kNonMoving;
  bool in_world_ = false;
  std::uint8_t event_flags_ = 0;  // kSensor | kSensorDetectsStatic | kReportContacts | kValidateContacts
  RelaxedAtomic<bool> sleeping_ = false;
  bool allow_sleeping_ = true;
  bool gyroscopic_ = false;  // the inertia is not a multiple of the identity, so spin can precess
};

}  // namespace strata
