#include "physics/body/BodyCreationSettings.h"

#include <sstream>
#include <string>

namespace strata {

namespace {
Status Invalid(const std::string& message) {
  return MakeError(ErrorCode::kInvalidArgument, message);
}
std::string Number(float value) {
  std::ostringstream text;
  text << value;
  return text.str();
}
}  // namespace

Status BodyCreationSettings::Validate() const {
  if (!shape) return Invalid("body has no shape");
  if (!IsFinite(position)) return Invalid("body position is not finite");
  if (!IsFinite(rotation) || std::abs(rotation.norm() - 1.0f) > 1e-3f)
    return Invalid("body rotation must be a finite unit quaternion");
  if (!IsFinite(linear_velocity) || !IsFinite(angular_velocity))
    return Invalid("body velocity is not finite");
  if (mass && (!IsFinite(*mass) || *mass <= 0.0f))
    return Invalid("body mass must be a positive finite number, got " + std::to_string(*mass));
  if (!mass && (!IsFinite(density) || density <= 0.0f))
    return Invalid("body density must be a positive finite number, got " + std::to_string(density));
  if (!IsFinite(friction) || friction < 0.0f) return Invalid("friction must be >= 0");
  if (!IsFinite(restitution) || restitution < 0.0f || restitution > 1.0f)
    return Invalid("restitution must be in [0, 1]");
  if (!IsFinite(linear_damping) || linear_damping < 0.0f || !IsFinite(angular_damping) ||
      angular_damping < 0.0f)
    return Invalid("damping must be >= 0");
  if (!IsFinite(gravity_factor)) return Invalid("gravity factor is not finite");
  if (!(max_linear_velocity > 0.0f) || !(max_angular_velocity > 0.0f))
    return Invalid("max velocities must be positive");
  if (is_sensor && !shape->IsConvex())
    return Invalid("a sensor's shape must be convex (a box, sphere, capsule or hull)");
  if (sensor_detects_static && !is_sensor)
    return Invalid("sensor_detects_static is set on a body that is no sensor");
  if (is_sensor && (report_contacts || validate_contacts))
    return Invalid(
        "a sensor has no contacts: it reports overlaps as sensor events (leave report_contacts and "
        "validate_contacts off)");
  if (motion_type == MotionType::kDynamic && !shape->IsConvex())
    return MakeError(ErrorCode::kInvalidArgument,
                     "a triangle mesh has no volume: it can only be static or kinematic");
  if (motion_type == MotionType::kDynamic && !mass && shape->ComputeMassProperties(density).mass <= 0.0f)
    return MakeError(ErrorCode::kDegenerateShape, "body shape has no volume, so its mass would be zero");
  if (motion_type != MotionType::kDynamic) return Status::Ok();
  const float body_mass = mass ? *mass : shape->ComputeMassProperties(density).mass;
  if (!(body_mass >= kMinMass && body_mass <= kMaxMass))
    return Invalid("body mass must be in [1e-6, 1e10] kg, got " + Number(body_mass) +
                   (mass ? "" : " (from its density)"));
  if (shape->LocalBounds().HalfExtents().minCoeff() < kMinHalfExtent)
    return Invalid("a dynamic body's shape must be at least 2 mm across on every axis");
  return Status::Ok();
}

}  // namespace strata
