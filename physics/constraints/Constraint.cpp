#include "physics/constraints/Constraint.h"

#include <cmath>

namespace strata {

std::string_view ToString(ConstraintType type) {
  switch (type) {
    case ConstraintType::kFixed:
      return "fixed";
    case ConstraintType::kPoint:
      return "point";
    case ConstraintType::kDistance:
      return "distance";
    case ConstraintType::kHinge:
      return "hinge";
    case ConstraintType::kSlider:
      return "slider";
    case ConstraintType::kSwingTwist:
      return "swing_twist";
  }
  return "unknown";
}

Status JointSettingsBase::ValidateBase() const {
  if (body_b.IsInvalid()) return MakeError(ErrorCode::kInvalidArgument, "body_b must be a body");
  if (body_a == body_b) return MakeError(ErrorCode::kInvalidArgument, "body_a and body_b are the same body");
  if (!std::isfinite(max_force) || max_force < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "max_force must be finite and >= 0 (0 = unbreakable)");
  if (!std::isfinite(max_torque) || max_torque < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "max_torque must be finite and >= 0 (0 = unbreakable)");
  return Status::Ok();
}

Result<Vec3> UnitAxis(const Vec3& axis, const char* what) {
  const float length = IsFinite(axis) ? axis.norm() : 0.0f;
  if (!(length > 1e-6f) || !std::isfinite(length))
    return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " must be a finite, non-zero vector");
  return Vec3(axis / length);
}

Result<Vec3> PerpendicularAxis(const Vec3& axis, const Vec3& normal, const char* what) {
  if (!IsFinite(normal)) return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " must be finite");
  Vec3 perpendicular = normal - normal.dot(axis) * axis;
  if (normal.isZero(0.0f)) {
    // Any: the world axis least along `axis`, made perpendicular.
    Eigen::Index least = 0;
    axis.cwiseAbs().minCoeff(&least);
    perpendicular = Vec3::Unit(least) - axis[least] * axis;
  }
  const float length = perpendicular.norm();
  if (!(length > 1e-4f * std::max(1.0f, normal.norm())))
    return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " must not be parallel to the axis");
  return Vec3(perpendicular / length);
}

Status CheckPoint(const Vec3& point, const char* what) {
  if (!IsFinite(point) || point.cwiseAbs().maxCoeff() > kMaxJointCoordinate)
    return MakeError(ErrorCode::kInvalidArgument, std::string(what) + " must be finite and within " +
                                                      std::to_string(kMaxJointCoordinate) +
                                                      " m of the origin");
  return Status::Ok();
}

Constraint::Constraint(ConstraintType type, const JointSettingsBase& settings, const LocalFrames& frames)
    : type_(type),
      body_a_(settings.body_a),
      body_b_(settings.body_b),
      local_(frames),
      max_force_(settings.max_force),
      max_torque_(settings.max_torque),
      collide_connected_(settings.collide_connected) {}

Constraint::LocalFrames Constraint::MakeLocalFrames(const BodyFrame& a, const BodyFrame& b,
                                                    const Vec3& anchor_a, const Vec3& anchor_b,
                                                    const Vec3& axis, const Vec3& normal) {
  Mat3 world;
  world.col(0) = axis;
  world.col(1) = normal;
  world.col(2) = axis.cross(normal);
  const Quat frame(world);
  LocalFrames local;
  local.anchor_a = a.rotation.conjugate() * (anchor_a - a.center_of_mass);
  local.anchor_b = b.rotation.conjugate() * (anchor_b - b.center_of_mass);
  local.frame_a = (a.rotation.conjugate() * frame).normalized();
  local.frame_b = (b.rotation.conjugate() * frame).normalized();
  return local;
}

Constraint::WorldFrames Constraint::Frames(const ConstraintBodies& bodies) const {
  WorldFrames frames;
  frames.r_a = bodies.rotation_a * local_.anchor_a;
  frames.r_b = bodies.rotation_b * local_.anchor_b;
  frames.separation = (bodies.center_b + frames.r_b) - (bodies.center_a + frames.r_a);
  frames.axes_a = (bodies.rotation_a * local_.frame_a).toRotationMatrix();
  frames.axes_b = (bodies.rotation_b * local_.frame_b).toRotationMatrix();
  return frames;
}

void Constraint::BeginStep(const ConstraintSide& a, const ConstraintSide& b, float h) {
  side_a_ = a;
  side_b_ = b;
  // The kept impulses are per substep: a different substep scales them (a longer one pushes longer).
  if (substep_ > 0.0f && h != substep_) ScaleImpulses(h / substep_);
  substep_ = h;
}

namespace {
// A side that takes no impulse: its own velocity (a kinematic body's, or none) and no inverse mass, in a
// copy only this pass writes; its pose carried along its velocity to `elapsed`.
void StandIn(const ConstraintSide& side, float elapsed, SolverBody& scratch, Vec3& center, Quat& rotation) {
  scratch = SolverBody();
  scratch.linear_velocity = ToVec4(side.linear_velocity);
  scratch.angular_velocity = ToVec4(side.angular_velocity);
  center = side.start.center_of_mass + elapsed * side.linear_velocity;
  rotation = side.start.rotation;
  if (side.angular_velocity.isZero(0.0f)) return;
  const Vec3 turn = elapsed * side.angular_velocity;
  const float angle = turn.norm();
  rotation = (Quat(Eigen::AngleAxisf(angle, turn / angle)) * rotation).normalized();
}
}  // namespace

ConstraintBodies Constraint::BodiesForPass(SolverBody* bodies, const SolverPose* poses, float elapsed,
                                           SolverBody& scratch_a, SolverBody& scratch_b) const {
  ConstraintBodies view;
  if (side_a_.solver_index != 0) {
    view.a = &bodies[side_a_.solver_index];
    view.center_a = ToVec3(poses[side_a_.solver_index].center_of_mass);
    view.rotation_a = poses[side_a_.solver_index].rotation;
  } else {
    StandIn(side_a_, elapsed, scratch_a, view.center_a, view.rotation_a);
    view.a = &scratch_a;
  }
  if (side_b_.solver_index != 0) {
    view.b = &bodies[side_b_.solver_index];
    view.center_b = ToVec3(poses[side_b_.solver_index].center_of_mass);
    view.rotation_b = poses[side_b_.solver_index].rotation;
  } else {
    StandIn(side_b_, elapsed, scratch_b, view.center_b, view.rotation_b);
    view.b = &scratch_b;
  }
  return view;
}

void Constraint::EndStep() {
  const Impulses impulses = AccumulatedImpulses();
  const float inverse_h = substep_ > 0.0f ? 1.0f / substep_ : 0.0f;
  forces_.force = inverse_h * impulses.linear;
  forces_.torque = inverse_h * impulses.angular;
  const bool over_force = max_force_ > 0.0f && forces_.force.norm() > max_force_;
  const bool over_torque = max_torque_ > 0.0f && forces_.torque.norm() > max_torque_;
  if (!over_force && !over_torque) return;
  broken_ = true;
  ScaleImpulses(0.0f);
}

void Constraint::Draw(const BodyFrame& a, const BodyFrame& b, std::vector<ConstraintLine>& lines) const {
  const Vec3 anchor_a = a.center_of_mass + a.rotation * local_.anchor_a;
  const Vec3 anchor_b = b.center_of_mass + b.rotation * local_.anchor_b;
  const ConstraintLine::Kind kind = broken_ ? ConstraintLine::Kind::kBroken : ConstraintLine::Kind::kAnchor;
  lines.push_back({a.center_of_mass, anchor_a, kind});
  lines.push_back({b.center_of_mass, anchor_b, kind});
  const Vec3 axis = (a.rotation * local_.frame_a) * Vec3::UnitX();
  lines.push_back({anchor_a, anchor_a + 0.25f * axis, ConstraintLine::Kind::kAxis});
}

}  // namespace strata
