#include "physics/constraints/JointConstraintKind.h"

#include <algorithm>

namespace strata {

void JointConstraintKind::BeginStep(const SolverStep& step, std::uint32_t job_count) {
  step_ = step;
  const PhysicsSettings& settings = *step.settings;
  // Only joints use it: a world without any is spared its divisions.
  if (!input_joints_.empty())
    rigid_spring_ = MakeSoftSpring(std::min(settings.joint_hertz, 0.25f / step.substep_dt),
                                   settings.joint_damping_ratio, step.substep_dt);
  SortJointsByIsland();
  if (jobs_.size() < job_count) jobs_.resize(job_count);
  if (!input_joints_.empty())
    for (JobScratch& job : jobs_)
      job.first_row_of_body.resize(step.solver_body_count, ExactJointSolver::kNoRow);
}

void JointConstraintKind::SortJointsByIsland() {
  // A counting sort by island; within an island the joints keep the step's order (slot order).
  const IslandBuilder& islands = *step_.islands;
  const std::uint32_t island_count = islands.island_count();
  if (input_joints_.empty()) {  // no joints: no counting, no exact-solve decisions, no work in any island
    island_begin_.clear();
    joints_.clear();
    exact_.clear();
    return;
  }
  island_begin_.assign(island_count + 2, 0);
  for (const std::uint32_t body : input_island_body_) ++island_begin_[islands.island_of(body) + 2];
  for (std::uint32_t island = 2; island < island_count + 2; ++island)
    island_begin_[island] += island_begin_[island - 1];
  joints_.resize(input_joints_.size());
  for (std::size_t k = 0; k < input_joints_.size(); ++k)
    joints_[island_begin_[islands.island_of(input_island_body_[k]) + 1]++] = input_joints_[k];
  island_begin_.pop_back();
  // An island's joints go to a ExactJointSolver when one of them needs it (decided per island, so what
  // other islands share its group changes nothing).
  exact_.assign(joints_.size(), kPassesSolve);
  for (std::uint32_t island = 0; island < island_count; ++island) {
    const std::uint32_t begin = island_begin_[island], end = island_begin_[island + 1];
    const bool exact = std::any_of(joints_.begin() + begin, joints_.begin() + end,
                                   [&](const Constraint* joint) { return NeedsExactSolve(*joint); });
    if (!exact) continue;
    for (std::uint32_t k = begin; k < end; ++k)
      exact_[k] = joints_[k]->OnlyRigidRows() ? kExactOnly : kExactRigidRows;
  }
}

bool JointConstraintKind::NeedsExactSolve(const Constraint& joint) const {
  const PhysicsSettings& settings = *step_.settings;
  if (!settings.exact_joints) return false;
  // Passes move a load between a light and a heavy body a mass ratio's share at a time.
  const std::uint32_t a = joint.side_a().solver_index, b = joint.side_b().solver_index;
  if (a == 0 || b == 0) return false;
  const float inverse_a = step_.bodies[a].inverse_mass, inverse_b = step_.bodies[b].inverse_mass;
  return std::max(inverse_a, inverse_b) >= settings.exact_joint_mass_ratio * std::min(inverse_a, inverse_b);
}

std::uint32_t JointConstraintKind::IslandWork(std::uint32_t island) const {
  if (island_begin_.empty()) return 0;  // no joints this step
  return island_begin_[island + 1] - island_begin_[island];
}

void JointConstraintKind::BeginGroups(std::span<const SolverGroup> groups) {
  groups_.resize(groups.size());
  if (island_begin_.empty()) {  // no joints this step
    for (const SolverGroup& g : groups) groups_[g.index] = Group{};
    return;
  }
  for (const SolverGroup& g : groups) {
    Group& group = groups_[g.index];
    const std::uint32_t first = island_begin_[g.first_island];
    group.joints = joints_.data() + first;
    group.joint_count = island_begin_[g.end_island] - first;
    group.exact = exact_.data() + first;
    group.exact_solver = nullptr;
    group.exact_alone = false;
    group.solved_substep = -1;
  }
}

GroupLayout JointConstraintKind::PrepareGroup(const SolverGroup& solver_group, BlockArena& arena,
                                              std::uint32_t job) {
  Group& group = groups_[solver_group.index];
  GroupLayout layout;
  if (group.joint_count == 0) return layout;
  layout.splits = 1;
  // The islands' joints that are solved exactly, in order.
  const auto exact = static_cast<std::uint32_t>(
      group.joint_count - std::count(group.exact, group.exact + group.joint_count, kPassesSolve));
  if (exact > 0) {
    Constraint** rows_of = arena.AllocateArray<Constraint*>(exact);
    std::uint32_t n = 0;
    for (std::uint32_t j = 0; j < group.joint_count; ++j)
      if (group.exact[j] != kPassesSolve) rows_of[n++] = group.joints[j];
    group.exact_solver = ExactJointSolver::Create(arena, std::span<Constraint* const>(rows_of, exact),
                                                  jobs_[job].first_row_of_body.data());
    group.exact_alone =
        solver_group.one_kind_per_island && std::all_of(group.exact, group.exact + group.joint_count,
                                                        [](std::uint8_t e) { return e == kExactOnly; });
  }
  layout.positions = true;
  return layout;
}

std::uint32_t JointConstraintKind::Items(std::uint32_t, const SolverPass& pass) const {
  // Joints do not bounce; every other pass is one item, in order: a group's joints share bodies.
  return pass.kind == SolverPassKind::kRestitution ? 0 : 1;
}

void JointConstraintKind::Run(std::uint32_t group_index, const SolverPass& pass, std::uint32_t, std::uint32_t,
                              std::uint32_t) {
  Group& group = groups_[group_index];
  ExactJointSolver* const exact_solver = group.exact_solver;
  if (pass.kind == SolverPassKind::kPositions) {
    // One joint at a time for those the passes solve, then the exact rows all at once.
    for (std::uint32_t k = 0; k < group.joint_count; ++k)
      if (group.exact[k] == kPassesSolve)
        group.joints[k]->SolvePosition(step_.bodies, step_.poses, pass.elapsed);
    if (exact_solver != nullptr)
      exact_solver->SolvePositions(step_.bodies, step_.poses, pass.elapsed, pass.pose_version);
    return;
  }
  ConstraintPassContext context;
  context.h = step_.substep_dt;
  context.inverse_h = 1.0f / step_.substep_dt;
  context.rigid_spring = rigid_spring_;
  context.use_bias = pass.kind == SolverPassKind::kVelocity;
  context.pose_version = pass.pose_version;
  // The exact solve's rows first, built from the poses the pass sees: at the substep's start for warm start
  // and velocity passes, after its integration for relax passes (a whipping chain's links turn enough in a
  // substep that stale rows let it drift apart). A relax pass's build serves the next substep's passes too:
  // they see its poses. Built before the joints' own rows, so their limits and drives solve against the
  // masses the rigid rows leave them from the first pass that sees the poses.
  if (exact_solver != nullptr &&
      exact_solver->Build(step_.bodies, step_.poses, pass.elapsed, pass.pose_version)) {
    exact_solver->ReduceFreeRows(step_.bodies, step_.poses, context, pass.elapsed);
    group.solved_substep = -1;
  }
  if (pass.kind == SolverPassKind::kWarmStart) group.solved_substep = -1;
  // A second velocity (or relax) pass of a substep over joints the exact solve holds alone changes nothing:
  // with A = J M^-1 J^T, u = A^-1 (rate + bias) and the accumulated impulse l, a pass maps (u, l) by
  // [[s, -s], [-m, m]] (m and s the mass and impulse scales, m + s = 1; rigid: m = 1, s = 0), and that map
  // applied twice is itself. Passes of other kinds or joints would move the bodies in between; here none do.
  if (group.exact_alone && pass.kind != SolverPassKind::kWarmStart) {
    if (group.solved_substep == pass.substep && group.solved_kind == pass.kind) return;
    group.solved_substep = pass.substep;
    group.solved_kind = pass.kind;
  }
  // Alternating the order from pass to pass carries a load along a chain both ways.
  for (std::uint32_t k = 0; k < group.joint_count; ++k) {
    const std::uint32_t index = pass.reverse ? group.joint_count - 1 - k : k;
    if (pass.kind != SolverPassKind::kWarmStart && group.exact[index] == kExactOnly) continue;
    Constraint& joint = *group.joints[index];
    SolverBody stand_in_a, stand_in_b;
    ConstraintBodies bodies =
        joint.BodiesForPass(step_.bodies, step_.poses, pass.elapsed, stand_in_a, stand_in_b);
    if (pass.kind == SolverPassKind::kWarmStart)
      joint.WarmStart(bodies, context);
    else if (group.exact[index] == kPassesSolve)
      joint.SolveVelocity(bodies, context, true);
    else if (exact_solver->solves_free_rows())
      joint.SolveUnreducibleRows(bodies, context);
    else
      joint.SolveVelocity(bodies, context, false);
  }
  if (exact_solver == nullptr || pass.kind == SolverPassKind::kWarmStart) return;
  // The limits and drives of the exact solve's joints against its rigid rows, then those rows last,
  // exactly: limits and drives before them cannot pull a chain apart.
  exact_solver->SolveFreeRows(step_.bodies, context);
  exact_solver->Solve(step_.bodies, context);
}

}  // namespace strata
