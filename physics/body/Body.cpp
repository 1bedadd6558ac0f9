#include "physics/body/Body.h"

#include "physics/body/GyroscopicTorque.h"

namespace strata {

void Body::ResetInternal(const BodyCreationSettings& settings, BodyID id) {
  *this = Body();
  id_ = id;
  shape_ = settings.shape;
  local_bounds_ = shape_->LocalBounds();
  bounds_turn_ = shape_->BoundsTurnWithBody();
  bounds_rounding_ = shape_->BoundsRounding();
  pose_ = {settings.position, settings.rotation.normalized()};
  motion_type_ = settings.motion_type;
  motion_quality_ = settings.motion_quality;
  object_layer_ = settings.object_layer;
  friction_ = settings.friction;
  restitution_ = settings.restitution;
  linear_damping_ = settings.linear_damping;
  angular_damping_ = settings.angular_damping;
  gravity_factor_ = settings.gravity_factor;
  max_linear_velocity_ = settings.max_linear_velocity;
  max_angular_velocity_ = settings.max_angular_velocity;
  allow_sleeping_ = settings.allow_sleeping;
  user_data_ = settings.user_data;
  event_flags_ = static_cast<std::uint8_t>((settings.is_sensor ? kSensor : 0) |
                                           (settings.sensor_detects_static ? kSensorDetectsStatic : 0) |
                                           (settings.report_contacts ? kReportContacts : 0) |
                                           (settings.validate_contacts ? kValidateContacts : 0));
  if (motion_type_ != MotionType::kStatic) {
    linear_velocity_ = settings.linear_velocity;
    angular_velocity_ = settings.angular_velocity;
  }
  if (shape_->IsConvex()) {
    MassProperties properties = shape_->ComputeMassProperties(settings.density);
    if (settings.mass) properties = properties.WithMass(*settings.mass);
    center_of_mass_local_ = properties.center_of_mass;
    centered_ = center_of_mass_local_.isZero(0.0f);
    if (motion_type_ == MotionType::kDynamic) {
      inverse_mass_ = 1.0f / properties.mass;
      inverse_inertia_local_ = properties.inertia.inverse();
      inertia_local_ = properties.inertia;
      gyroscopic_ = HasGyroscopicTorque(properties.inertia);
    }
  }
  UpdateWorldBoundsInternal();
}

}  // namespace strata
