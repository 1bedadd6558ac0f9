#include "physics/solver/DirectContactSolver.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace strata {

namespace {

constexpr int kNormal = 0;
// Rigid rows still get this much softness (relative to the row's own inverse mass): four coplanar points
// between two bodies have only three independent motions, and the small term picks the even split.
constexpr float kRigidSoftness = 1e-6f;
// Rounds of freeing and holding rows at their limits in one pass; a pass that runs out keeps its last
// iterate, which is within the limits, and the next pass goes on from there.
constexpr int kMaxActiveSetRounds = 16;
constexpr double kUnbounded = 1e30;
// Solves with friction limits updated from the normal impulses, until they move less than this fraction.
constexpr int kMaxFrictionLimitUpdates = 3;
constexpr double kFrictionLimitTolerance = 0.01;
// A row held at a limit may pull away from it this fast (m/s) before it is freed.
constexpr double kResidualTolerance = 1e-6;

bool ShareBody(const SolverContact& x, const SolverContact& y) {
  const ContactConstraint& a = *x.constraint;
  const ContactConstraint& b = *y.constraint;
  auto moved = [](std::uint32_t body, bool dynamic) { return dynamic ? body : 0u; };
  const std::uint32_t xa = moved(a.body_a, a.dynamic_a), xb = moved(a.body_b, a.dynamic_b);
  const std::uint32_t ya = moved(b.body_a, b.dynamic_a), yb = moved(b.body_b, b.dynamic_b);
  return (xa != 0 && (xa == ya || xa == yb)) || (xb != 0 && (xb == ya || xb == yb));
}

// Reverse Cuthill-McKee over contacts (`adjacent`: share a body the solver moves), each component starting
// from a contact with the fewest neighbours: a stack comes out end to end, so its coupling is banded.
void BandedOrder(std::uint32_t count, const std::uint8_t* adjacent, std::uint32_t* order,
                 std::uint32_t* degree, std::uint8_t* placed) {
  for (std::uint32_t i = 0; i < count; ++i) {
    degree[i] = 0;
    placed[i] = 0;
    for (std::uint32_t j = 0; j < count; ++j) degree[i] += j != i && adjacent[i * count + j];
  }
  std::uint32_t filled = 0;
  while (filled < count) {
    std::uint32_t start = count;
    for (std::uint32_t i = 0; i < count; ++i)
      if (!placed[i] && (start == count || degree[i] < degree[start])) start = i;
    placed[start] = 1;
    order[filled++] = start;
    for (std::uint32_t head = filled - 1; head < filled; ++head) {
      const std::uint32_t from = order[head];
      const std::uint32_t begin = filled;
      for (std::uint32_t j = 0; j < count; ++j)
        if (!placed[j] && adjacent[from * count + j]) placed[j] = 1, order[filled++] = j;
      // Insertion sort by degree, stable (and no buffer to allocate, unlike std::stable_sort).
      for (std::uint32_t k = begin + 1; k < filled; ++k)
        for (std::uint32_t m = k; m > begin && degree[order[m]] < degree[order[m - 1]]; --m)
          std::swap(order[m], order[m - 1]);
    }
  }
  std::reverse(order, order + count);
}

// The mass a contact carries, from its warm impulse, over the heavier of its bodies' masses (at least 1).
float LoadScale(const SolverContact& c, const SolverBody* bodies, float weight_per_impulse) {
  float impulse = 0.0f;
  for (int k = 0; k < c.point_count; ++k) impulse += c.points()[k].normal_impulse;
  const float a = bodies[c.constraint->body_a].inverse_mass;
  const float b = bodies[c.constraint->body_b].inverse_mass;
  const float lighter = std::min(a > 0.0f ? a : kLargeFloat, b > 0.0f ? b : kLargeFloat);
  if (lighter >= kLargeFloat) return 1.0f;
  return std::max(1.0f, impulse * weight_per_impulse * lighter);
}

const Vec4& Direction(const SolverContact& c, int axis) {
  return axis == kNormal ? c.normal : c.tangent[axis - 1];
}

float& Accumulated(SolverContactPoint& p, int axis) {
  return axis == kNormal ? p.normal_impulse : p.tangent_impulse[axis - 1];
}

}  // namespace

float DirectContactSolver::RowCoupling(const Row& ri, const Row& rj, const SolverBody* bodies) {
  const SolverContactPoint& pi = *ri.point;
  const SolverContactPoint& pj = *rj.point;
  const Vec4& di = Direction(*ri.contact, ri.axis);
  const Vec4& dj = Direction(*rj.contact, rj.axis);
  // Through each body both rows move: side signs (-1 on A's side, +1 on B's) times the body's response.
  auto through = [&](std::uint32_t body, float side_i, const Vec4& angular_i, float side_j,
                     const Vec4& response_j) {
    return side_i * side_j * (bodies[body].inverse_mass * di.dot(dj) + angular_i.dot(response_j));
  };
  float sum = 0.0f;
  if (ri.body_a != 0 && ri.body_a == rj.body_a)
    sum += through(ri.body_a, -1, pi.angular_a[ri.axis], -1, pj.response_a[rj.axis]);
  if (ri.body_a != 0 && ri.body_a == rj.body_b)
    sum += through(ri.body_a, -1, pi.angular_a[ri.axis], 1, pj.response_b[rj.axis]);
  if (ri.body_b != 0 && ri.body_b == rj.body_a)
    sum += through(ri.body_b, 1, pi.angular_b[ri.axis], -1, pj.response_a[rj.axis]);
  if (ri.body_b != 0 && ri.body_b == rj.body_b)
    sum += through(ri.body_b, 1, pi.angular_b[ri.axis], 1, pj.response_b[rj.axis]);
  return sum;
}

DirectContactSolver* DirectContactSolver::Create(BlockArena& arena, std::span<SolverContact* const> contacts,
                                                 const SolverBody* bodies, float weight_per_impulse) {
  std::uint32_t points = 0;
  for (const SolverContact* c : contacts) points += c->point_count;
  if (points == 0 || points > kMaxPoints) return nullptr;
  auto* solver =
      new (arena.Allocate(sizeof(DirectContactSolver), alignof(DirectContactSolver))) DirectContactSolver;
  solver->contacts_ = contacts;
  const std::uint32_t count = 3 * points;
  solver->count_ = count;
  const auto contact_count = static_cast<std::uint32_t>(contacts.size());
  auto* adjacent = arena.AllocateArray<std::uint8_t>(static_cast<std::size_t>(contact_count) * contact_count);
  for (std::uint32_t i = 0; i < contact_count; ++i)
    for (std::uint32_t j = 0; j <= i; ++j)
      adjacent[i * contact_count + j] = adjacent[j * contact_count + i] =
          i == j || ShareBody(*contacts[i], *contacts[j]);
  auto* order = arena.AllocateArray<std::uint32_t>(contact_count);
  auto* degree = arena.AllocateArray<std::uint32_t>(contact_count);
  auto* placed = arena.AllocateArray<std::uint8_t>(contact_count);
  BandedOrder(contact_count, adjacent, order, degree, placed);
  // Rows contact by contact in the banded order; contact k's rows are [row_begin[k], row_begin[k + 1]).
  auto* row_begin = arena.AllocateArray<std::uint32_t>(contact_count + 1);
  solver->rows_ = arena.AllocateArray<Row>(count);
  std::uint32_t row = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    SolverContact* c = contacts[order[k]];
    const ContactConstraint& constraint = *c->constraint;
    const float load = LoadScale(*c, bodies, weight_per_impulse);
    row_begin[k] = row;
    for (int p = 0; p < c->point_count; ++p)
      for (std::uint8_t axis = 0; axis < 3; ++axis)
        solver->rows_[row++] = {c,
                                &c->points()[p],
                                constraint.dynamic_a ? constraint.body_a : 0u,
                                constraint.dynamic_b ? constraint.body_b : 0u,
                                axis,
                                load};
  }
  row_begin[contact_count] = row;
  // Each row's neighbours: every row of every contact that shares a body with its contact (itself too), in
  // row order.
  solver->neighbour_begin_ = arena.AllocateArray<std::uint32_t>(count + 1);
  std::uint32_t neighbour_count = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k)
    for (std::uint32_t l = 0; l < contact_count; ++l)
      if (adjacent[order[k] * contact_count + order[l]])
        neighbour_count += (row_begin[k + 1] - row_begin[k]) * (row_begin[l + 1] - row_begin[l]);
  solver->neighbours_ = arena.AllocateArray<std::uint32_t>(neighbour_count);
  solver->coupling_ = arena.AllocateArray<float>(neighbour_count);
  // Where contact l's rows start in the neighbour list of a row of contact k (when they share a body).
  auto* block_offset =
      arena.AllocateArray<std::uint32_t>(static_cast<std::size_t>(contact_count) * contact_count);
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    std::uint32_t offset = 0;
    for (std::uint32_t l = 0; l < contact_count; ++l) {
      block_offset[k * contact_count + l] = offset;
      if (adjacent[order[k] * contact_count + order[l]]) offset += row_begin[l + 1] - row_begin[l];
    }
  }
  neighbour_count = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k)
    for (std::uint32_t i = row_begin[k]; i < row_begin[k + 1]; ++i) {
      solver->neighbour_begin_[i] = neighbour_count;
      for (std::uint32_t l = 0; l < contact_count; ++l) {
        if (!adjacent[order[k] * contact_count + order[l]]) continue;
        for (std::uint32_t j = row_begin[l]; j < row_begin[l + 1]; ++j)
          solver->neighbours_[neighbour_count++] = j;
      }
    }
  solver->neighbour_begin_[count] = neighbour_count;
  // The coupling is symmetric: each block of two contacts is computed once and stored on both sides.
  for (std::uint32_t k = 0; k < contact_count; ++k)
    for (std::uint32_t l = 0; l <= k; ++l) {
      if (!adjacent[order[k] * contact_count + order[l]]) continue;
      for (std::uint32_t i = row_begin[k]; i < row_begin[k + 1]; ++i)
        for (std::uint32_t j = row_begin[l]; j < row_begin[l + 1] && (l < k || j <= i); ++j) {
          const float value = RowCoupling(solver->rows_[i], solver->rows_[j], bodies);
          solver->coupling_[solver->neighbour_begin_[i] + block_offset[k * contact_count + l] +
                            (j - row_begin[l])] = value;
          solver->coupling_[solver->neighbour_begin_[j] + block_offset[l * contact_count + k] +
                            (i - row_begin[k])] = value;
        }
    }
  solver->diagonal_ = arena.AllocateArray<float>(count);
  for (std::uint32_t i = 0; i < count; ++i)
    for (std::uint32_t k = solver->neighbour_begin_[i]; k < solver->neighbour_begin_[i + 1]; ++k)
      if (solver->neighbours_[k] == i) solver->diagonal_[i] = solver->coupling_[k];
  for (Factor& factor : solver->factors_) solver->AllocateFactor(arena, factor);
  solver->offset_ = arena.AllocateArray<double>(count);
  solver->right_ = arena.AllocateArray<double>(count);
  solver->impulse_ = arena.AllocateArray<double>(count);
  solver->bound_ = arena.AllocateArray<double>(count);
  solver->lower_ = arena.AllocateArray<double>(count);
  solver->upper_ = arena.AllocateArray<double>(count);
  solver->target_ = arena.AllocateArray<double>(count);
  solver->scratch_ = arena.AllocateArray<double>(count);
  solver->dense_row_ = arena.AllocateArray<double>(count);
  std::fill(solver->dense_row_, solver->dense_row_ + count, 0.0);
  solver->softness_ = arena.AllocateArray<float>(count);
  solver->free_ = arena.AllocateArray<std::uint8_t>(count);
  solver->packed_of_ = arena.AllocateArray<std::uint32_t>(count);
  return solver;
}

void DirectContactSolver::AllocateFactor(BlockArena& arena, Factor& factor) const {
  // The envelope of any subset of rows is no wider than that of all rows: row i reaches back to its first
  // neighbour.
  std::size_t capacity = 0;
  for (std::uint32_t i = 0; i < count_; ++i) capacity += i - neighbours_[neighbour_begin_[i]] + 1;
  factor.lower = arena.AllocateArray<double>(capacity);
  factor.start = arena.AllocateArray<std::uint32_t>(count_ + 1);
  factor.rows = arena.AllocateArray<std::uint32_t>(count_);
  factor.first = arena.AllocateArray<std::uint32_t>(count_);
  factor.free = arena.AllocateArray<std::uint8_t>(count_);
  factor.softness = arena.AllocateArray<float>(count_);
  factor.valid = false;
}

bool DirectContactSolver::Refactor(Factor& factor) {
  const std::uint32_t n = count_;
  if (factor.valid && std::equal(free_, free_ + n, factor.free) &&
      std::equal(softness_, softness_ + n, factor.softness))
    return true;
  std::copy(free_, free_ + n, factor.free);
  std::copy(softness_, softness_ + n, factor.softness);
  std::uint32_t m = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    if (free_[i]) packed_of_[i] = m, factor.rows[m++] = i;
  factor.size = m;
  // Skyline (envelope) Cholesky: packed row r of the factor is zero left of the first free neighbour of its
  // row, so a banded matrix costs rows x band^2.
  factor.start[0] = 0;
  for (std::uint32_t r = 0; r < m; ++r) {
    const std::uint32_t i = factor.rows[r];
    std::uint32_t first = r;
    for (std::uint32_t k = neighbour_begin_[i]; k < neighbour_begin_[i + 1]; ++k)
      if (free_[neighbours_[k]]) {
        first = std::min(first, packed_of_[neighbours_[k]]);
        break;  // neighbours are in row order
      }
    factor.first[r] = first;
    factor.start[r + 1] = factor.start[r] + (r - first + 1);
  }
  // Row r of the factor as an array indexed by packed column (valid from first[r] to r), so the inner loop
  // is a plain dot product over contiguous memory.
  auto row_of = [&](std::uint32_t r) { return factor.lower + factor.start[r] - factor.first[r]; };
  bool positive = true;
  for (std::uint32_t r = 0; r < m && positive; ++r) {
    const std::uint32_t i = factor.rows[r];
    for (std::uint32_t k = neighbour_begin_[i]; k < neighbour_begin_[i + 1]; ++k)
      dense_row_[neighbours_[k]] = coupling_[k];
    double* const row = row_of(r);
    const std::uint32_t row_first = factor.first[r];
    for (std::uint32_t c = row_first; c < r; ++c) {
      const double* const column = row_of(c);
      double sum = dense_row_[factor.rows[c]];
      for (std::uint32_t k = std::max(row_first, factor.first[c]); k < c; ++k) sum -= row[k] * column[k];
      row[c] = sum / column[c];
    }
    double diagonal = dense_row_[i] + softness_[i];
    for (std::uint32_t k = row_first; k < r; ++k) diagonal -= row[k] * row[k];
    if (diagonal > 0.0)
      row[r] = std::sqrt(diagonal);
    else
      positive = false;  // never seen: the softness keeps the matrix positive definite
    for (std::uint32_t k = neighbour_begin_[i]; k < neighbour_begin_[i + 1]; ++k)
      dense_row_[neighbours_[k]] = 0.0;
  }
  return factor.valid = positive;
}

void DirectContactSolver::SolveWith(const Factor& factor, const double* right, double* out) const {
  const std::uint32_t m = factor.size;
  auto row_of = [&](std::uint32_t r) { return factor.lower + factor.start[r] - factor.first[r]; };
  double* packed = scratch_;
  for (std::uint32_t r = 0; r < m; ++r) {
    const double* const row = row_of(r);
    double sum = right[factor.rows[r]];
    for (std::uint32_t k = factor.first[r]; k < r; ++k) sum -= row[k] * packed[k];
    packed[r] = sum / row[r];
  }
  for (std::uint32_t r = m; r-- > 0;) {
    const double* const row = row_of(r);
    packed[r] /= row[r];
    const double value = packed[r];
    for (std::uint32_t k = factor.first[r]; k < r; ++k) packed[k] -= row[k] * value;
  }
  for (std::uint32_t r = 0; r < m; ++r) out[factor.rows[r]] = packed[r];
}

double DirectContactSolver::Residual(std::uint32_t row, const double* impulse) const {
  double sum = offset_[row] + softness_[row] * impulse[row];
  for (std::uint32_t k = neighbour_begin_[row]; k < neighbour_begin_[row + 1]; ++k)
    sum += coupling_[k] * impulse[neighbours_[k]];
  return sum;
}

bool DirectContactSolver::FreeRowsStep(Factor& factor) {
  const std::uint32_t n = count_;
  // Where the free rows would go with the others held: the equality-constrained minimum.
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!free_[i]) continue;
    double sum = -offset_[i];
    for (std::uint32_t k = neighbour_begin_[i]; k < neighbour_begin_[i + 1]; ++k)
      if (!free_[neighbours_[k]]) sum -= coupling_[k] * impulse_[neighbours_[k]];
    right_[i] = sum;
  }
  if (!Refactor(factor)) return false;
  SolveWith(factor, right_, target_);
  // Go there as far as the limits allow; the first row to reach a limit is held at it.
  double step = 1.0;
  std::uint32_t blocking = n;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!free_[i]) continue;
    const double change = target_[i] - impulse_[i];
    if (target_[i] < lower_[i] && change < 0.0 && (lower_[i] - impulse_[i]) / change < step)
      step = (lower_[i] - impulse_[i]) / change, blocking = i;
    if (target_[i] > upper_[i] && change > 0.0 && (upper_[i] - impulse_[i]) / change < step)
      step = (upper_[i] - impulse_[i]) / change, blocking = i;
  }
  for (std::uint32_t i = 0; i < n; ++i)
    if (free_[i])
      impulse_[i] = std::clamp(impulse_[i] + step * (target_[i] - impulse_[i]), lower_[i], upper_[i]);
  if (blocking < n) {
    free_[blocking] = 0;
    impulse_[blocking] = target_[blocking] < lower_[blocking] ? lower_[blocking] : upper_[blocking];
    return true;
  }
  // At the minimum for this set: free every held row whose residual pulls it off its limit.
  bool freed = false;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (free_[i] || lower_[i] == upper_[i]) continue;
    const double residual = Residual(i, impulse_);
    const bool at_lower = impulse_[i] <= lower_[i];
    if ((at_lower && residual < -kResidualTolerance) || (!at_lower && residual > kResidualTolerance))
      free_[i] = 1, freed = true;
  }
  return freed;
}

void DirectContactSolver::Solve(SolverBody* bodies, const SubstepContext& context, bool use_bias,
                                float* deepest) {
  const std::uint32_t n = count_;
  float lowest = kLargeFloat;
  // Each free row aims for residual = velocity + bias + softness * impulse = 0: the fixed point of the
  // sequential soft update, with a normal row's spring scaled by its load.
  for (std::uint32_t i = 0; i < n; ++i) {
    const Row& r = rows_[i];
    const SolverContact& c = *r.contact;
    SolverContactPoint& p = *r.point;
    const float stiffness = diagonal_[i];
    float softness = kRigidSoftness * stiffness;
    float bias = 0.0f;
    if (r.axis == kNormal) {
      const float separation = SeparationNow(p, MotionSinceStepBegan(c, bodies, context.elapsed));
      lowest = std::min(lowest, separation);
      // The softness depends only on the pass, so one factorisation serves every pass of its kind while the
      // same rows are free (a gap that may close is as soft as an overlap).
      if (use_bias && c.softness.mass_scale > 0.0f)
        softness =
            std::max(softness, c.softness.impulse_scale * stiffness / (c.softness.mass_scale * r.load));
      if (separation > 0.0f)
        bias = separation * context.inverse_h;
      else if (use_bias)
        bias = std::max(c.softness.bias_rate * separation, -context.max_push_velocity);
    }
    const SolverBody& a = bodies[c.constraint->body_a];
    const SolverBody& b = bodies[c.constraint->body_b];
    const float velocity = (Direction(c, r.axis).cwiseProduct(b.linear_velocity - a.linear_velocity) +
                            p.angular_b[r.axis].cwiseProduct(b.angular_velocity) -
                            p.angular_a[r.axis].cwiseProduct(a.angular_velocity))
                               .sum();
    softness_[i] = softness;
    impulse_[i] = Accumulated(p, r.axis);
    // Friction is bounded by the normal impulse the pass starts from: with bounds that moved with the
    // solution, opposed friction at the limits and the normal impulses feeding them could grow together.
    bound_[i] = r.axis == kNormal ? 0.0 : r.contact->friction * std::max(p.normal_impulse, 0.0f);
    offset_[i] = static_cast<double>(velocity) + bias;
  }
  // q = velocity + bias - coupling * impulse0, so that residual = (coupling + softness) impulse + q.
  for (std::uint32_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (std::uint32_t k = neighbour_begin_[i]; k < neighbour_begin_[i + 1]; ++k)
      sum += coupling_[k] * impulse_[neighbours_[k]];
    scratch_[i] = sum;
  }
  for (std::uint32_t i = 0; i < n; ++i) offset_[i] -= scratch_[i];
  // A primal active-set method on the convex problem min 1/2 x'(coupling + softness)x + q'x within the rows'
  // limits: every iterate stays within the limits (a round that cannot finish leaves a usable answer) and
  // the objective falls each round, so it cannot cycle. Rows strictly inside their limits are free. The
  // friction limits follow the normal impulses: solved with the pass's starting ones, then again with the
  // new ones while they still move (as the sequential solver bounds friction by the normal impulse just
  // solved).
  Factor& factor = factors_[use_bias ? 1 : 0];
  bool converged = true;
  for (int limits = 0; limits < kMaxFrictionLimitUpdates; ++limits) {
    for (std::uint32_t i = 0; i < n; ++i) {
      lower_[i] = rows_[i].axis == kNormal ? 0.0 : -bound_[i];
      upper_[i] = rows_[i].axis == kNormal ? kUnbounded : bound_[i];
      impulse_[i] = std::clamp(impulse_[i], lower_[i], upper_[i]);
      free_[i] = impulse_[i] > lower_[i] && impulse_[i] < upper_[i];
    }
    int round = 0;
    while (round < kMaxActiveSetRounds && FreeRowsStep(factor)) ++round;
    converged = round < kMaxActiveSetRounds;
    // Only a row held at its limit, or one the new limit would cut, needs another solve.
    bool moved = false;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (rows_[i].axis == kNormal) continue;
      const double bound = rows_[i].contact->friction * impulse_[i - rows_[i].axis];
      moved |= (!free_[i] && std::abs(bound - bound_[i]) > kFrictionLimitTolerance * (bound + bound_[i])) ||
               std::abs(impulse_[i]) > bound;
      bound_[i] = bound;
    }
    if (!moved) break;
  }
  for (std::uint32_t i = 0; i < n; i += 3) {
    const Row& r = rows_[i];
    SolverContactPoint& p = *r.point;
    const double normal = impulse_[i];
    double first = impulse_[i + 1];
    double second = impulse_[i + 2];
    // The active set holds friction inside a box; the sequential solver's limit is the circle.
    const double limit = r.contact->friction * normal;
    const double length = std::sqrt(first * first + second * second);
    if (length > limit) {
      const double scale = length > 0.0 ? limit / length : 0.0;
      first *= scale;
      second *= scale;
    }
    const double values[3] = {normal, first, second};
    for (int axis = 0; axis < 3; ++axis) {
      const float value = static_cast<float>(values[axis]);
      const float delta = value - Accumulated(p, axis);
      Accumulated(p, axis) = value;
      if (axis == kNormal) p.max_normal_impulse = std::max(p.max_normal_impulse, delta);
      const Vec4& direction = Direction(*r.contact, axis);
      if (r.body_a != 0) {
        SolverBody& a = bodies[r.body_a];
        a.linear_velocity -= (a.inverse_mass * delta) * direction;
        a.angular_velocity -= delta * p.response_a[axis];
      }
      if (r.body_b != 0) {
        SolverBody& b = bodies[r.body_b];
        b.linear_velocity += (b.inverse_mass * delta) * direction;
        b.angular_velocity += delta * p.response_b[axis];
      }
    }
  }
  // An unfinished active set (a pile landing at once) leaves no row worse than a sequential pass would.
  if (!converged)
    for (SolverContact* c : contacts_) SolveContactVelocity(*c, bodies, context, use_bias, false, nullptr);
  if (deepest != nullptr) *deepest = std::min(*deepest, lowest);
}

}  // namespace strata
