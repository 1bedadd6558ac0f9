#include "physics/constraints/FreeAxis.h"

#include <cmath>

namespace strata {

Status ValidateMotor(const JointMotor& motor) {
  if (!std::isfinite(motor.target_speed))
    return MakeError(ErrorCode::kInvalidArgument, "motor target_speed must be finite");
  if (!std::isfinite(motor.max_torque) || motor.max_torque < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "motor max_torque must be finite and >= 0");
  return Status::Ok();
}

Status ValidateDrive(float max_friction, const char* name, const JointMotor& motor) {
  if (!std::isfinite(max_friction) || max_friction < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, std::string(name) + " must be finite and >= 0");
  return ValidateMotor(motor);
}

}  // namespace strata
