#include "physics/constraints/ExactJointSolver.h"

#include <algorithm>

namespace strata {

namespace {
// Rows keep this share of their own stiffness on the diagonal, so redundant rows (a loop of joints, two
// joints between the same bodies) leave the matrix positive definite; a pivot below kTinyPivot of its
// diagonal is dropped.
constexpr double kRegularization = 1e-9;
constexpr double kTinyPivot = 1e-12;
// Constraint::kPositionFraction of the error per position step: the whole error at once (a Newton step)
// tore a 100-link chain with a 100 kg end apart when it was dropped level and whipped (84 cm; half the error:
// 4 cm); a fifth keeps every joint within 0.5 mm there, 0.1 mm in a 60-degree swing.
constexpr double kPositionFraction = Constraint::kPositionFraction;
}  // namespace

ExactJointSolver* ExactJointSolver::Create(BlockArena& arena, std::span<Constraint* const> joints,
                                           std::uint32_t* first_row_of_body) {
  auto* solver = new (arena.AllocateArray<ExactJointSolver>(1)) ExactJointSolver();
  solver->joints_ = joints;
  std::uint32_t rows = 0;
  for (const Constraint* joint : joints) rows += static_cast<std::uint32_t>(joint->RigidRowCount());
  solver->row_count_ = rows;
  solver->rows_ = arena.AllocateArray<Row>(rows);
  solver->first_ = arena.AllocateArray<std::uint32_t>(rows);
  solver->end_ = arena.AllocateArray<std::uint32_t>(rows);
  solver->scratch_ = arena.AllocateArray<double>(rows);
  // A row couples with every row before it that shares a moving body with it: its skyline starts at the
  // first row that touched either of its bodies (or its joint's first row).
  std::uint32_t row = 0;
  std::uint32_t entries = 0;
  for (const Constraint* joint : joints) {
    const std::uint32_t joint_first = row;
    std::uint32_t first = joint_first;
    for (const std::uint32_t body : {joint->side_a().solver_index, joint->side_b().solver_index}) {
      if (body == 0) continue;
      if (first_row_of_body[body] == kNoRow) first_row_of_body[body] = joint_first;
      first = std::min(first, first_row_of_body[body]);
    }
    const auto count = static_cast<std::uint32_t>(joint->RigidRowCount());
    for (std::uint32_t k = 0; k < count; ++k, ++row) {
      solver->first_[row] = first;
      solver->end_[row] = joint_first + count;
    }
    entries += count * (joint_first + count - first);
  }
  for (const Constraint* joint : joints)
    for (const std::uint32_t body : {joint->side_a().solver_index, joint->side_b().solver_index})
      if (body != 0) first_row_of_body[body] = kNoRow;
  solver->ldlt_.Allocate(arena, rows, entries);
  return solver;
}

void ExactJointSolver::CoupleBlocks(std::uint32_t block_i, std::uint32_t block_j) {
  // Through each body the two joints share: one's Jacobian on that body times the other's push on it,
  // negated where the body is A to one and B to the other. Every row of a joint has its bodies, so which
  // sides meet is settled once for the pair of joints (two at most). Float products are exact in double.
  const std::uint32_t bodies_i[2] = {rows_[block_i].body_a, rows_[block_i].body_b};
  const std::uint32_t bodies_j[2] = {rows_[block_j].body_a, rows_[block_j].body_b};
  int side_i[2] = {0, 0}, side_j[2] = {0, 0};
  double sign[2] = {0.0, 0.0};
  int terms = 0;
  for (int si = 0; si < 2; ++si)
    for (int sj = 0; sj < 2; ++sj)
      if (bodies_i[si] != 0 && bodies_i[si] == bodies_j[sj] && terms < 2) {
        side_i[terms] = si;
        side_j[terms] = sj;
        sign[terms++] = si == sj ? 1.0 : -1.0;
      }
  auto dot = [](const Vec3& a, const Vec3& b) { return a.cast<double>().dot(b.cast<double>()); };
  const bool diagonal = block_i == block_j;
  for (std::uint32_t i = block_i; i < end_[block_i]; ++i) {
    const Row& row = rows_[i];
    double* const entries = ldlt_.Row(i);
    const std::uint32_t last = diagonal ? i + 1 : end_[block_j];
    for (std::uint32_t j = block_j; j < last; ++j) {
      const Row& other = rows_[j];
      double sum = 0.0;
      for (int t = 0; t < terms; ++t) {
        const Vec3& angular = side_i[t] == 0 ? row.row.angular_a : row.row.angular_b;
        const Vec3& push_linear = side_j[t] == 0 ? other.push_a_linear : other.push_b_linear;
        const Vec3& push_angular = side_j[t] == 0 ? other.push_a_angular : other.push_b_angular;
        sum += sign[t] * (dot(row.row.linear, push_linear) + dot(angular, push_angular));
      }
      entries[j] = sum;
    }
  }
}

void ExactJointSolver::Build(SolverBody* bodies, const SolverPose* poses, float elapsed, int pose_version) {
  if (pose_version >= 0 && pose_version == built_version_) return;
  built_version_ = pose_version;
  // A joint's rows are a block, coupled and factored as soon as they are made (what they couple with was
  // made just before: one pass over the rows, in cache). Rows whose pivot is lost to rounding (a loop of
  // joints repeats a constraint) are dropped from the solve.
  ldlt_.Clear();
  JointRow joint_rows[Constraint::kMaxRigidRows];
  for (Constraint* joint : joints_) {
    const int count = joint->RigidRowCount();
    if (count == 0) continue;
    SolverBody stand_in_a, stand_in_b;
    const ConstraintBodies view = joint->BodiesForPass(bodies, poses, elapsed, stand_in_a, stand_in_b);
    joint->RigidRows(view, joint_rows);
    const std::uint32_t body_a = joint->side_a().solver_index, body_b = joint->side_b().solver_index;
    const std::uint32_t block = ldlt_.AddBlock(first_[ldlt_.size()], count);
    for (int k = 0; k < count; ++k) {
      Row& r = rows_[block + static_cast<std::uint32_t>(k)];
      r.row = joint_rows[k];
      r.body_a = body_a;
      r.body_b = body_b;
      r.fixed_rate = 0.0f;
      if (body_a == 0)
        r.fixed_rate -= r.row.linear.dot(ToVec3(view.a->linear_velocity)) +
                        r.row.angular_a.dot(ToVec3(view.a->angular_velocity));
      if (body_b == 0)
        r.fixed_rate += r.row.linear.dot(ToVec3(view.b->linear_velocity)) +
                        r.row.angular_b.dot(ToVec3(view.b->angular_velocity));
      r.push_a_linear = body_a != 0 ? Vec3(view.a->inverse_mass * r.row.linear) : Vec3::Zero();
      r.push_a_angular = body_a != 0 ? InverseInertiaTimes(*view.a, r.row.angular_a) : Vec3::Zero();
      r.push_b_linear = body_b != 0 ? Vec3(view.b->inverse_mass * r.row.linear) : Vec3::Zero();
      r.push_b_angular = body_b != 0 ? InverseInertiaTimes(*view.b, r.row.angular_b) : Vec3::Zero();
    }
    for (std::uint32_t other = first_[block]; other <= block; other = end_[other]) CoupleBlocks(block, other);
    ldlt_.FactorLastBlock(kRegularization, kTinyPivot);
  }
}

void ExactJointSolver::SolvePositions(SolverBody* bodies, SolverPose* poses, float elapsed,
                                      int pose_version) {
  if (row_count_ == 0) return;
  Build(bodies, poses, elapsed, pose_version);
  built_version_ = -1;  // the bodies move: the rows no longer hold for any version
  for (std::uint32_t i = 0; i < row_count_; ++i)
    scratch_[i] = -kPositionFraction * static_cast<double>(rows_[i].row.error);
  ldlt_.Solve(scratch_);
  for (std::uint32_t i = 0; i < row_count_; ++i) {
    const Row& row = rows_[i];
    const auto change = static_cast<float>(scratch_[i]);
    if (row.body_a != 0)
      MoveSolverBody(bodies[row.body_a], poses[row.body_a], -change * row.push_a_linear,
                     -change * row.push_a_angular);
    if (row.body_b != 0)
      MoveSolverBody(bodies[row.body_b], poses[row.body_b], change * row.push_b_linear,
                     change * row.push_b_angular);
  }
}

float ExactJointSolver::Rate(const SolverBody* bodies, const Row& row) const {
  float rate = row.fixed_rate;
  if (row.body_a != 0) {
    const SolverBody& a = bodies[row.body_a];
    rate -= row.row.linear.dot(ToVec3(a.linear_velocity)) + row.row.angular_a.dot(ToVec3(a.angular_velocity));
  }
  if (row.body_b != 0) {
    const SolverBody& b = bodies[row.body_b];
    rate += row.row.linear.dot(ToVec3(b.linear_velocity)) + row.row.angular_b.dot(ToVec3(b.angular_velocity));
  }
  return rate;
}

void ExactJointSolver::Solve(SolverBody* bodies, const ConstraintPassContext& pass) {
  if (row_count_ == 0) return;
  // Box2D's soft update for all rows at once: with A = J M^-1 J^T, the change is
  // mass_scale * A^-1 (-(rate + bias)) - impulse_scale * impulse; a relax pass is the rigid A^-1 (-rate).
  const RowTarget soft = EqualityTarget(1.0f, pass);
  for (std::uint32_t i = 0; i < row_count_; ++i)
    scratch_[i] = -static_cast<double>(Rate(bodies, rows_[i]) + soft.bias * rows_[i].row.error);
  ldlt_.Solve(scratch_);
  for (std::uint32_t i = 0; i < row_count_; ++i) {
    const Row& row = rows_[i];
    const float change =
        soft.mass_scale * static_cast<float>(scratch_[i]) - soft.impulse_scale * *row.row.impulse;
    *row.row.impulse += change;
    if (row.body_a != 0) {
      SolverBody& a = bodies[row.body_a];
      a.linear_velocity -= ToVec4(change * row.push_a_linear);
      a.angular_velocity -= ToVec4(change * row.push_a_angular);
    }
    if (row.body_b != 0) {
      SolverBody& b = bodies[row.body_b];
      b.linear_velocity += ToVec4(change * row.push_b_linear);
      b.angular_velocity += ToVec4(change * row.push_b_angular);
    }
  }
}

}  // namespace strata
