#include "physics/constraints/ExactJointSolver.h"

#include <algorithm>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace strata {

namespace {
// Rows keep this share of their own stiffness on the diagonal, so redundant rows (a loop of joints, two
// joints between the same bodies) leave the matrix positive definite; a pivot below kTinyPivot of its
// diagonal is dropped.
constexpr double kRegularization = 1e-9;
constexpr double kTinyPivot = 1e-12;
// A free row whose effective inverse mass with the rigid rows holding is below this share of its own is held
// by them alone (its own would be a rounding error's).
constexpr double kTinyReducedShare = 1e-7;
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
  solver->coupling_rows_ = arena.AllocateArray<CouplingRow>(rows);
  solver->first_ = arena.AllocateArray<std::uint32_t>(rows);
  solver->end_ = arena.AllocateArray<std::uint32_t>(rows);
  solver->scratch_ = arena.AllocateArray<double>(rows);
  // The island's moving bodies, numbered here in the order the joints meet them (the scratch maps solver
  // index to that number meanwhile).
  std::uint32_t* const local_of_body = first_row_of_body;
  auto* const local = arena.AllocateArray<std::uint32_t>(2 * joints.size());
  auto* const island_body = arena.AllocateArray<std::uint32_t>(2 * joints.size());
  std::uint32_t body_count = 0;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const std::uint32_t sides[2] = {joints[j]->side_a().solver_index, joints[j]->side_b().solver_index};
    for (int side = 0; side < 2; ++side) {
      local[2 * j + side] = kNoRow;
      if (sides[side] == 0) continue;
      if (local_of_body[sides[side]] == kNoRow) {
        island_body[body_count] = sides[side];
        local_of_body[sides[side]] = body_count++;
      }
      local[2 * j + side] = local_of_body[sides[side]];
    }
  }
  for (const Constraint* joint : joints)
    for (const std::uint32_t body : {joint->side_a().solver_index, joint->side_b().solver_index})
      if (body != 0) local_of_body[body] = kNoRow;
  // Room for every joint that has more than rigid rows to have all its free directions, each with the
  // rigid rows' impulses and the bodies' velocities it causes.
  const auto free_joints = static_cast<std::uint32_t>(std::count_if(
      joints.begin(), joints.end(), [](const Constraint* joint) { return !joint->OnlyRigidRows(); }));
  const std::uint32_t directions = free_joints * Constraint::kMaxFreeRows;
  const std::uint64_t per_direction = rows + std::uint64_t{kBodyResponseSize} * body_count;
  if (free_joints > 0 && rows > 0 && directions * per_direction <= kMaxReducedEntries) {
    solver->body_count_ = body_count;
    solver->local_body_ = local;
    solver->island_body_ = island_body;
    solver->free_begin_ = arena.AllocateArray<std::uint32_t>(joints.size() + 1);
    solver->directions_ = arena.AllocateArray<FreeDirection>(directions);
    solver->responses_ = arena.AllocateArray<float>(std::size_t{directions} * rows);
    solver->body_responses_ =
        arena.AllocateArray<float>(std::size_t{directions} * kBodyResponseSize * body_count);
    solver->coupling_ = arena.AllocateArray<double>(rows);
    solver->body_scratch_ = arena.AllocateArray<double>(std::size_t{kBodyResponseSize} * body_count);
  }
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

namespace {

// Which sides of two rows (0 = A, 1 = B) are the same moving body, and the sign of their coupling through it
// (negative where it is A to one and B to the other). Returns how many (two at most).
template <class RowType>
int SharedSides(const RowType& row, const RowType& other, int (&side)[2], int (&other_side)[2],
                double (&sign)[2]) {
  const std::uint32_t bodies[2] = {row.body_a, row.body_b};
  const std::uint32_t other_bodies[2] = {other.body_a, other.body_b};
  int shared = 0;
  for (int s = 0; s < 2; ++s)
    for (int o = 0; o < 2; ++o)
      if (bodies[s] != 0 && bodies[s] == other_bodies[o] && shared < 2) {
        side[shared] = s;
        other_side[shared] = o;
        sign[shared++] = s == o ? 1.0 : -1.0;
      }
  return shared;
}

// `v` in double, lane for lane (Eigen's cast converts one scalar at a time).
Eigen::Vector4d Widen(const Vec4& v) {
#if defined(__SSE2__)
  Eigen::Vector4d wide;
  const __m128 narrow = _mm_load_ps(v.data());
  _mm_store_pd(wide.data(), _mm_cvtps_pd(narrow));
  _mm_store_pd(wide.data() + 2, _mm_cvtps_pd(_mm_movehl_ps(narrow, narrow)));
  return wide;
#else
  return v.cast<double>();
#endif
}

// One row's Jacobian on its side `side` times another row's push on its side `other_side` (CouplingRow).
template <class CouplingRowType>
double SideCoupling(const CouplingRowType& row, int side, const CouplingRowType& other, int other_side) {
  return (row.linear.cwiseProduct(other.push_linear[other_side]) +
          row.angular[side].cwiseProduct(other.push_angular[other_side]))
      .sum();
}

// A row's rate from its two bodies' velocities (`relative_linear` B's less A's): linear . (v_B - v_A) +
// angular_b . w_B - angular_a . w_A, and what the sides that take no impulse add.
template <class RowType>
float RowRate(const RowType& row, const Vec4& relative_linear, const Vec4& angular_a, const Vec4& angular_b) {
  return row.fixed_rate + (row.linear.cwiseProduct(relative_linear) + row.angular_b.cwiseProduct(angular_b) -
                           row.angular_a.cwiseProduct(angular_a))
                              .sum();
}

}  // namespace

void ExactJointSolver::CoupleBlocks(std::uint32_t block_i, std::uint32_t block_j) {
  // Through each body the two joints share: one's Jacobian on that body times the other's push on it. Every
  // row of a joint has its bodies, so which sides meet is settled once for the pair of joints.
  int side_i[2] = {0, 0}, side_j[2] = {0, 0};
  double sign[2] = {0.0, 0.0};
  const int terms = SharedSides(rows_[block_i], rows_[block_j], side_i, side_j, sign);
  const bool diagonal = block_i == block_j;
  const std::uint32_t end_i = end_[block_i], end_j = end_[block_j];
  // The number of terms fixed at compile time, so an entry is straight-line code: 0 + sign * coupling
  // through the first shared body (+ through the second), summed in that order.
  const auto couple = [&](auto term_count) {
    constexpr int kTerms = decltype(term_count)::value;
    for (std::uint32_t i = block_i; i < end_i; ++i) {
      const CouplingRow& row = coupling_rows_[i];
      double* const entries = ldlt_.Row(i);
      const std::uint32_t last = diagonal ? i + 1 : end_j;
      for (std::uint32_t j = block_j; j < last; ++j) {
        const CouplingRow& other = coupling_rows_[j];
        double sum = 0.0;
        for (int t = 0; t < kTerms; ++t) sum += sign[t] * SideCoupling(row, side_i[t], other, side_j[t]);
        entries[j] = sum;
      }
    }
  };
  if (terms == 2)
    couple(std::integral_constant<int, 2>{});
  else if (terms == 1)
    couple(std::integral_constant<int, 1>{});
  else
    couple(std::integral_constant<int, 0>{});
}

ExactJointSolver::Row ExactJointSolver::MakeRow(const ConstraintBodies& view, const JointRow& joint_row,
                                                std::uint32_t body_a, std::uint32_t body_b) {
  Row r;
  r.linear = ToVec4(joint_row.linear);
  r.angular_a = ToVec4(joint_row.angular_a);
  r.angular_b = ToVec4(joint_row.angular_b);
  r.impulse = joint_row.impulse;
  r.error = joint_row.error;
  r.body_a = body_a;
  r.body_b = body_b;
  r.fixed_rate = 0.0f;
  if (body_a == 0)
    r.fixed_rate -= r.linear.dot(view.a->linear_velocity) + r.angular_a.dot(view.a->angular_velocity);
  if (body_b == 0)
    r.fixed_rate += r.linear.dot(view.b->linear_velocity) + r.angular_b.dot(view.b->angular_velocity);
  r.push_a_linear = body_a != 0 ? Vec4(view.a->inverse_mass * r.linear) : Vec4::Zero();
  r.push_a_angular = body_a != 0 ? view.a->InverseInertiaTimes(r.angular_a) : Vec4::Zero();
  r.push_b_linear = body_b != 0 ? Vec4(view.b->inverse_mass * r.linear) : Vec4::Zero();
  r.push_b_angular = body_b != 0 ? view.b->InverseInertiaTimes(r.angular_b) : Vec4::Zero();
  return r;
}

void ExactJointSolver::MakeCouplingRow(const Row& row, CouplingRow& coupling) {
  coupling.linear = Widen(row.linear);
  coupling.angular[0] = Widen(row.angular_a);
  coupling.angular[1] = Widen(row.angular_b);
  coupling.push_linear[0] = Widen(row.push_a_linear);
  coupling.push_linear[1] = Widen(row.push_b_linear);
  coupling.push_angular[0] = Widen(row.push_a_angular);
  coupling.push_angular[1] = Widen(row.push_b_angular);
}

bool ExactJointSolver::Build(SolverBody* bodies, const SolverPose* poses, float elapsed, int pose_version) {
  if (pose_version >= 0 && pose_version == built_version_) return false;
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
      const std::uint32_t row = block + static_cast<std::uint32_t>(k);
      rows_[row] = MakeRow(view, joint_rows[k], body_a, body_b);
      MakeCouplingRow(rows_[row], coupling_rows_[row]);
    }
    for (std::uint32_t other = first_[block]; other <= block; other = end_[other]) CoupleBlocks(block, other);
    ldlt_.FactorLastBlock(kRegularization, kTinyPivot);
  }
  return true;
}

void ExactJointSolver::ReduceFreeRows(SolverBody* bodies, const SolverPose* poses,
                                      const ConstraintPassContext& pass, float elapsed) {
  if (!solves_free_rows()) return;
  JointRow joint_rows[Constraint::kMaxFreeRows];
  std::uint32_t direction = 0;
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    free_begin_[j] = direction;
    Constraint& joint = *joints_[j];
    if (joint.OnlyRigidRows()) continue;
    SolverBody stand_in_a, stand_in_b;
    const ConstraintBodies view = joint.BodiesForPass(bodies, poses, elapsed, stand_in_a, stand_in_b);
    const int count = joint.FreeRows(view, pass, joint_rows);
    for (int k = 0; k < count; ++k, ++direction) {
      const Row free = MakeRow(view, joint_rows[k], joint.side_a().solver_index, joint.side_b().solver_index);
      CouplingRow free_coupling;
      MakeCouplingRow(free, free_coupling);
      directions_[direction] =
          Reduce(free, free_coupling, local_body_[2 * j], local_body_[2 * j + 1],
                 responses_ + std::size_t{direction} * row_count_,
                 body_responses_ + std::size_t{direction} * kBodyResponseSize * body_count_);
    }
  }
  free_begin_[joints_.size()] = direction;
}

ExactJointSolver::FreeDirection ExactJointSolver::Reduce(const Row& free, const CouplingRow& free_coupling,
                                                         std::uint32_t local_a, std::uint32_t local_b,
                                                         float* response, float* body_response) {
  const double alone = (free.body_a != 0 ? SideCoupling(free_coupling, 0, free_coupling, 0) : 0.0) +
                       (free.body_b != 0 ? SideCoupling(free_coupling, 1, free_coupling, 1) : 0.0);
  // b: only the rows of joints that share a body with this one couple with it.
  for (std::uint32_t block = 0; block < row_count_; block = end_[block]) {
    int side[2] = {0, 0}, free_side[2] = {0, 0};
    double sign[2] = {0.0, 0.0};
    const int terms = SharedSides(rows_[block], free, side, free_side, sign);
    for (std::uint32_t i = block; i < end_[block]; ++i) {
      double sum = 0.0;
      for (int t = 0; t < terms; ++t)
        sum += sign[t] * SideCoupling(coupling_rows_[i], side[t], free_coupling, free_side[t]);
      coupling_[i] = sum;
      scratch_[i] = sum;
    }
  }
  ldlt_.Solve(scratch_);
  // The bodies' velocities per unit impulse: the row's push on its two bodies less the rigid rows' answer,
  // summed in double (the two nearly cancel on a light body the rigid rows hold), then rounded once.
  std::fill(body_scratch_, body_scratch_ + std::size_t{kBodyResponseSize} * body_count_, 0.0);
  AddPush(free, local_a, local_b, 1.0);
  double held = 0.0;
  std::uint32_t row = 0;
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const auto count = static_cast<std::uint32_t>(joints_[j]->RigidRowCount());
    for (std::uint32_t end = row + count; row < end; ++row) {
      held += coupling_[row] * scratch_[row];
      response[row] = static_cast<float>(scratch_[row]);
      if (scratch_[row] != 0.0)
        AddPush(rows_[row], local_body_[2 * j], local_body_[2 * j + 1], -scratch_[row]);
    }
  }
  FreeDirection direction{free, 0.0f, body_count_, 0};
  for (std::uint32_t body = 0; body < body_count_; ++body) {
    const double* const from = body_scratch_ + std::size_t{kBodyResponseSize} * body;
    float* const to = body_response + std::size_t{kBodyResponseSize} * body;
    bool moves = false;
    for (int k = 0; k < kBodyResponseSize; ++k) {
      to[k] = static_cast<float>(from[k]);
      moves = moves || to[k] != 0.0f;
    }
    if (!moves) continue;
    direction.body_begin = std::min(direction.body_begin, body);
    direction.body_end = body + 1;
  }
  direction.body_begin = std::min(direction.body_begin, direction.body_end);
  const double reduced = alone - held;
  // A direction the rigid rows hold all but alone (to rounding) needs nothing from the free rows.
  if (reduced > kTinyReducedShare * alone) direction.effective_mass = static_cast<float>(1.0 / reduced);
  return direction;
}

void ExactJointSolver::AddPush(const Row& row, std::uint32_t local_a, std::uint32_t local_b, double scale) {
  auto add = [&](std::uint32_t body, const Vec4& linear, const Vec4& angular, double sign) {
    double* const to = body_scratch_ + std::size_t{kBodyResponseSize} * body;
    for (int k = 0; k < 3; ++k) {
      to[k] += sign * scale * linear[k];
      to[3 + k] += sign * scale * angular[k];
    }
  };
  if (row.body_a != 0) add(local_a, row.push_a_linear, row.push_a_angular, -1.0);
  if (row.body_b != 0) add(local_b, row.push_b_linear, row.push_b_angular, 1.0);
}

void ExactJointSolver::SolveFreeRows(SolverBody* bodies, const ConstraintPassContext& pass) {
  if (!solves_free_rows()) return;
  FreeRowPass passes[Constraint::kMaxFreeRowPasses];
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    if (free_begin_[j] == free_begin_[j + 1]) continue;
    const int count = joints_[j]->FreeRowPasses(pass, passes);
    for (int k = 0; k < count; ++k) {
      const FreeRowPass& row = passes[k];
      const std::uint32_t direction = free_begin_[j] + static_cast<std::uint32_t>(row.direction);
      const FreeDirection& free = directions_[direction];
      const float change = RowImpulse(row.sign * Rate(bodies, free.row), row.target, free.effective_mass,
                                      *row.impulse, row.low, row.high);
      if (change == 0.0f) continue;
      // The rigid rows answer at once, so the next row sees velocities they hold.
      const float along = row.sign * change;
      const float* const response = responses_ + std::size_t{direction} * row_count_;
      for (std::uint32_t i = 0; i < row_count_; ++i) *rows_[i].impulse -= along * response[i];
      const float* const moves = body_responses_ + std::size_t{direction} * kBodyResponseSize * body_count_;
      for (std::uint32_t body = free.body_begin; body < free.body_end; ++body) {
        const float* const move = moves + std::size_t{kBodyResponseSize} * body;
        SolverBody& target = bodies[island_body_[body]];
        target.linear_velocity += ToVec4(along * Vec3(move[0], move[1], move[2]));
        target.angular_velocity += ToVec4(along * Vec3(move[3], move[4], move[5]));
      }
    }
  }
}

void ExactJointSolver::SolvePositions(SolverBody* bodies, SolverPose* poses, float elapsed,
                                      int pose_version) {
  if (row_count_ == 0) return;
  Build(bodies, poses, elapsed, pose_version);
  built_version_ = -1;  // the bodies move: the rows no longer hold for any version
  for (std::uint32_t i = 0; i < row_count_; ++i)
    scratch_[i] = -kPositionFraction * static_cast<double>(rows_[i].error);
  ldlt_.Solve(scratch_);
  // A joint's rows share its two bodies: each side moves once by the sum of its rows' pushes.
  for (std::uint32_t block = 0; block < row_count_; block = end_[block]) {
    Vec4 move_a = Vec4::Zero(), turn_a = Vec4::Zero(), move_b = Vec4::Zero(), turn_b = Vec4::Zero();
    for (std::uint32_t i = block; i < end_[block]; ++i) {
      const Row& row = rows_[i];
      const auto change = static_cast<float>(scratch_[i]);
      move_a += change * row.push_a_linear;
      turn_a += change * row.push_a_angular;
      move_b += change * row.push_b_linear;
      turn_b += change * row.push_b_angular;
    }
    const Row& first = rows_[block];
    if (first.body_a != 0)
      MoveSolverBody(bodies[first.body_a], poses[first.body_a], -ToVec3(move_a), -ToVec3(turn_a));
    if (first.body_b != 0)
      MoveSolverBody(bodies[first.body_b], poses[first.body_b], ToVec3(move_b), ToVec3(turn_b));
  }
}

float ExactJointSolver::Rate(const SolverBody* bodies, const Row& row) {
  const SolverBody& a = bodies[row.body_a];  // the fixed body (no velocity) for a side that takes no impulse
  const SolverBody& b = bodies[row.body_b];
  return RowRate(row, b.linear_velocity - a.linear_velocity, a.angular_velocity, b.angular_velocity);
}

void ExactJointSolver::Solve(SolverBody* bodies, const ConstraintPassContext& pass) {
  if (row_count_ == 0) return;
  // Box2D's soft update for all rows at once: with A = J M^-1 J^T, the change is
  // mass_scale * A^-1 (-(rate + bias)) - impulse_scale * impulse; a relax pass is the rigid A^-1 (-rate).
  RowTarget soft = EqualityTarget(1.0f, pass);
  if (solves_free_rows() && free_begin_[joints_.size()] > 0) soft = {soft.bias, 1.0f, 0.0f};
  // A joint's rows share its two bodies (the fixed body, with no velocity, for a side that takes no
  // impulse): their velocities are read once per joint, and each side is written once with the sum of its
  // rows' pushes. A joint's row count is a compile-time constant in each, so the loops unroll.
  for (std::uint32_t block = 0; block < row_count_; block = end_[block])
    BlockSkylineLdlt::WithBlockSize(static_cast<int>(end_[block] - block), [&](auto size) {
      constexpr int kRows = decltype(size)::value;
      const Row* const rows = rows_ + block;
      const SolverBody& a = bodies[rows[0].body_a];
      const SolverBody& b = bodies[rows[0].body_b];
      const Vec4 relative_linear = b.linear_velocity - a.linear_velocity;
      for (int i = 0; i < kRows; ++i)
        scratch_[block + i] =
            -static_cast<double>(RowRate(rows[i], relative_linear, a.angular_velocity, b.angular_velocity) +
                                 soft.bias * rows[i].error);
    });
  ldlt_.Solve(scratch_);
  for (std::uint32_t block = 0; block < row_count_; block = end_[block])
    BlockSkylineLdlt::WithBlockSize(static_cast<int>(end_[block] - block), [&](auto size) {
      constexpr int kRows = decltype(size)::value;
      const Row* const rows = rows_ + block;
      Vec4 linear_a = Vec4::Zero(), angular_a = Vec4::Zero(), linear_b = Vec4::Zero(),
           angular_b = Vec4::Zero();
      for (int i = 0; i < kRows; ++i) {
        const Row& row = rows[i];
        const float change =
            soft.mass_scale * static_cast<float>(scratch_[block + i]) - soft.impulse_scale * *row.impulse;
        linear_a += change * row.push_a_linear;
        angular_a += change * row.push_a_angular;
        linear_b += change * row.push_b_linear;
        angular_b += change * row.push_b_angular;
        *row.impulse += change;
      }
      if (rows[0].body_a != 0) {
        SolverBody& a = bodies[rows[0].body_a];
        a.linear_velocity -= linear_a;
        a.angular_velocity -= angular_a;
      }
      if (rows[0].body_b != 0) {
        SolverBody& b = bodies[rows[0].body_b];
        b.linear_velocity += linear_b;
        b.angular_velocity += angular_b;
      }
    });
}

}  // namespace strata
