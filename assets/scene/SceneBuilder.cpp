#include "assets/scene/SceneBuilder.h"

#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"

namespace strata {

Result<ShapeRef> MakeShape(const SceneDescription& scene, const BodyDescription& body) {
  switch (body.shape) {
    case SceneShape::kBox:
      return BoxShape::Create(body.half_extents);
    case SceneShape::kSphere:
      return SphereShape::Create(body.radius);
    case SceneShape::kCapsule:
      return CapsuleShape::Create(body.half_height, body.radius);
    case SceneShape::kHull:
      return ConvexHullShape::Create(scene.hull_points);
    case SceneShape::kMesh:
      return TriangleMeshShape::Create(scene.mesh_vertices, scene.mesh_triangles);
    case SceneShape::kHeightField:
      return HeightFieldShape::Create(scene.field_columns, scene.field_rows, scene.field_cell,
                                      scene.field_heights);
  }
  return MakeError(ErrorCode::kInvalidArgument, "unknown shape kind");
}

BodyCreationSettings ToBodySettings(const BodyDescription& body, ShapeRef shape) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.position = body.position;
  settings.rotation = body.rotation;
  settings.motion_type = body.dynamic ? MotionType::kDynamic : MotionType::kStatic;
  settings.object_layer = body.dynamic ? layers::kMoving : layers::kNonMoving;
  settings.friction = body.friction;
  settings.restitution = body.restitution;
  if (body.mass > 0.0f) settings.mass = body.mass;
  settings.linear_velocity = body.linear_velocity;
  settings.angular_velocity = body.angular_velocity;
  return settings;
}

JointSettings ToJointSettings(const JointDescription& joint, std::span<const BodyID> ids) {
  const BodyID a = joint.body_a >= 0 ? ids[static_cast<std::size_t>(joint.body_a)] : BodyID{};
  const BodyID b = ids[static_cast<std::size_t>(joint.body_b)];
  switch (joint.kind) {
    case JointKind::kHinge: {
      HingeJointSettings hinge;
      hinge.body_a = a, hinge.body_b = b, hinge.anchor = joint.anchor;
      hinge.axis = joint.axis, hinge.normal = joint.normal;
      hinge.limits = true, hinge.min_angle = joint.min_angle, hinge.max_angle = joint.max_angle;
      return hinge;
    }
    case JointKind::kSwingTwist: {
      SwingTwistJointSettings cone;
      cone.body_a = a, cone.body_b = b, cone.anchor = joint.anchor;
      cone.twist_axis = joint.axis, cone.normal = joint.normal, cone.cone_half_angle = joint.cone;
      cone.min_twist = joint.min_angle, cone.max_twist = joint.max_angle;
      return cone;
    }
    case JointKind::kPoint:
      break;
  }
  PointJointSettings point;
  point.body_a = a, point.body_b = b, point.anchor = joint.anchor;
  return point;
}

}  // namespace strata
