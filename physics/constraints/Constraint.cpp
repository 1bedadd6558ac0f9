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

Constraint::WorldArms Constraint::Arms(const ConstraintBodies& bodies) const {
  WorldArms arms;
  arms.r_a = bodies.rotation_a * local_.anchor_a;
  arms.r_b = bodies.rotation_b * local_.anchor_b;
  arms.separation = (bodies.center_b + arms.r_b) - (bodies.center_a + arms.r_a);
  return arms;
}

Constraint::WorldFrames Constraint::Frames(const ConstraintBodies& bodies) const {
  WorldFrames frames;
  static_cast<WorldArms&>(frames) = Arms(bodies);
  frames.frame_a = bodies.rotation_a * local_.frame_a;
  frames.frame_b = bodies.rotation_b * local_.frame_b;
  frames.axes_a = frames.frame_a.toRotationMatrix();
  frames.axes_b = frames.frame_b.toRotationMatrix();
  return frames;
}

void Constraint::BeginStep(const ConstraintSide& a, const ConstraintSide& b, float h) {
  side_a_ = a;
  side_b_ = b;
  set_up_version_ = -1;
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

void Constraint::LinkIslands(IslandBuilder& islands) const {
  if (side_a_.solver_index != 0 && side_b_.solver_index != 0)
    islands.Link(side_a_.solver_index - 1, side_b_.solver_index - 1);
}

namespace {
// Solves K x = b for the symmetric `k` (its lower triangle, n <= kMaxRigidRows rows) by L D L^T in place,
// without pivoting; `x` holds b on entry. A pivot lost to rounding (two rows made parallel by a degenerate
// pose) drops its row, whose unknown comes out 0, rather than pushing it with a huge impulse.
void SolveSmallSymmetric(double (&k)[Constraint::kMaxRigidRows][Constraint::kMaxRigidRows], double* x,
                         int n) {
  constexpr double kTinyPivot = 1e-12;
  double inverse_pivot[Constraint::kMaxRigidRows];
  for (int r = 0; r < n; ++r) {
    // The row as L(r, c) D(c) first (rows above hold L), then scaled to L(r, c).
    for (int c = 0; c < r; ++c)
      for (int m = 0; m < c; ++m) k[r][c] -= k[r][m] * k[c][m];
    double pivot = k[r][r];
    for (int c = 0; c < r; ++c) {
      const double scaled = k[r][c] * inverse_pivot[c];
      pivot -= scaled * k[r][c];
      k[r][c] = scaled;
    }
    const bool kept = pivot > kTinyPivot * k[r][r];
    inverse_pivot[r] = kept ? 1.0 / pivot : 0.0;
  }
  for (int r = 0; r < n; ++r)
    for (int m = 0; m < r; ++m) x[r] -= k[r][m] * x[m];
  for (int r = 0; r < n; ++r) x[r] *= inverse_pivot[r];
  for (int r = n; r-- > 0;)
    for (int m = r + 1; m < n; ++m) x[r] -= k[m][r] * x[m];
}
}  // namespace

void Constraint::SolvePosition(SolverBody* bodies, SolverPose* poses, float elapsed) {
  const int count = RigidRowCount();
  if (count == 0) return;
  SolverBody stand_in_a, stand_in_b;
  const ConstraintBodies view = BodiesForPass(bodies, poses, elapsed, stand_in_a, stand_in_b);
  JointRow rows[kMaxRigidRows];
  RigidRows(view, rows);
  // K = J M^-1 J^T of the joint's rows (they couple through its two bodies), in double: a point row and a
  // rotation row of a light link differ by orders of magnitude.
  double coupling[kMaxRigidRows][kMaxRigidRows];
  double lambda[kMaxRigidRows];
  Vec3 push_a_angular[kMaxRigidRows], push_b_angular[kMaxRigidRows];
  const float inverse_mass = view.a->inverse_mass + view.b->inverse_mass;
  for (int i = 0; i < count; ++i) {
    push_a_angular[i] = InverseInertiaTimes(*view.a, rows[i].angular_a);
    push_b_angular[i] = InverseInertiaTimes(*view.b, rows[i].angular_b);
    lambda[i] = -static_cast<double>(kPositionFraction * rows[i].error);
  }
  for (int i = 0; i < count; ++i)
    for (int j = 0; j <= i; ++j)
      coupling[i][j] = inverse_mass * rows[i].linear.dot(rows[j].linear) +
                       rows[i].angular_a.dot(push_a_angular[j]) + rows[i].angular_b.dot(push_b_angular[j]);
  SolveSmallSymmetric(coupling, lambda, count);
  for (int i = 0; i < count; ++i)
    if (!std::isfinite(lambda[i])) return;
  Vec3 linear = Vec3::Zero(), turn_a = Vec3::Zero(), turn_b = Vec3::Zero();
  for (int i = 0; i < count; ++i) {
    const auto change = static_cast<float>(lambda[i]);
    linear += change * rows[i].linear;
    turn_a += change * push_a_angular[i];
    turn_b += change * push_b_angular[i];
  }
  if (side_a_.solver_index != 0)
    MoveSolverBody(bodies[side_a_.solver_index], poses[side_a_.solver_index], -view.a->inverse_mass * linear,
                   -turn_a);
  if (side_b_.solver_index != 0)
    MoveSolverBody(bodies[side_b_.solver_index], poses[side_b_.solver_index], view.b->inverse_mass * linear,
                   turn_b);
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
