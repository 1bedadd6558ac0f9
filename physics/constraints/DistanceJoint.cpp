#include "physics/constraints/DistanceJoint.h"

#include <cmath>
#include <limits>

namespace strata {

namespace {
constexpr float kUnbounded = std::numeric_limits<float>::infinity();
}  // namespace

Result<std::unique_ptr<DistanceJoint>> DistanceJoint::Create(const DistanceJointSettings& settings,
                                                             const BodyFrame& a, const BodyFrame& b) {
  if (Status valid = settings.ValidateBase(); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor_a, "anchor_a"); !valid) return valid.error();
  if (Status valid = CheckPoint(settings.anchor_b, "anchor_b"); !valid) return valid.error();
  auto invalid = [](const std::string& message) { return MakeError(ErrorCode::kInvalidArgument, message); };
  for (const float value : {settings.rest_length, settings.min_distance, settings.max_distance,
                            settings.spring_hertz, settings.spring_damping_ratio})
    if (!std::isfinite(value)) return invalid("distance joint settings must be finite numbers");
  const float rest =
      settings.rest_length >= 0.0f ? settings.rest_length : (settings.anchor_b - settings.anchor_a).norm();
  const float least = settings.min_distance >= 0.0f ? settings.min_distance : rest;
  const float most = settings.max_distance >= 0.0f ? settings.max_distance : rest;
  if (least > most) return invalid("min_distance must not exceed max_distance");
  if (rest < least || rest > most) return invalid("rest_length must lie within [min_distance, max_distance]");
  if (settings.spring_hertz < 0.0f) return invalid("spring_hertz must be >= 0");
  if (settings.spring_damping_ratio < 0.0f) return invalid("spring_damping_ratio must be >= 0");
  const Vec3 along = settings.anchor_b - settings.anchor_a;
  const Vec3 axis = along.norm() > 1e-6f ? Vec3(along.normalized()) : Vec3::UnitY();
  const Result<Vec3> normal = PerpendicularAxis(axis, Vec3::Zero(), "normal");
  if (!normal) return normal.error();
  const LocalFrames frames =
      MakeLocalFrames(a, b, settings.anchor_a, settings.anchor_b, axis, normal.value());
  return std::unique_ptr<DistanceJoint>(new DistanceJoint(settings, frames, rest, least, most));
}

DistanceJoint::DistanceJoint(const DistanceJointSettings& settings, const LocalFrames& frames, float rest,
                             float least, float most)
    : Constraint(ConstraintType::kDistance, settings, frames),
      rest_length_(rest),
      min_distance_(least),
      max_distance_(most),
      spring_hertz_(settings.spring_hertz),
      spring_damping_ratio_(settings.spring_damping_ratio) {}

std::string DistanceJoint::Describe() const {
  return "distance joint, rest " + std::to_string(rest_length_) + " m in [" + std::to_string(min_distance_) +
         ", " + std::to_string(max_distance_) + "]" +
         (spring_hertz_ > 0.0f ? ", spring " + std::to_string(spring_hertz_) + " Hz" : "");
}

float DistanceJoint::Axis(const Vec3& separation) {
  const float distance = separation.norm();
  if (distance > 1e-6f) axis_ = separation / distance;
  return distance;
}

void DistanceJoint::SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  if (!NeedsSetUp(pass)) return;
  const WorldArms arms = Arms(bodies);
  distance_ = Axis(arms.separation);
  spring_.Prepare(bodies, arms.r_a, arms.r_b, axis_);
  if (rigid()) return;
  lower_.Prepare(bodies, arms.r_a, arms.r_b, axis_);
  upper_.PrepareOpposite(lower_);
}

void DistanceJoint::WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) {
  SetUp(bodies, pass);
  spring_.WarmStart(bodies);
  if (rigid()) return;
  lower_.WarmStart(bodies);
  upper_.WarmStart(bodies);
}

void DistanceJoint::SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass,
                                  bool rigid_rows) {
  if (rigid()) {
    if (!rigid_rows) return;
    SetUp(bodies, pass);
    spring_.Solve(bodies, EqualityTarget(distance_ - rest_length_, pass), -kUnbounded, kUnbounded);
    return;
  }
  SetUp(bodies, pass);
  FreeRowPass rows[kMaxFreeRowPasses];
  AxisConstraintPart* parts[kMaxFreeRowPasses];
  const int count = SoftRows(pass, rows, parts);
  for (int k = 0; k < count; ++k) parts[k]->Solve(bodies, rows[k].target, rows[k].low, rows[k].high);
}

int DistanceJoint::SoftRows(const ConstraintPassContext& pass, FreeRowPass* rows,
                            AxisConstraintPart** parts) {
  int count = 0;
  auto add = [&](AxisConstraintPart& part, float sign, const RowTarget& target, float low) {
    parts[count] = &part;
    rows[count++] = {0, sign, target, low, kUnbounded, part.Row(0.0f).impulse};
  };
  if (spring_hertz_ > 0.0f) {
    const SoftSpring spring = MakeSoftSpring(spring_hertz_, spring_damping_ratio_, pass.h);
    add(spring_, 1.0f, SpringTarget(distance_ - rest_length_, spring), -kUnbounded);
  }
  if (min_distance_ > 0.0f)  // a distance is never below 0: a rope needs no lower row
    add(lower_, 1.0f, LimitTarget(distance_ - min_distance_, pass), 0.0f);
  add(upper_, -1.0f, LimitTarget(max_distance_ - distance_, pass), 0.0f);
  return count;
}

int DistanceJoint::RigidRowCount() const {
  return rigid() ? 1 : 0;
}

void DistanceJoint::RigidRows(const ConstraintBodies& bodies, JointRow* rows) {
  if (!rigid()) return;
  const WorldArms arms = Arms(bodies);
  const float distance = Axis(arms.separation);
  spring_.Prepare(bodies, arms.r_a, arms.r_b, axis_);
  rows[0] = spring_.Row(distance - rest_length_);
}

// A rod's one row is rigid; otherwise the spring and both limits share one row (the upper limit's the other
// way).
int DistanceJoint::FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass,
                            JointRow* rows) {
  if (rigid()) return 0;
  SetUp(bodies, pass);
  rows[0] = lower_.Row(0.0f);
  return 1;
}

int DistanceJoint::FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) {
  if (rigid()) return 0;
  AxisConstraintPart* parts[kMaxFreeRowPasses];
  return SoftRows(pass, rows, parts);
}

Constraint::Impulses DistanceJoint::AccumulatedImpulses() const {
  return {spring_.LinearImpulse() + lower_.LinearImpulse() + upper_.LinearImpulse(), Vec3::Zero()};
}

void DistanceJoint::ScaleImpulses(float ratio) {
  spring_.ScaleImpulse(ratio);
  lower_.ScaleImpulse(ratio);
  upper_.ScaleImpulse(ratio);
}

}  // namespace strata
