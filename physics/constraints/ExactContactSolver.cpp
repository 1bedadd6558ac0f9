// Over 600 lines on purpose: the rows, the friction patches and the active-set solve of one island are one
// algorithm over one RowSet layout; split, each part would need all of it.
#include "physics/constraints/ExactContactSolver.h"

#include "physics/constraints/ContactOrdering.h"

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
// A row held at a limit may pull away from it this fast (m/s) before it is freed.
constexpr double kResidualTolerance = 1e-6;

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

constexpr int kTwist = 3;
// Patches whose points are closer together than this (summed squared offsets, m^2) get no twist row: one
// point, or points at one place, cannot resist a turn about the normal.
constexpr float kMinSpread = 1e-8f;
const Vec4 kNoDirection = Vec4::Zero();

// The patch's bound on friction axis `axis` (1, 2) or on the twist: friction times the points' normal
// impulses, for the twist each times the point's distance from the centre.
float PatchBound(const SolverContact& c, const float* lever, int axis) {
  float bound = 0.0f;
  for (int k = 0; k < c.point_count; ++k) {
    const float pushed = std::max(c.points()[k].normal_impulse, 0.0f);
    bound += axis == kTwist ? pushed * lever[k] : pushed;
  }
  return c.friction * bound;
}

}  // namespace

int ExactContactSolver::SharedBodies(const Row& ri, const Row& rj, const SolverBody* bodies,
                                     SharedBody shared[2]) {
  int count = 0;
  const std::uint32_t sides_i[2] = {ri.body_a, ri.body_b}, sides_j[2] = {rj.body_a, rj.body_b};
  for (std::uint8_t side_i = 0; side_i < 2; ++side_i)
    for (std::uint8_t side_j = 0; side_j < 2; ++side_j)
      if (sides_i[side_i] != 0 && sides_i[side_i] == sides_j[side_j])
        shared[count++] = {bodies[sides_i[side_i]].inverse_mass, side_i == side_j ? 1.0f : -1.0f, side_i,
                           side_j};
  return count;
}

struct ExactContactSolver::Layout {
  std::span<SolverContact* const> contacts;
  Patch* patches;              // by contact
  const std::uint32_t* order;  // contacts in banded order
  // Banded position k's links (itself and the contacts that share a body the solver moves with it), as
  // banded positions in increasing order: linked[linked_begin[k] .. linked_begin[k + 1]).
  const std::uint32_t* linked_begin;
  const std::uint32_t* linked;
  float weight_per_impulse;
};

ExactContactSolver* ExactContactSolver::Create(BlockArena& arena, std::span<SolverContact* const> contacts,
                                               const SolverBody* bodies, float weight_per_impulse) {
  std::uint32_t points = 0;
  for (const SolverContact* c : contacts) points += c->point_count;
  if (points == 0 || points > kMaxPoints) return nullptr;
  auto* solver =
      new (arena.Allocate(sizeof(ExactContactSolver), alignof(ExactContactSolver))) ExactContactSolver;
  solver->contacts_ = contacts;
  const auto contact_count = static_cast<std::uint32_t>(contacts.size());
  std::uint32_t* links_begin = nullptr;
  std::uint32_t* links = nullptr;
  LinkContacts(arena, contacts, links_begin, links);
  auto* order = arena.AllocateArray<std::uint32_t>(contact_count);
  auto* degree = arena.AllocateArray<std::uint32_t>(contact_count);
  auto* placed = arena.AllocateArray<std::uint8_t>(contact_count);
  BandedOrder(contact_count, links_begin, links, order, degree, placed);
  auto* position = degree;  // reused: banded position of each contact
  for (std::uint32_t k = 0; k < contact_count; ++k) position[order[k]] = k;
  // The links again, by banded position.
  auto* linked_begin = arena.AllocateArray<std::uint32_t>(contact_count + 1);
  auto* linked = arena.AllocateArray<std::uint32_t>(links_begin[contact_count]);
  std::uint32_t link_count = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    linked_begin[k] = link_count;
    for (std::uint32_t e = links_begin[order[k]]; e < links_begin[order[k] + 1]; ++e)
      linked[link_count++] = position[links[e]];
    std::sort(linked + linked_begin[k], linked + link_count);
  }
  linked_begin[contact_count] = link_count;
  solver->patches_ = arena.AllocateArray<Patch>(contact_count);
  for (std::uint32_t k = 0; k < contact_count; ++k) MakePatch(*contacts[k], bodies, solver->patches_[k]);
  const Layout layout{contacts, solver->patches_, order, linked_begin, linked, weight_per_impulse};
  BuildRowSet(arena, layout, bodies, false, solver->normals_);
  BuildRowSet(arena, layout, bodies, true, solver->friction_);
  // Scratch for the longer set.
  const std::uint32_t count = std::max(solver->normals_.count, solver->friction_.count);
  solver->offset_ = arena.AllocateArray<double>(count);
  solver->right_ = arena.AllocateArray<double>(count);
  solver->impulse_ = arena.AllocateArray<double>(count);
  solver->start_ = arena.AllocateArray<double>(count);
  solver->lower_ = arena.AllocateArray<double>(count);
  solver->upper_ = arena.AllocateArray<double>(count);
  solver->target_ = arena.AllocateArray<double>(count);
  solver->scratch_ = arena.AllocateArray<double>(count);
  solver->softness_ = arena.AllocateArray<float>(count);
  solver->free_ = arena.AllocateArray<std::uint8_t>(count);
  solver->packed_of_ = arena.AllocateArray<std::uint32_t>(count);
  return solver;
}

void ExactContactSolver::MakePatch(const SolverContact& c, const SolverBody* bodies, Patch& patch) {
  const ContactConstraint& constraint = *c.constraint;
  const ContactConstraintPoint* points = constraint.points();
  const int count = c.point_count;
  const float share = 1.0f / static_cast<float>(count);
  Vec3 centre_a = Vec3::Zero(), centre = Vec3::Zero();  // the points' centre, from A's and from B's centre
  for (int k = 0; k < count; ++k) {
    centre_a += points[k].r_a;
    centre += points[k].r_b;
  }
  centre_a *= share;
  centre *= share;
  const SolverBody& a = bodies[constraint.body_a];
  const SolverBody& b = bodies[constraint.body_b];
  for (int axis = 0; axis < 2; ++axis) {
    patch.angular_a[axis] = Cross(ToVec4(centre_a), c.tangent[axis]);
    patch.angular_b[axis] = Cross(ToVec4(centre), c.tangent[axis]);
    patch.response_a[axis] =
        constraint.dynamic_a ? a.InverseInertiaTimes(patch.angular_a[axis]) : Vec4::Zero();
    patch.response_b[axis] =
        constraint.dynamic_b ? b.InverseInertiaTimes(patch.angular_b[axis]) : Vec4::Zero();
  }
  patch.angular_a[2] = patch.angular_b[2] = c.normal;
  patch.response_a[2] = a.InverseInertiaTimes(c.normal);
  patch.response_b[2] = b.InverseInertiaTimes(c.normal);
  const Vec3 normal = ToVec3(c.normal);
  patch.spread = 0.0f;
  for (int k = 0; k < count; ++k) {
    Vec3 offset = points[k].r_b - centre;
    offset -= offset.dot(normal) * normal;
    patch.turn[k] = ToVec4(normal.cross(offset));
    patch.lever[k] = patch.turn[k].norm();
    patch.spread += offset.squaredNorm();
  }
}

void ExactContactSolver::WarmStart(SolverBody* bodies) {
  for (std::size_t k = 0; k < contacts_.size(); ++k) {
    const SolverContact& c = *contacts_[k];
    Patch& patch = patches_[k];
    GatherPatch(c, patch);
    const float* friction = patch.accumulated;
    float pushed = 0.0f;
    Vec4 turn_a = friction[0] * patch.response_a[0] + friction[1] * patch.response_a[1] +
                  friction[2] * patch.response_a[2];
    Vec4 turn_b = friction[0] * patch.response_b[0] + friction[1] * patch.response_b[1] +
                  friction[2] * patch.response_b[2];
    for (int i = 0; i < c.point_count; ++i) {
      const SolverContactPoint& p = c.points()[i];
      pushed += p.normal_impulse;
      turn_a += p.normal_impulse * p.response_a[kNormal];
      turn_b += p.normal_impulse * p.response_b[kNormal];
    }
    const Vec4 impulse = pushed * c.normal + friction[0] * c.tangent[0] + friction[1] * c.tangent[1];
    const ContactConstraint& constraint = *c.constraint;
    if (constraint.dynamic_a) {
      SolverBody& a = bodies[constraint.body_a];
      a.linear_velocity -= a.inverse_mass * impulse;
      a.angular_velocity -= turn_a;
    }
    if (constraint.dynamic_b) {
      SolverBody& b = bodies[constraint.body_b];
      b.linear_velocity += b.inverse_mass * impulse;
      b.angular_velocity += turn_b;
    }
  }
}

void ExactContactSolver::GatherPatch(const SolverContact& c, Patch& patch) {
  // The points' friction impulses as the patch's: their sum along each axis, and their turn about the centre.
  patch.accumulated[0] = patch.accumulated[1] = patch.accumulated[2] = 0.0f;
  for (int k = 0; k < c.point_count; ++k) {
    const SolverContactPoint& p = c.points()[k];
    patch.accumulated[0] += p.tangent_impulse[0];
    patch.accumulated[1] += p.tangent_impulse[1];
    patch.accumulated[2] += p.tangent_impulse[0] * patch.turn[k].dot(c.tangent[0]) +
                            p.tangent_impulse[1] * patch.turn[k].dot(c.tangent[1]);
  }
}

void ExactContactSolver::SpreadPatch(SolverContact& c, const Patch& patch, int axis, float delta) {
  // A change of the patch's impulse shared out over its points so that their sum and their turn about the
  // centre change by as much (the smallest such change of each point): the points keep the impulses that
  // warm start the next step and any sequential pass.
  SolverContactPoint* points = c.points();
  if (axis != kTwist) {
    const float share = delta / static_cast<float>(c.point_count);
    for (int k = 0; k < c.point_count; ++k) points[k].tangent_impulse[axis - 1] += share;
    return;
  }
  const float per_spread = delta / patch.spread;
  for (int k = 0; k < c.point_count; ++k)
    for (int t = 0; t < 2; ++t) points[k].tangent_impulse[t] += per_spread * patch.turn[k].dot(c.tangent[t]);
}

float& ExactContactSolver::Accumulated(const Row& row) {
  return row.axis == kNormal ? row.point->normal_impulse : row.patch->accumulated[row.axis - 1];
}

void ExactContactSolver::BuildRowSet(BlockArena& arena, const Layout& layout, const SolverBody* bodies,
                                     bool friction, RowSet& set) {
  const auto contact_count = static_cast<std::uint32_t>(layout.contacts.size());
  std::uint32_t* const row_begin = LayOutRows(arena, layout, bodies, friction, set);
  LinkRows(arena, layout, row_begin, set);
  // Each row's own entry now (every pass reads it); the rest of the coupling when a pass first solves the set
  // (a resting contact's friction, right after its warm start, needs none: see AtMinimum).
  set.contact_count = contact_count;
  set.row_begin = row_begin;
  set.linked_begin = layout.linked_begin;
  set.linked = layout.linked;
  set.coupled = false;
  set.diagonal = arena.AllocateArray<float>(set.count);
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    // A row shares with itself each side the solver moves, A's first (as SharedBodies lists them).
    const Row& first = set.rows[row_begin[k]];
    SharedBody shared[2];
    int shared_count = 0;
    if (first.body_a != 0) shared[shared_count++] = {bodies[first.body_a].inverse_mass, 1.0f, 0, 0};
    if (first.body_b != 0) shared[shared_count++] = {bodies[first.body_b].inverse_mass, 1.0f, 1, 1};
    for (std::uint32_t i = row_begin[k]; i < row_begin[k + 1]; ++i)
      set.diagonal[i] =
          Coupling(set.rows[i], *set.rows[i].direction, set.rows[i].response, shared, shared_count);
  }
  // Friction rows are solved in velocity passes only (see Solve): one factor.
  AllocateFactor(arena, set, set.factors[0]);
  if (!friction) AllocateFactor(arena, set, set.factors[1]);
}

std::uint32_t* ExactContactSolver::LayOutRows(BlockArena& arena, const Layout& layout,
                                              const SolverBody* bodies, bool friction, RowSet& set) {
  const auto contact_count = static_cast<std::uint32_t>(layout.contacts.size());
  const std::uint32_t* order = layout.order;
  // Normals: one row per point. Friction: the patch's two axes, and its twist if its points are apart.
  auto rows_for = [&](std::uint32_t contact) -> std::uint32_t {
    if (!friction) return layout.contacts[contact]->point_count;
    return layout.patches[contact].spread > kMinSpread ? 3 : 2;
  };
  // Rows contact by contact in the banded order; contact k's rows are [row_begin[k], row_begin[k + 1]).
  auto* row_begin = arena.AllocateArray<std::uint32_t>(contact_count + 1);
  std::uint32_t count = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k) count += rows_for(k);
  set.count = count;
  set.rows = arena.AllocateArray<Row>(count);
  std::uint32_t row = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    SolverContact* c = layout.contacts[order[k]];
    Patch* patch = &layout.patches[order[k]];
    const ContactConstraint& constraint = *c->constraint;
    const float load = LoadScale(*c, bodies, layout.weight_per_impulse);
    const std::uint32_t body_a = constraint.dynamic_a ? constraint.body_a : 0u;
    const std::uint32_t body_b = constraint.dynamic_b ? constraint.body_b : 0u;
    row_begin[k] = row;
    if (!friction) {
      for (int point = 0; point < c->point_count; ++point) {
        SolverContactPoint* p = &c->points()[point];
        set.rows[row++] = {c,
                           p,
                           nullptr,
                           &c->normal,
                           {&p->angular_a[0], &p->angular_b[0]},
                           {&p->response_a[0], &p->response_b[0]},
                           body_a,
                           body_b,
                           kNormal,
                           load};
      }
      continue;
    }
    const std::uint32_t axes = rows_for(order[k]);
    for (std::uint8_t axis = 1; axis <= axes; ++axis)
      set.rows[row++] = {c,
                         nullptr,
                         patch,
                         axis == kTwist ? &kNoDirection : &c->tangent[axis - 1],
                         {&patch->angular_a[axis - 1], &patch->angular_b[axis - 1]},
                         {&patch->response_a[axis - 1], &patch->response_b[axis - 1]},
                         body_a,
                         body_b,
                         axis,
                         load};
  }
  row_begin[contact_count] = row;
  return row_begin;
}

void ExactContactSolver::LinkRows(BlockArena& arena, const Layout& layout, const std::uint32_t* row_begin,
                                  RowSet& set) {
  const auto contact_count = static_cast<std::uint32_t>(layout.contacts.size());
  const std::uint32_t count = set.count;
  // Each row's neighbours: every row of every contact linked to its contact (itself too), in row order.
  // Where contact k's e-th link's rows start in the neighbour list of a row of k: link_offset[e].
  const std::uint32_t* linked_begin = layout.linked_begin;
  const std::uint32_t* linked = layout.linked;
  auto* link_offset = arena.AllocateArray<std::uint32_t>(linked_begin[contact_count]);
  auto rows_of = [&](std::uint32_t k) { return row_begin[k + 1] - row_begin[k]; };
  std::uint32_t neighbour_count = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    std::uint32_t offset = 0;
    for (std::uint32_t e = linked_begin[k]; e < linked_begin[k + 1]; ++e) {
      link_offset[e] = offset;
      offset += rows_of(linked[e]);
    }
    neighbour_count += rows_of(k) * offset;
  }
  set.neighbour_begin = arena.AllocateArray<std::uint32_t>(count + 1);
  set.neighbours = arena.AllocateArray<std::uint32_t>(neighbour_count);
  set.coupling = arena.AllocateArray<float>(neighbour_count);
  // Every row of a contact has the same neighbours: the first row's list is written, the others copy it.
  neighbour_count = 0;
  for (std::uint32_t k = 0; k < contact_count; ++k) {
    const std::uint32_t first = neighbour_count;
    for (std::uint32_t e = linked_begin[k]; e < linked_begin[k + 1]; ++e) {
      const std::uint32_t begin = row_begin[linked[e]], end = row_begin[linked[e] + 1];
      for (std::uint32_t j = begin; j < end; ++j) set.neighbours[neighbour_count++] = j;
    }
    const std::uint32_t length = neighbour_count - first;
    set.neighbour_begin[row_begin[k]] = first;
    for (std::uint32_t i = row_begin[k] + 1; i < row_begin[k + 1]; ++i) {
      set.neighbour_begin[i] = neighbour_count;
      std::copy_n(set.neighbours + first, length, set.neighbours + neighbour_count);
      neighbour_count += length;
    }
  }
  set.neighbour_begin[count] = neighbour_count;
  set.link_offset = link_offset;
}

float ExactContactSolver::Coupling(const Row& i, const Vec4& direction_j, const Vec4* const response_j[2],
                                   const SharedBody shared[2], int shared_count) {
  // Through each body both rows move: the side signs times the body's response.
  const float directions = i.direction->dot(direction_j);
  float value = 0.0f;
  for (int b = 0; b < shared_count; ++b)
    value += shared[b].sign * (shared[b].inverse_mass * directions +
                               i.angular[shared[b].side_i]->dot(*response_j[shared[b].side_j]));
  return value;
}

void ExactContactSolver::Couple(RowSet& set, const SolverBody* bodies) {
  if (set.coupled) return;
  set.coupled = true;
  const std::uint32_t* row_begin = set.row_begin;
  const std::uint32_t* link_offset = set.link_offset;
  const std::uint32_t* linked_begin = set.linked_begin;
  const std::uint32_t* linked = set.linked;
  // The coupling is symmetric: each block of two contacts is computed once (l <= k) and stored on both
  // sides (k's entry in l's links found by a short search).
  for (std::uint32_t k = 0; k < set.contact_count; ++k)
    for (std::uint32_t e = linked_begin[k]; e < linked_begin[k + 1] && linked[e] <= k; ++e) {
      const std::uint32_t l = linked[e];
      std::uint32_t back = linked_begin[l];
      while (linked[back] != k) ++back;
      // Every row of a contact has the same bodies: which ones the two contacts share is found once.
      SharedBody shared[2];
      const int shared_count = SharedBodies(set.rows[row_begin[k]], set.rows[row_begin[l]], bodies, shared);
      for (std::uint32_t i = row_begin[k]; i < row_begin[k + 1]; ++i) {
        const Row& ri = set.rows[i];
        float* const row_i = set.coupling + set.neighbour_begin[i] + link_offset[e];
        const std::uint32_t end = (l < k ? row_begin[l + 1] : i + 1) - row_begin[l];
        for (std::uint32_t j = 0; j < end; ++j) {
          const Row& rj = set.rows[row_begin[l] + j];
          const float value = Coupling(ri, *rj.direction, rj.response, shared, shared_count);
          row_i[j] = value;
          set.coupling[set.neighbour_begin[row_begin[l] + j] + link_offset[back] + (i - row_begin[k])] =
              value;
        }
      }
    }
}

void ExactContactSolver::AllocateFactor(BlockArena& arena, const RowSet& set, Factor& factor) {
  // The envelope of any subset of rows is no wider than that of all rows: row i reaches back to its first
  // neighbour.
  std::uint32_t capacity = 0;
  for (std::uint32_t i = 0; i < set.count; ++i) capacity += i - set.neighbours[set.neighbour_begin[i]] + 1;
  factor.ldlt.Allocate(arena, set.count, capacity);
  factor.rows = arena.AllocateArray<std::uint32_t>(set.count);
  factor.free = arena.AllocateArray<std::uint8_t>(set.count);
  factor.softness = arena.AllocateArray<float>(set.count);
  factor.valid = false;
}

bool ExactContactSolver::Refactor(const RowSet& set, Factor& factor) {
  const std::uint32_t n = set.count;
  if (factor.valid && std::equal(free_, free_ + n, factor.free) &&
      std::equal(softness_, softness_ + n, factor.softness))
    return true;
  std::copy(free_, free_ + n, factor.free);
  std::copy(softness_, softness_ + n, factor.softness);
  std::uint32_t m = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    if (free_[i]) packed_of_[i] = m, factor.rows[m++] = i;
  factor.ldlt.Clear();
  for (std::uint32_t r = 0; r < m; ++r) {
    const std::uint32_t i = factor.rows[r];
    const std::uint32_t* const neighbours = set.neighbours + set.neighbour_begin[i];
    const std::uint32_t neighbour_count = set.neighbour_begin[i + 1] - set.neighbour_begin[i];
    const float* const coupling = set.coupling + set.neighbour_begin[i];
    // Neighbours are in row order and the row is its own neighbour: the first free one starts the envelope.
    std::uint32_t k = 0;
    while (!free_[neighbours[k]]) ++k;
    const std::uint32_t row_first = packed_of_[neighbours[k]];
    double* const row = factor.ldlt.AddRow(row_first);
    // The row of the matrix: zero, then the free neighbours up to the diagonal.
    std::fill(row + row_first, row + r + 1, 0.0);
    for (; k < neighbour_count && neighbours[k] <= i; ++k)
      if (free_[neighbours[k]]) row[packed_of_[neighbours[k]]] = coupling[k];
    // Never refused: the softness keeps the matrix positive definite.
    if (!factor.ldlt.FactorLastRow(softness_[i], 0.0)) return factor.valid = false;
  }
  return factor.valid = true;
}

void ExactContactSolver::SolveWith(const Factor& factor, const double* right, double* out) const {
  const std::uint32_t m = factor.ldlt.size();
  double* packed = scratch_;
  for (std::uint32_t r = 0; r < m; ++r) packed[r] = right[factor.rows[r]];
  factor.ldlt.Solve(packed);
  for (std::uint32_t r = 0; r < m; ++r) out[factor.rows[r]] = packed[r];
}

double ExactContactSolver::Residual(const RowSet& set, std::uint32_t row, const double* impulse) const {
  double sum = offset_[row] + softness_[row] * impulse[row];
  for (std::uint32_t k = set.neighbour_begin[row]; k < set.neighbour_begin[row + 1]; ++k)
    sum += set.coupling[k] * (impulse[set.neighbours[k]] - start_[set.neighbours[k]]);
  return sum;
}

bool ExactContactSolver::AtMinimum(RowSet& set, const SolverBody* bodies) {
  // Rows clamped into their limits have moved off their start: only then does the coupling enter.
  bool clamped = false;
  for (std::uint32_t i = 0; i < set.count && !clamped; ++i) clamped = impulse_[i] != start_[i];
  if (clamped) Couple(set, bodies);
  for (std::uint32_t i = 0; i < set.count; ++i) {
    const double residual = clamped ? Residual(set, i, impulse_) : offset_[i] + softness_[i] * impulse_[i];
    const bool free = free_[i] != 0, at_lower = impulse_[i] <= lower_[i];
    if (free ? std::abs(residual) > kResidualTolerance
             : lower_[i] != upper_[i] &&
                   (at_lower ? residual < -kResidualTolerance : residual > kResidualTolerance))
      return false;
  }
  return true;
}

bool ExactContactSolver::FreeRowsStep(const RowSet& set, Factor& factor) {
  const std::uint32_t n = set.count;
  // Where the free rows would go with the others held: the equality-constrained minimum, solved for the
  // change from the pass's starting impulses (whose effect the velocities already carry). Only a held row
  // that moved off its start couples into the free rows' right-hand side.
  bool held_moved = false;
  for (std::uint32_t i = 0; i < n && !held_moved; ++i) held_moved = !free_[i] && impulse_[i] != start_[i];
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!free_[i]) continue;
    double sum = -(offset_[i] + softness_[i] * start_[i]);
    if (held_moved)
      for (std::uint32_t k = set.neighbour_begin[i]; k < set.neighbour_begin[i + 1]; ++k) {
        const std::uint32_t j = set.neighbours[k];
        if (!free_[j]) sum -= set.coupling[k] * (impulse_[j] - start_[j]);
      }
    right_[i] = sum;
  }
  if (!Refactor(set, factor)) return false;
  SolveWith(factor, right_, target_);
  for (std::uint32_t i = 0; i < n; ++i)
    if (free_[i]) target_[i] += start_[i];
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
    const double residual = Residual(set, i, impulse_);
    const bool at_lower = impulse_[i] <= lower_[i];
    if ((at_lower && residual < -kResidualTolerance) || (!at_lower && residual > kResidualTolerance))
      free_[i] = 1, freed = true;
  }
  return freed;
}

bool ExactContactSolver::SolveRows(RowSet& set, SolverBody* bodies, const SubstepContext& context,
                                   bool use_bias, float* lowest) {
  const bool friction = &set == &friction_;
  if (friction)
    for (std::size_t k = 0; k < contacts_.size(); ++k) GatherPatch(*contacts_[k], patches_[k]);
  LoadRows(set, bodies, context, use_bias, lowest);
  // A primal active-set method on the convex problem min 1/2 x'(coupling + softness)x + q'x within the rows'
  // limits: every iterate stays within the limits (a round that cannot finish leaves a usable answer) and
  // the objective falls each round, so it cannot cycle. Rows strictly inside their limits are free.
  // Only the normals' softness differs between velocity and relax passes.
  Factor& factor = set.factors[use_bias && !friction ? 1 : 0];
  int round = 0;
  if (!AtMinimum(set, bodies)) {
    Couple(set, bodies);
    while (round < kMaxActiveSetRounds && FreeRowsStep(set, factor)) ++round;
  }
  ApplyImpulses(set, bodies);
  return round < kMaxActiveSetRounds;
}

void ExactContactSolver::LoadRows(const RowSet& set, const SolverBody* bodies, const SubstepContext& context,
                                  bool use_bias, float* lowest) {
  const std::uint32_t n = set.count;
  // Each free row aims for residual = velocity + bias + softness * impulse = 0: the fixed point of the
  // sequential soft update, with a normal row's spring scaled by its load. A friction row is held within
  // the friction of the normal impulses solved last.
  const SolverContact* moved = nullptr;  // whose motion `motion` is (a contact's rows are consecutive)
  ContactMotion motion;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Row& r = set.rows[i];
    const SolverContact& c = *r.contact;
    const float stiffness = set.diagonal[i];
    float softness = kRigidSoftness * stiffness;
    float bias = 0.0f;
    if (r.axis == kNormal) {
      if (moved != &c) motion = MotionSinceStepBegan(c, bodies, context.elapsed), moved = &c;
      const float separation = SeparationNow(*r.point, motion);
      *lowest = std::min(*lowest, separation);
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
    const float velocity =
        (r.direction->cwiseProduct(b.linear_velocity - a.linear_velocity) +
         r.angular[1]->cwiseProduct(b.angular_velocity) - r.angular[0]->cwiseProduct(a.angular_velocity))
            .sum();
    const double bound = r.axis == kNormal ? 0.0 : PatchBound(c, r.patch->lever, r.axis);
    lower_[i] = r.axis == kNormal ? 0.0 : -bound;
    upper_[i] = r.axis == kNormal ? kUnbounded : bound;
    softness_[i] = softness;
    // The velocity carries the accumulated impulses: residual = coupling (impulse - start) + softness
    // impulse + offset.
    start_[i] = Accumulated(r);
    impulse_[i] = std::clamp(start_[i], lower_[i], upper_[i]);
    free_[i] = impulse_[i] > lower_[i] && impulse_[i] < upper_[i];
    offset_[i] = static_cast<double>(velocity) + bias;
  }
}

void ExactContactSolver::ApplyImpulses(const RowSet& set, SolverBody* bodies) {
  const std::uint32_t n = set.count;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Row& r = set.rows[i];
    double value = impulse_[i];
    if (r.axis == 1) {
      // The active set holds friction inside a box; the sequential solver's limit is the circle.
      const double second = impulse_[i + 1];
      const double limit = upper_[i];  // the axes' bound
      const double length = std::sqrt(value * value + second * second);
      if (length > limit) {
        const double scale = length > 0.0 ? limit / length : 0.0;
        impulse_[i] = value * scale;
        impulse_[i + 1] = second * scale;
        value = impulse_[i];
      }
    }
    float& accumulated = Accumulated(r);
    const float delta = static_cast<float>(value) - accumulated;
    if (delta == 0.0f) continue;  // a row the pass left as it was (a set already at its minimum)
    accumulated = static_cast<float>(value);
    if (r.axis == kNormal)
      r.point->max_normal_impulse = std::max(r.point->max_normal_impulse, delta);
    else
      SpreadPatch(*r.contact, *r.patch, r.axis, delta);
    if (r.body_a != 0) {
      SolverBody& a = bodies[r.body_a];
      a.linear_velocity -= (a.inverse_mass * delta) * *r.direction;
      a.angular_velocity -= delta * *r.response[0];
    }
    if (r.body_b != 0) {
      SolverBody& b = bodies[r.body_b];
      b.linear_velocity += (b.inverse_mass * delta) * *r.direction;
      b.angular_velocity += delta * *r.response[1];
    }
  }
}

void ExactContactSolver::Solve(SolverBody* bodies, const SubstepContext& context, bool use_bias,
                               float* deepest) {
  // Friction first, within the normal impulses so far, then the normals against the velocities friction
  // left: the pass ends with every point's non-penetration exact (friction turning a light box under a heavy
  // one afterwards would open or close its contacts again). The two sets are a block Gauss-Seidel step on
  // the whole problem; solving each set exactly keeps what carries load through a stack. A relax pass solves
  // the normals alone: it takes out the push the velocity pass gave overlaps, which is along the normals, and
  // leaves friction as that pass solved it (the accuracy suite comes out as with friction solved again, for
  // a resting stack's step noticeably cheaper than solving friction again).
  float lowest = kLargeFloat;
  const bool friction_settled = !use_bias || SolveRows(friction_, bodies, context, use_bias, &lowest);
  const bool normals_settled = SolveRows(normals_, bodies, context, use_bias, &lowest);
  // An unfinished active set (a pile landing at once) leaves no row worse than a sequential pass would.
  if (!friction_settled || !normals_settled)
    for (SolverContact* c : contacts_) {
      SetupPendingFrictionRows(*c, bodies);
      SolveContactVelocity(*c, bodies, context, use_bias, false, nullptr);
    }
  if (deepest != nullptr) *deepest = std::min(*deepest, lowest);
}

}  // namespace strata
