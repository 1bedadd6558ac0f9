#include "physics/world/PhysicsSettings.h"

#include <string>

namespace strata {

namespace {
Status Bad(const std::string& field, const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, "physics setting '" + field + "' " + why);
}
bool NonNegative(float value) {
  return IsFinite(value) && value >= 0.0f;
}
}  // namespace

Status PhysicsSettings::Validate() const {
  if (!IsFinite(gravity)) return Bad("gravity", "is not finite");
  if (velocity_iterations < 1 || velocity_iterations > 1000)
    return Bad("velocity_iterations", "must be in [1, 1000]");
  if (position_iterations < 0 || position_iterations > 1000)
    return Bad("position_iterations", "must be in [0, 1000]");
  if (!NonNegative(speculative_distance)) return Bad("speculative_distance", "must be >= 0");
  if (!NonNegative(penetration_slop)) return Bad("penetration_slop", "must be >= 0");
  if (!(baumgarte > 0.0f && baumgarte <= 1.0f)) return Bad("baumgarte", "must be in (0, 1]");
  if (!(max_position_correction > 0.0f) || !IsFinite(max_position_correction))
    return Bad("max_position_correction", "must be > 0");
  if (!NonNegative(min_velocity_for_restitution)) return Bad("min_velocity_for_restitution", "must be >= 0");
  if (!NonNegative(contact_match_distance)) return Bad("contact_match_distance", "must be >= 0");
  if (!NonNegative(body_pair_cache_max_distance)) return Bad("body_pair_cache_max_distance", "must be >= 0");
  if (!(body_pair_cache_max_angle >= 0.0f && body_pair_cache_max_angle <= 180.0f))
    return Bad("body_pair_cache_max_angle", "must be in [0, 180] degrees");
  if (!NonNegative(time_before_sleep)) return Bad("time_before_sleep", "must be >= 0");
  if (!NonNegative(sleep_linear_velocity) || !NonNegative(sleep_angular_velocity))
    return Bad("sleep velocities", "must be >= 0");
  return Status::Ok();
}

}  // namespace strata
