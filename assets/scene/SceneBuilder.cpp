#include "assets/scene/SceneBuilder.h"

#include <map>
#include <tuple>
#include <utility>

#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"

namespace strata {

namespace {

bool UsesGeometry(SceneShape shape) {
  return shape == SceneShape::kHull || shape == SceneShape::kMesh || shape == SceneShape::kHeightField;
}

template <class Geometry>
Result<const Geometry*> GeometryAt(const std::vector<Geometry>& list, std::uint32_t index, const char* what) {
  if (index >= list.size())
    return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " " + std::to_string(index) +
                                                      " is not in the scene (it has " +
                                                      std::to_string(list.size()) + ")");
  return &list[index];
}

void SetMotion(const BodyDescription& body, BodyCreationSettings& settings) {
  switch (body.motion) {
    case SceneMotion::kStatic:
      settings.motion_type = MotionType::kStatic;
      break;
    case SceneMotion::kKinematic:
      settings.motion_type = MotionType::kKinematic;
      break;
    case SceneMotion::kDynamic:
      settings.motion_type = MotionType::kDynamic;
      break;
  }
  // A sensor goes on the moving layer whatever its motion: the default layers never pair two static ones,
  // and a static trigger that sees static bodies must be paired with them.
  const bool moving = body.motion != SceneMotion::kStatic || body.sensor;
  settings.object_layer = moving ? layers::kMoving : layers::kNonMoving;
  settings.motion_quality = body.linear_cast ? MotionQuality::kLinearCast : MotionQuality::kDiscrete;
}

void SetTunings(const BodyDescription& body, BodyCreationSettings& settings) {
  const auto set = [](const std::optional<float>& value, float& out) {
    if (value) out = *value;
  };
  set(body.density, settings.density);
  set(body.linear_damping, settings.linear_damping);
  set(body.angular_damping, settings.angular_damping);
  set(body.gravity_factor, settings.gravity_factor);
  set(body.max_linear_velocity, settings.max_linear_velocity);
  set(body.max_angular_velocity, settings.max_angular_velocity);
  settings.allow_sleeping = body.allow_sleeping;
  settings.is_sensor = body.sensor;
  settings.sensor_detects_static = body.sensor_detects_static;
  settings.report_contacts = body.report_contacts;
}

template <class Settings>
Settings WithBase(const JointDescription& joint, BodyID a, BodyID b) {
  Settings settings;
  settings.body_a = a, settings.body_b = b;
  settings.max_force = joint.break_force, settings.max_torque = joint.break_torque;
  settings.collide_connected = joint.collide_connected;
  return settings;
}

JointMotor Motor(const JointDescription& joint) {
  return {joint.motor, joint.motor_speed, joint.motor_max};
}

}  // namespace

PhysicsSettings ToPhysicsSettings(const SceneDescription& scene) {
  PhysicsSettings settings;
  settings.gravity = scene.gravity;
  settings.substeps = scene.substeps;
  settings.velocity_iterations = scene.velocity_iterations;
  settings.relax_iterations = scene.relax_iterations;
  settings.restitution_iterations = scene.restitution_iterations;
  settings.contact_hertz = scene.contact_hertz;
  settings.contact_damping_ratio = scene.contact_damping_ratio;
  settings.contact_push_max_velocity = scene.contact_push_max_velocity;
  settings.exact_small_islands = scene.exact_small_islands;
  settings.gyroscopic_torque = scene.gyroscopic_torque;
  settings.allow_sleeping = scene.sleeping;
  settings.sleep_rule = scene.sleep_rule;
  settings.sleep_point_velocity = scene.sleep_point_velocity;
  settings.min_velocity_for_restitution = scene.min_velocity_for_restitution;
  return settings;
}

Result<ShapeRef> MakeShape(const SceneDescription& scene, const BodyDescription& body) {
  switch (body.shape) {
    case SceneShape::kBox:
      if (body.convex_radius) return BoxShape::Create(body.half_extents, *body.convex_radius);
      return BoxShape::Create(body.half_extents);
    case SceneShape::kSphere:
      return SphereShape::Create(body.radius);
    case SceneShape::kCapsule:
      return CapsuleShape::Create(body.half_height, body.radius);
    case SceneShape::kHull: {
      Result<const HullGeometry*> hull = GeometryAt(scene.hulls, body.geometry, "hull");
      if (!hull) return hull.error();
      if (body.convex_radius) return ConvexHullShape::Create((*hull)->points, *body.convex_radius);
      return ConvexHullShape::Create((*hull)->points);
    }
    case SceneShape::kMesh: {
      Result<const MeshGeometry*> mesh = GeometryAt(scene.meshes, body.geometry, "mesh");
      if (!mesh) return mesh.error();
      return TriangleMeshShape::Create((*mesh)->vertices, (*mesh)->triangles);
    }
    case SceneShape::kHeightField: {
      Result<const HeightFieldGeometry*> field =
          GeometryAt(scene.height_fields, body.geometry, "height field");
      if (!field) return field.error();
      const HeightFieldGeometry& f = **field;
      return HeightFieldShape::Create(f.columns, f.rows, f.cell, f.heights);
    }
  }
  return MakeError(ErrorCode::kInvalidArgument, "unknown shape kind");
}

Result<std::vector<ShapeRef>> MakeShapes(const SceneDescription& scene) {
  // Bodies share a shape made from the same geometry with the same rounding (-1: the default's).
  std::map<std::tuple<SceneShape, std::uint32_t, float>, ShapeRef> made;
  std::vector<ShapeRef> shapes;
  shapes.reserve(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDescription& body = scene.bodies[i];
    const auto key = std::make_tuple(body.shape, body.geometry, body.convex_radius.value_or(-1.0f));
    if (UsesGeometry(body.shape) && made.count(key)) {
      shapes.push_back(made[key]);
      continue;
    }
    Result<ShapeRef> shape = MakeShape(scene, body);
    if (!shape)
      return MakeError(shape.error().code, "body " + std::to_string(i) + ": " + shape.error().message);
    if (UsesGeometry(body.shape)) made[key] = *shape;
    shapes.push_back(std::move(*shape));
  }
  return shapes;
}

BodyCreationSettings ToBodySettings(const BodyDescription& body, ShapeRef shape) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.position = body.position;
  settings.rotation = body.rotation;
  SetMotion(body, settings);
  settings.friction = body.friction;
  settings.restitution = body.restitution;
  if (body.mass > 0.0f) settings.mass = body.mass;
  settings.linear_velocity = body.linear_velocity;
  settings.angular_velocity = body.angular_velocity;
  SetTunings(body, settings);
  return settings;
}

JointSettings ToJointSettings(const JointDescription& joint, std::span<const BodyID> ids) {
  const BodyID a = joint.body_a >= 0 ? ids[static_cast<std::size_t>(joint.body_a)] : BodyID{};
  const BodyID b = ids[static_cast<std::size_t>(joint.body_b)];
  switch (joint.kind) {
    case JointKind::kFixed: {
      auto fixed = WithBase<FixedJointSettings>(joint, a, b);
      fixed.anchor = joint.anchor;
      return fixed;
    }
    case JointKind::kDistance: {
      auto rod = WithBase<DistanceJointSettings>(joint, a, b);
      rod.anchor_a = joint.anchor, rod.anchor_b = joint.anchor_b, rod.rest_length = joint.rest_length;
      rod.min_distance = joint.min_distance, rod.max_distance = joint.max_distance;
      rod.spring_hertz = joint.spring_hertz, rod.spring_damping_ratio = joint.spring_damping_ratio;
      return rod;
    }
    case JointKind::kHinge: {
      auto hinge = WithBase<HingeJointSettings>(joint, a, b);
      hinge.anchor = joint.anchor, hinge.axis = joint.axis, hinge.normal = joint.normal;
      hinge.limits = joint.limits, hinge.min_angle = joint.min_limit, hinge.max_angle = joint.max_limit;
      hinge.max_friction_torque = joint.max_friction, hinge.motor = Motor(joint);
      return hinge;
    }
    case JointKind::kSlider: {
      auto slider = WithBase<SliderJointSettings>(joint, a, b);
      slider.anchor = joint.anchor, slider.axis = joint.axis;
      slider.limits = joint.limits, slider.min_position = joint.min_limit,
      slider.max_position = joint.max_limit;
      slider.max_friction_force = joint.max_friction, slider.motor = Motor(joint);
      return slider;
    }
    case JointKind::kSwingTwist: {
      auto cone = WithBase<SwingTwistJointSettings>(joint, a, b);
      cone.anchor = joint.anchor, cone.twist_axis = joint.axis, cone.normal = joint.normal;
      cone.cone_half_angle = joint.cone, cone.min_twist = joint.min_limit, cone.max_twist = joint.max_limit;
      cone.max_friction_torque = joint.max_friction;
      return cone;
    }
    case JointKind::kPoint:
      break;
  }
  auto point = WithBase<PointJointSettings>(joint, a, b);
  point.anchor = joint.anchor;
  return point;
}

}  // namespace strata
