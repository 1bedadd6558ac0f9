#include "physics/constraints/SwingTwistJoint.h"

#include <cmath>
#include <limits>

namespace strata {

namespace {
constexpr float kUnbounded = std::numeric_limits<float>::infinity();

// B's joint frame in A's: its twist is the turn about x.
float TwistOf(const Quat& relative) {
  Quat q = relative;
  if (q.w() < 0.0f) q.coeffs() = -q.coeffs();
  return 2.0f * FastAtan2(q.x(), q.w());
}
}  // namespace

Result<std::unique_ptr<SwingTwistJoint>> SwingTwistJoint::Create(const SwingTwistJointSettings& settings,
                                                                 const BodyFrame& a, const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor, "anchor"); !valid) return valid.error();
  const Result<Vec3> axis = UnitAxis(settings.twist_axis, "twist_axis");
  if (!axis) return axis.error();
  const Result<Vec3> normal = PerpendicularAxis(axis.value(), settings.normal, "normal");
  if (!normal) return normal.error();
  auto invalid = [](const char* message) { return MakeError(ErrorCode::kInvalidArgument, message); };
  if (!std::isfinite(settings.cone_half_angle) || settings.cone_half_angle <= 0.0f ||
      settings.cone_half_angle > kPi + 1e-6f)
    return invalid("cone_half_angle must be in (0, pi] (rad)");
  if (!std::isfinite(settings.min_twist) || !std::isfinite(settings.max_twist) ||
      settings.min_twist < -kPi - 1e-6f || settings.min_twist > 0.0f || settings.max_twist < 0.0f ||
      settings.max_twist > kPi + 1e-6f)
    return invalid("twist limits must be min_twist in [-pi, 0] and max_twist in [0, pi] (rad)");
  if (!std::isfinite(settings.max_friction_torque) || settings.max_friction_torque < 0.0f)
    return invalid("max_friction_torque must be finite and >= 0");
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor, settings.anchor, axis.value(), normal.value());
  return std::unique_ptr<SwingTwistJoint>(new SwingTwistJoint(settings, frames));
}

SwingTwistJoint::SwingTwistJoint(const SwingTwistJointSettings& settings, const LocalFrames& frames)
    : Constraint(ConstraintType::kSwingTwist, settings, frames),
      cone_half_angle_(settings.cone_half_angle),
      min_twist_(settings.min_twist),
      max_twist_(settings.max_twist),
      max_friction_torque_(settings.max_friction_torque) {}

std::string SwingTwistJoint::Describe() const {
  return "swing-twist joint, cone " + std::to_string(cone_half_angle_) + " rad, twist [" +
         std::to_string(min_twist_) + ", " + std::to_string(max_twist_) + "] rad";
}

float SwingTwistJoint::SwingAngle(const Quat& rotation_a, const Quat& rotation_b) const {
  const Vec3 twist_a = (rotation_a * local().frame_a) * Vec3::UnitX();
  const Vec3 twist_b = (rotation_b * local().frame_b) * Vec3::UnitX();
  return FastAtan2(twist_a.cross(twist_b).norm(), twist_a.dot(twist_b));
}

float SwingTwistJoint::TwistAngle(const Quat& rotation_a, const Quat& rotation_b) const {
  return TwistOf((rotation_a * local().frame_a).conjugate() * (rotation_b * local().frame_b));
}

void SwingTwistJoint::SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  if (!NeedsSetUp(pass)) return;
  const WorldFrames frames = Frames(bodies);
  point_.Prepare(frames.r_a, frames.r_b);
  separation_ = frames.separation;
  const Vec3 twist_a = frames.axes_a.col(0), twist_b = frames.axes_b.col(0);
  const Vec3 bend = twist_a.cross(twist_b);
  const float bend_size = bend.norm();
  swing_ = FastAtan2(bend_size, twist_a.dot(twist_b));
  // The swing grows as B turns about twist_a x twist_b; the row holds the opposite way. With the axes in
  // line there is no direction to hold (and no limit near).
  swing_axis_valid_ = bend_size > 1e-6f;
  if (swing_axis_valid_) swing_row_.Prepare(bodies, -bend / bend_size);
  twist_ = TwistOf(frames.frame_a.conjugate() * frames.frame_b);
  const Vec3 mean_axis = (twist_a + twist_b).normalized();
  twist_lower_.Prepare(bodies, mean_axis);
  twist_upper_.PrepareOpposite(twist_lower_);
  if (max_friction_torque_ > 0.0f) friction_.Prepare();
}

void SwingTwistJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  point_.WarmStart(bodies);
  if (swing_axis_valid_) swing_row_.WarmStart(bodies);
  twist_lower_.WarmStart(bodies);
  twist_upper_.WarmStart(bodies);
  if (max_friction_torque_ > 0.0f) friction_.WarmStart(bodies);
}

void SwingTwistJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass,
                                    bool rigid_rows) {
  SetUp(bodies, pass);
  if (max_friction_torque_ > 0.0f) friction_.SolveFriction(bodies, max_friction_torque_ * pass.h);
  FreeRowPass rows[kMaxFreeRowPasses];
  AngleConstraintPart* parts[kMaxFreeRowPasses];
  const int count = LimitRows(pass, rows, parts);
  for (int k = 0; k < count; ++k) parts[k]->Solve(bodies, rows[k].target, rows[k].low, rows[k].high);
  if (!rigid_rows) return;
  const RowTarget target = EqualityTarget(1.0f, pass);
  point_.Solve(bodies, target.bias * separation_, target);
}

void SwingTwistJoint::SolveUnreducibleRows(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  if (max_friction_torque_ > 0.0f) friction_.SolveFriction(bodies, max_friction_torque_ * pass.h);
}

int SwingTwistJoint::LimitRows(const ConstraintPassContext& pass, FreeRowPass* rows,
                               AngleConstraintPart** parts) {
  int count = 0;
  auto add = [&](AngleConstraintPart& part, int direction, float sign, const RowTarget& target) {
    parts[count] = &part;
    rows[count++] = {direction, sign, target, 0.0f, kUnbounded, part.Row(0.0f).impulse};
  };
  int twist_direction = 0;
  if (SwingLimited())
    add(swing_row_, twist_direction++, 1.0f, LimitTarget(cone_half_angle_ - swing_, pass));
  else
    swing_row_.ResetImpulse();
  add(twist_lower_, twist_direction, 1.0f, LimitTarget(twist_ - min_twist_, pass));
  add(twist_upper_, twist_direction, -1.0f, LimitTarget(max_twist_ - twist_, pass));
  return count;
}

int SwingTwistJoint::RigidRowCount() const {
  return 3;
}

void SwingTwistJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  const WorldArms arms = Arms(bodies);
  point_.Prepare(arms.r_a, arms.r_b);
  point_.Rows(arms.separation, rows);
}

bool SwingTwistJoint::SwingLimited() const {
  return swing_axis_valid_ && cone_half_angle_ < kPi;
}

// The swing row while the passes solve it, then the twist (its limits share a row). The friction's three
// rows keep their own 3 x 3 effective mass.
int SwingTwistJoint::FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass,
                              JointRow* rows) {
  SetUp(bodies, pass);
  int count = 0;
  if (SwingLimited()) rows[count++] = swing_row_.Row(0.0f);
  rows[count++] = twist_lower_.Row(0.0f);
  return count;
}

int SwingTwistJoint::FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) {
  AngleConstraintPart* parts[kMaxFreeRowPasses];
  return LimitRows(pass, rows, parts);
}

Constraint::Impulses SwingTwistJoint::AccumulatedImpulses() const {
  return {point_.impulse(), swing_row_.AngularImpulse() + twist_lower_.AngularImpulse() +
                                twist_upper_.AngularImpulse() + friction_.impulse()};
}

void SwingTwistJoint::ScaleImpulses(float ratio) {
  point_.ScaleImpulse(ratio);
  swing_row_.ScaleImpulse(ratio);
  twist_lower_.ScaleImpulse(ratio);
  twist_upper_.ScaleImpulse(ratio);
  friction_.ScaleImpulse(ratio);
}

}  // namespace strata
