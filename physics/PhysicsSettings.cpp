#include "physics/PhysicsSettings.h"

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
  // A thousand g: beyond it a step's velocity change dwarfs every body's velocity limit.
  if (gravity.norm() > kMaxGravity) return Bad("gravity", "must be at most 1e4 m/s^2 in magnitude");
  if (substeps < 1 || substeps > 64) return Bad("substeps", "must be in [1, 64]");
  if (velocity_iterations < 1 || velocity_iterations > 1000)
    return Bad("velocity_iterations", "must be in [1, 1000]");
  if (relax_iterations < 0 || relax_iterations > 1000) return Bad("relax_iterations", "must be in [0, 1000]");
  if (restitution_iterations < 1 || restitution_iterations > 1000)
    return Bad("restitution_iterations", "must be in [1, 1000]");
  if (!(contact_hertz > 0.0f) || !IsFinite(contact_hertz)) return Bad("contact_hertz", "must be > 0");
  if (!NonNegative(contact_damping_ratio)) return Bad("contact_damping_ratio", "must be >= 0");
  if (!(contact_push_max_velocity > 0.0f) || !IsFinite(contact_push_max_velocity))
    return Bad("contact_push_max_velocity", "must be > 0");
  if (!(joint_hertz > 0.0f) || !IsFinite(joint_hertz)) return Bad("joint_hertz", "must be > 0");
  if (!NonNegative(joint_damping_ratio)) return Bad("joint_damping_ratio", "must be >= 0");
  if (!(exact_joint_mass_ratio >= 1.0f) || !IsFinite(exact_joint_mass_ratio))
    return Bad("exact_joint_mass_ratio", "must be >= 1");
  if (!NonNegative(speculative_distance)) return Bad("speculative_distance", "must be >= 0");
  if (!NonNegative(min_velocity_for_restitution)) return Bad("min_velocity_for_restitution", "must be >= 0");
  if (!NonNegative(contact_match_distance)) return Bad("contact_match_distance", "must be >= 0");
  if (!NonNegative(body_pair_cache_max_distance)) return Bad("body_pair_cache_max_distance", "must be >= 0");
  if (!(body_pair_cache_max_angle >= 0.0f && body_pair_cache_max_angle <= 180.0f))
    return Bad("body_pair_cache_max_angle", "must be in [0, 180] degrees");
  if (!NonNegative(time_before_sleep)) return Bad("time_before_sleep", "must be >= 0");
  if (!NonNegative(sleep_linear_velocity) || !NonNegative(sleep_angular_velocity))
    return Bad("sleep velocities", "must be >= 0");
  if (!NonNegative(sleep_point_velocity)) return Bad("sleep_point_velocity", "must be >= 0");
  if (sleep_rule != SleepRule::kVelocity && sleep_rule != SleepRule::kPointMovement)
    return Bad("sleep_rule", "must be kVelocity or kPointMovement");
  return Status::Ok();
}

}  // namespace strata
