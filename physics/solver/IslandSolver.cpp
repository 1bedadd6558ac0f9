#include "physics/solver/IslandSolver.h"

#include <algorithm>
#include <thread>

#include "physics/body/GyroscopicTorque.h"
#include "physics/core/Atomics.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace strata {

namespace {

constexpr std::uint32_t kBundleBatch = 16 / ContactBundle::kLanes;  // sixteen constraints
constexpr std::uint32_t kBodyBatch = 64;
// Idle laps (a pause each, about a microsecond in all) before a waiting job yields its core.
constexpr std::uint32_t kSpinsBeforeYield = 64;

void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

}  // namespace

void IslandSolver::BeginStep(const Input& input, std::uint32_t job_count) {
  input_ = input;
  const PhysicsSettings& settings = *input.settings;
  substep_dt_ = input.dt / static_cast<float>(settings.substeps);
  // Contacts stiffer than a quarter of the substep rate would ring; contacts with a fixed body may be twice
  // as stiff, since only one side moves.
  const float hertz = std::min(settings.contact_hertz, 0.25f / substep_dt_);
  context_.between_moving = MakeSoftSpring(hertz, settings.contact_damping_ratio, substep_dt_);
  context_.against_fixed = MakeSoftSpring(2.0f * hertz, settings.contact_damping_ratio, substep_dt_);
  context_.inverse_h = 1.0f / substep_dt_;
  context_.max_push_velocity = settings.contact_push_max_velocity;
  context_.restitution_threshold = settings.min_velocity_for_restitution;
  context_.elapsed = 0.0f;
  joint_spring_ = MakeSoftSpring(std::min(settings.joint_hertz, 0.25f / substep_dt_),
                                 settings.joint_damping_ratio, substep_dt_);
  const float gravity = settings.gravity.norm();
  context_.weight_per_impulse = gravity > 0.0f ? 1.0f / (gravity * substep_dt_) : 0.0f;
  const IslandBuilder& islands = *input.islands;
  const std::uint32_t island_count = islands.island_count();
  ordered_.resize(input.constraints.size());
  body_masks_.resize(input.solver_body_count);
  SortJointsByIsland();
  island_direct_.resize(island_count);
  for (std::uint32_t island = 0; island < island_count; ++island)
    island_direct_[island] = IsDirectIsland(island);
  // Groups: a large island alone, or consecutive small islands of one kind (solved directly or not) until
  // they hold kGroupConstraints.
  // An island's work: its contacts and its joints (joint-only islands, ragdolls in flight, must not all
  // gather in one group).
  auto work = [&](std::uint32_t island) {
    return islands.constraint_count(island, island + 1) + island_joint_begin_[island + 1] -
           island_joint_begin_[island];
  };
  auto form_groups = [&](auto&& add) {
    std::uint32_t island = 0;
    while (island < island_count) {
      const std::uint32_t first = island;
      if (work(island) >= LargeIslandSplitter::kMinConstraintsToSplit) {
        add(first, ++island, false);
        continue;
      }
      const bool direct = island_direct_[island] != 0;
      std::uint32_t total = 0;
      while (island < island_count && total < kGroupConstraints &&
             work(island) < LargeIslandSplitter::kMinConstraintsToSplit &&
             (island_direct_[island] != 0) == direct)
        total += work(island), ++island;
      add(first, island, direct);
    }
  };
  std::uint32_t count = 0;
  form_groups([&](std::uint32_t, std::uint32_t, bool) { ++count; });
  if (count > group_capacity_) {
    group_capacity_ = count;
    groups_ = std::make_unique<Group[]>(group_capacity_);
  }
  group_count_ = 0;
  form_groups([&](std::uint32_t first, std::uint32_t end, bool direct) { AddGroup(first, end, direct); });
  groups_finished_.store(0, std::memory_order_relaxed);
  if (jobs_.size() < job_count) {
    jobs_.resize(job_count);
    for (JobState& job : jobs_) job.arena.SetPool(pool_);
  }
  // Any job may prepare any group: size every job's splitting buffers for the largest.
  std::uint32_t largest = 0;
  for (std::uint32_t g = 0; g < group_count_; ++g)
    largest = std::max(largest, islands.constraint_count(groups_[g].first_island, groups_[g].end_island));
  for (JobState& job : jobs_) {
    job.arena.Recycle();
    job.split_of.reserve(largest);
    job.scratch.reserve(largest);
    if (!input.joints.empty())
      job.first_row_of_body.resize(input.solver_body_count, DirectJointSolver::kNoRow);
    job.deepest = 0.0f;
  }
}

void IslandSolver::SortJointsByIsland() {
  // A counting sort by island; within an island the joints keep the step's order (slot order).
  const std::uint32_t island_count = input_.islands->island_count();
  if (input_.joints.empty()) {  // no joints: no counting, no exact-solve decisions
    island_joint_begin_.assign(island_count + 1, 0);
    joints_.clear();
    joint_direct_.clear();
    return;
  }
  island_joint_begin_.assign(island_count + 2, 0);
  for (const std::uint32_t body : input_.joint_island_body)
    ++island_joint_begin_[input_.islands->island_of(body) + 2];
  for (std::uint32_t island = 2; island < island_count + 2; ++island)
    island_joint_begin_[island] += island_joint_begin_[island - 1];
  joints_.resize(input_.joints.size());
  for (std::size_t k = 0; k < input_.joints.size(); ++k)
    joints_[island_joint_begin_[input_.islands->island_of(input_.joint_island_body[k]) + 1]++] =
        input_.joints[k];
  island_joint_begin_.pop_back();
  // An island's joints go to a DirectJointSolver when one of them needs it (decided per island, so what
  // other islands share its group changes nothing).
  joint_direct_.assign(joints_.size(), 0);
  for (std::uint32_t island = 0; island < island_count; ++island) {
    const std::uint32_t begin = island_joint_begin_[island], end = island_joint_begin_[island + 1];
    const bool direct = std::any_of(joints_.begin() + begin, joints_.begin() + end,
                                    [&](const Constraint* joint) { return NeedsDirectSolve(*joint); });
    std::fill(joint_direct_.begin() + begin, joint_direct_.begin() + end, direct ? 1 : 0);
  }
}

bool IslandSolver::IsDirectIsland(std::uint32_t island) const {
  // Worth it where sequential passes fall short and affordable: bodies resting on each other (a single body
  // on the ground gains nothing), few points per body (a body on many mesh triangles has far more rows than
  // its six motions; they would make the solve cost the cube of that), and at rest (a landing pile changes
  // which rows push every pass, and moving piles show no sag).
  if (!input_.settings->direct_small_islands) return false;
  // Joints are solved by passes; an island with joints keeps its contacts in passes too.
  if (island_joint_begin_[island + 1] != island_joint_begin_[island]) return false;
  const std::span<const std::uint32_t> bodies = input_.islands->bodies(island, island + 1);
  // A load passes through a body only between two contacts; two bodies touching each other and nothing else
  // (spheres that met in flight) gain nothing from it either.
  if (bodies.size() < 2 || input_.islands->constraint_count(island, island + 1) < 2) return false;
  std::uint32_t points = 0;
  for (const std::uint32_t index : input_.islands->constraints(island))
    points += input_.constraints[index]->point_count;
  if (points == 0 || points > DirectContactSolver::kMaxPoints ||
      points > kDirectMaxPointsPerBody * bodies.size())
    return false;
  constexpr float kRest2 = kDirectRestSpeed * kDirectRestSpeed;
  return std::all_of(bodies.begin(), bodies.end(), [&](std::uint32_t body) {
    const SolverBody& b = input_.bodies[body + 1];
    return b.linear_velocity.squaredNorm() <= kRest2 && b.angular_velocity.squaredNorm() <= kRest2;
  });
}

void IslandSolver::AddGroup(std::uint32_t first_island, std::uint32_t end_island, bool direct) {
  Group& group = groups_[group_count_++];
  group.first_island = first_island;
  group.end_island = end_island;
  group.direct = direct;
  group.first_constraint = input_.islands->constraint_offset(first_island);
  group.joints = joints_.data() + island_joint_begin_[first_island];
  group.joint_count = island_joint_begin_[end_island] - island_joint_begin_[first_island];
}

void IslandSolver::PrepareGroup(std::uint32_t group_index, std::uint32_t job_index) {
  Group& group = groups_[group_index];
  const IslandBuilder& islands = *input_.islands;
  const std::uint32_t constraint_count = islands.constraint_count(group.first_island, group.end_island);
  if (constraint_count == 0 && group.joint_count == 0) {
    PrepareFreeGroup(group);
    return;
  }
  group.free = false;
  group.joint_solver = nullptr;
  const std::span<ContactConstraint*> ordered =
      std::span(ordered_).subspan(group.first_constraint, constraint_count);
  std::size_t k = 0;
  for (std::uint32_t island = group.first_island; island < group.end_island; ++island)
    for (const std::uint32_t index : islands.constraints(island)) ordered[k++] = input_.constraints[index];

  JobState& job = jobs_[job_index];
  // One sequential split in island order: for a direct group, whose islands' rows are solved together, and
  // for a group too small for any parallel split (the splitter would merge each into the sequential one).
  if (group.direct || constraint_count < LargeIslandSplitter::kMinSplitSize) {
    group.splits = IslandSplits{};
    group.splits.split_count = constraint_count > 0 ? 1 : 0;
    group.splits.begin[1] = constraint_count;
    group.splits.last_is_sequential = constraint_count > 0;
  } else {
    for (const std::uint32_t body : islands.bodies(group.first_island, group.end_island))
      body_masks_[body + 1] = 0;
    group.splits = LargeIslandSplitter::Split(ordered, body_masks_.data(), job.split_of, job.scratch);
  }
  if (group.direct)
    group.direct_solvers =
        job.arena.AllocateArray<DirectContactSolver*>(group.end_island - group.first_island);
  const std::uint32_t splits = group.splits.split_count;
  const std::uint32_t parallel_splits = splits - (group.splits.last_is_sequential ? 1 : 0);
  // Bundles of consecutive constraints of a parallel split; set up later, in the setup round.
  group.bundle_count = 0;
  for (std::uint32_t s = 0; s < parallel_splits; ++s)
    group.bundle_count += (group.splits.begin[s + 1] - group.splits.begin[s] + ContactBundle::kLanes - 1) /
                          ContactBundle::kLanes;
  group.bundles = job.arena.AllocateArray<ContactBundle*>(group.bundle_count);
  std::uint32_t bundle = 0;
  for (std::uint32_t s = 0; s < parallel_splits; ++s) {
    group.bundle_begin[s] = bundle;
    for (std::uint32_t c = group.splits.begin[s]; c < group.splits.begin[s + 1]; c += ContactBundle::kLanes) {
      const std::uint32_t end = std::min<std::uint32_t>(c + ContactBundle::kLanes, group.splits.begin[s + 1]);
      group.bundles[bundle++] = AllocateBundle(job.arena, ordered.subspan(c, end - c));
    }
  }
  group.bundle_begin[parallel_splits] = bundle;
  group.sequential_count = 0;
  if (group.splits.last_is_sequential) {
    group.sequential = ordered.data() + group.splits.begin[parallel_splits];
    group.sequential_count = group.splits.begin[splits] - group.splits.begin[parallel_splits];
    group.sequential_contacts = job.arena.AllocateArray<SolverContact*>(group.sequential_count);
  }
  if (group.joint_count > 0) {
    // The islands' joints that are solved exactly, in order.
    const std::size_t first = static_cast<std::size_t>(group.joints - joints_.data());
    const auto direct = static_cast<std::uint32_t>(
        std::count(joint_direct_.begin() + first, joint_direct_.begin() + first + group.joint_count, 1));
    if (direct > 0) {
      Constraint** exact = job.arena.AllocateArray<Constraint*>(direct);
      std::uint32_t n = 0;
      for (std::uint32_t j = 0; j < group.joint_count; ++j)
        if (joint_direct_[first + j] != 0) exact[n++] = group.joints[j];
      group.joint_solver = DirectJointSolver::Create(job.arena, std::span<Constraint* const>(exact, direct),
                                                     job.first_row_of_body.data());
    }
  }
  const float threshold = -input_.settings->min_velocity_for_restitution;
  group.has_restitution = std::any_of(ordered.begin(), ordered.end(), [&](const ContactConstraint* c) {
    if (c->restitution <= 0.0f) return false;
    const auto points = std::span(c->points(), c->point_count);
    return std::any_of(points.begin(), points.end(),
                       [&](const ContactConstraintPoint& p) { return p.normal_velocity < threshold; });
  });
  const PhysicsSettings& settings = *input_.settings;
  group.round_splits = splits + (group.joint_count > 0 ? 1 : 0);
  const auto per_substep = group.round_splits * static_cast<std::uint32_t>(1 + settings.velocity_iterations +
                                                                           settings.relax_iterations) +
                           2;
  group.round_count =
      1 + static_cast<std::uint32_t>(settings.substeps) * per_substep +
      (group.has_restitution ? splits * static_cast<std::uint32_t>(settings.restitution_iterations) : 0) +
      (group.joint_solver != nullptr ? 1 : 0);
  group.one_job =
      group.bundle_count == 0 && islands.bodies(group.first_island, group.end_island).size() <= kBodyBatch;
  group.processed.store(0, std::memory_order_relaxed);
  group.status.store(0, std::memory_order_release);
}

void IslandSolver::PrepareFreeGroup(Group& group) {
  group.splits = IslandSplits{};
  group.round_splits = 0;
  group.free = true;
  group.bundle_count = 0;
  group.sequential_count = 0;
  group.has_restitution = false;
  // Per substep its forces (but the first's) and its integration: the rounds of a group without splits.
  group.round_count = 1 + 2 * static_cast<std::uint32_t>(input_.settings->substeps);
  group.one_job = input_.islands->bodies(group.first_island, group.end_island).size() <= kBodyBatch;
  group.processed.store(0, std::memory_order_relaxed);
  group.status.store(0, std::memory_order_release);
}

void IslandSolver::RunFreeGroup(const Group& group) const {
  const std::span<const std::uint32_t> bodies = input_.islands->bodies(group.first_island, group.end_island);
  for (int substep = 0; substep < input_.settings->substeps; ++substep) {
    if (substep > 0)
      for (const std::uint32_t body : bodies) AddForces(body);
    for (const std::uint32_t body : bodies) Integrate(body);
  }
}

IslandSolver::Round IslandSolver::Describe(const Group& group, std::uint32_t round) const {
  const std::uint32_t splits = group.round_splits;
  if (round == 0) return {RoundKind::kSetup};
  round -= 1;
  const PhysicsSettings& settings = *input_.settings;
  const auto velocity = static_cast<std::uint32_t>(settings.velocity_iterations);
  const auto relax = static_cast<std::uint32_t>(settings.relax_iterations);
  const std::uint32_t per_substep = splits * (1 + velocity + relax) + 2;
  const auto substeps = static_cast<std::uint32_t>(settings.substeps);
  if (round >= substeps * per_substep) {
    round -= substeps * per_substep;
    // The joints' position step comes last, after any restitution.
    const std::uint32_t restitution =
        group.has_restitution
            ? group.splits.split_count * static_cast<std::uint32_t>(settings.restitution_iterations)
            : 0;
    if (round >= restitution) return {RoundKind::kJointPositions, group.splits.split_count, 0, 0};
    // Only contacts bounce: the restitution rounds go over the contact splits.
    const std::uint32_t contact_splits = group.splits.split_count;
    return {RoundKind::kRestitution, round % contact_splits, static_cast<int>(round / contact_splits)};
  }
  const auto substep = static_cast<int>(round / per_substep);
  round %= per_substep;
  if (round == 0) return {RoundKind::kAddForces, 0, 0, substep};
  round -= 1;
  // Warm starting is a pass of its own (as in Jolt): folding it into each split's first velocity pass lets
  // the first splits solve against velocities that lack the later splits' warm impulses, and stacks sag.
  if (round < splits) return {RoundKind::kWarmStart, round, 0, substep};
  round -= splits;
  if (round < velocity * splits)
    return {RoundKind::kVelocity, round % splits, static_cast<int>(round / splits), substep};
  round -= velocity * splits;
  if (round == 0) return {RoundKind::kIntegrate, 0, 0, substep};
  round -= 1;
  return {RoundKind::kRelax, round % splits, static_cast<int>(round / splits), substep};
}

bool IslandSolver::IsLastSolvePass(const Round& round) const {
  const PhysicsSettings& settings = *input_.settings;
  if (round.substep + 1 != settings.substeps) return false;
  if (settings.relax_iterations > 0)
    return round.kind == RoundKind::kRelax && round.iteration + 1 == settings.relax_iterations;
  return round.kind == RoundKind::kVelocity && round.iteration + 1 == settings.velocity_iterations;
}

std::uint32_t IslandSolver::RoundItems(const Group& split, const Round& round) const {
  switch (round.kind) {
    case RoundKind::kSetup:
      return split.bundle_count + (split.sequential_count > 0 ? 1 : 0);
    case RoundKind::kAddForces:
      // The first substep's share was added before the solve.
      if (round.substep == 0) return 0;
      [[fallthrough]];
    case RoundKind::kIntegrate:
      return static_cast<std::uint32_t>(input_.islands->bodies(split.first_island, split.end_island).size());
    default:
      // The sequential split and the joints' are one item each: their constraints share bodies, so one
      // thread takes them in order.
      return IsJointSplit(split, round.split) || IsSequential(split, round.split)
                 ? 1
                 : split.bundle_begin[round.split + 1] - split.bundle_begin[round.split];
  }
}

void IslandSolver::Integrate(std::uint32_t island_body) const {
  const std::uint32_t index = island_body + 1;
  SolverBody& body = input_.bodies[index];
  // Kinematic bodies were moved before the solve began; contacts follow them by their velocity.
  if (body.inverse_mass <= 0.0f) return;
  SolverPose& pose = input_.poses[index];
  const float h = substep_dt_;
  const Vec4 moved = body.linear_velocity * h;
  const Vec4 turn = body.angular_velocity * h;
  pose.center_of_mass += moved;
  const Quat delta(0.0f, 0.5f * turn.x(), 0.5f * turn.y(), 0.5f * turn.z());
  pose.rotation.coeffs() += (delta * pose.rotation).coeffs();
  pose.rotation.normalize();
  body.delta_position += moved;
  body.delta_rotation += turn;
}

void IslandSolver::AddForces(std::uint32_t island_body) const {
  const std::uint32_t index = island_body + 1;
  SolverBody& body = input_.bodies[index];
  const SolverVelocityStep& step = input_.velocity_steps[index];
  body.linear_velocity += step.linear;
  if (step.gyroscopic)
    body.angular_velocity = ToVec4(SpinWithoutTorque(step.inertia, input_.poses[index].rotation,
                                                     ToVec3(body.angular_velocity), substep_dt_));
  body.angular_velocity += step.angular;
}

void IslandSolver::RunBatch(Group& split, const Round& round, std::uint32_t begin, std::uint32_t end,
                            JobState& job) {
  SolverBody* bodies = input_.bodies;
  if (round.kind == RoundKind::kSetup) {
    for (std::uint32_t i = begin; i < end; ++i) {
      if (i < split.bundle_count) {
        SetupBundle(*split.bundles[i], bodies, context_);
        continue;
      }
      for (std::uint32_t k = 0; k < split.sequential_count; ++k)
        split.sequential_contacts[k] = SetupSolverContact(job.arena, *split.sequential[k], bodies, context_);
      if (split.direct) SetupDirectSolvers(split, job);
    }
    return;
  }
  if (round.kind == RoundKind::kIntegrate || round.kind == RoundKind::kAddForces) {
    const std::span<const std::uint32_t> island_bodies =
        input_.islands->bodies(split.first_island, split.end_island);
    if (round.kind == RoundKind::kIntegrate)
      for (std::uint32_t i = begin; i < end; ++i) Integrate(island_bodies[i]);
    else
      for (std::uint32_t i = begin; i < end; ++i) AddForces(island_bodies[i]);
    return;
  }
  if (IsJointSplit(split, round.split)) {
    RunJoints(split, round);
    return;
  }
  SubstepContext context = context_;
  // Velocity passes see the poses at the substep's start, relax passes those after its integration.
  context.elapsed =
      substep_dt_ * static_cast<float>(round.substep + (round.kind == RoundKind::kRelax ? 1 : 0));
  const bool last_solve_pass = IsLastSolvePass(round);
  // The impulses a next step warm-starts from are those after restitution, where there is one.
  const bool last_pass = split.has_restitution
                             ? round.kind == RoundKind::kRestitution &&
                                   round.iteration + 1 == input_.settings->restitution_iterations
                             : last_solve_pass;
  // Alternate the order points are visited in from pass to pass (and substep to substep), so a stack does
  // not lean towards the side solved first.
  const bool reverse =
      ((round.iteration + round.substep + (round.kind == RoundKind::kRelax ? 1 : 0)) & 1) != 0;
  float deepest = 0.0f;
  float* const measure = last_solve_pass ? &deepest : nullptr;
  const bool use_bias = round.kind == RoundKind::kVelocity;
  if (split.direct && (round.kind == RoundKind::kVelocity || round.kind == RoundKind::kRelax)) {
    for (std::uint32_t island = 0; island < split.end_island - split.first_island; ++island)
      split.direct_solvers[island]->Solve(bodies, context, use_bias, measure);
    if (last_pass)
      for (std::uint32_t k = 0; k < split.sequential_count; ++k)
        StoreContactImpulses(*split.sequential_contacts[k]);
  } else if (IsSequential(split, round.split)) {
    const std::span<SolverContact*> contacts(split.sequential_contacts, split.sequential_count);
    for (SolverContact* c : contacts) {
      switch (round.kind) {
        case RoundKind::kWarmStart:
          WarmStartContact(*c, bodies);
          break;
        case RoundKind::kVelocity:
        case RoundKind::kRelax:
          SolveContactVelocity(*c, bodies, context, use_bias, reverse, measure);
          break;
        case RoundKind::kRestitution:
          ApplyContactRestitution(*c, bodies, context);
          break;
        default:
          break;
      }
      if (last_pass) StoreContactImpulses(*c);
    }
  } else {
    ContactBundle* const* bundles = split.bundles + split.bundle_begin[round.split];
    for (std::uint32_t i = begin; i < end; ++i) {
      ContactBundle& bundle = *bundles[i];
      switch (round.kind) {
        case RoundKind::kWarmStart:
          WarmStartBundle(bundle, bodies);
          break;
        case RoundKind::kVelocity:
        case RoundKind::kRelax:
          SolveBundleVelocity(bundle, bodies, context, use_bias, reverse, measure);
          break;
        case RoundKind::kRestitution:
          ApplyBundleRestitution(bundle, bodies, context);
          break;
        default:
          break;
      }
      if (last_pass) StoreBundleImpulses(bundle);
    }
  }
  if (measure != nullptr) job.deepest = std::min(job.deepest, deepest);
}

bool IslandSolver::NeedsDirectSolve(const Constraint& joint) const {
  const PhysicsSettings& settings = *input_.settings;
  if (!settings.direct_joints) return false;
  // Passes move a load between a light and a heavy body a mass ratio's share at a time.
  const std::uint32_t a = joint.side_a().solver_index, b = joint.side_b().solver_index;
  if (a == 0 || b == 0) return false;
  const float inverse_a = input_.bodies[a].inverse_mass, inverse_b = input_.bodies[b].inverse_mass;
  return std::max(inverse_a, inverse_b) >= settings.direct_joint_mass_ratio * std::min(inverse_a, inverse_b);
}

void IslandSolver::RunJoints(const Group& group, const Round& round) const {
  ConstraintPassContext pass;
  pass.h = substep_dt_;
  pass.inverse_h = context_.inverse_h;
  pass.rigid_spring = joint_spring_;
  pass.use_bias = round.kind == RoundKind::kVelocity;
  // Velocity passes see the poses at the substep's start, relax passes those after its integration.
  const float elapsed =
      substep_dt_ * static_cast<float>(round.substep + (round.kind == RoundKind::kRelax ? 1 : 0));
  // Alternating the order from pass to pass carries a load along a chain both ways.
  const bool reverse =
      ((round.iteration + round.substep + (round.kind == RoundKind::kRelax ? 1 : 0)) & 1) != 0;
  DirectJointSolver* const direct = group.joint_solver;
  const std::uint8_t* const exact = joint_direct_.data() + (group.joints - joints_.data());
  if (round.kind == RoundKind::kJointPositions) {
    direct->SolvePositions(input_.bodies, input_.poses, input_.dt);
    return;
  }
  for (std::uint32_t k = 0; k < group.joint_count; ++k) {
    const std::uint32_t index = reverse ? group.joint_count - 1 - k : k;
    Constraint& joint = *group.joints[index];
    SolverBody stand_in_a, stand_in_b;
    ConstraintBodies bodies =
        joint.BodiesForPass(input_.bodies, input_.poses, elapsed, stand_in_a, stand_in_b);
    if (round.kind == RoundKind::kWarmStart)
      joint.WarmStart(bodies, pass);
    else
      joint.SolveVelocity(bodies, pass, exact[index] == 0);
  }
  if (direct == nullptr) return;
  // The rows that always hold last, exactly: limits and drives before them cannot pull a chain apart.
  // Built from the poses the pass sees: at the substep's start for warm start and velocity passes, after
  // its integration for relax passes (a whipping chain's links turn enough in a substep that stale rows
  // let it drift apart).
  if (round.kind == RoundKind::kWarmStart || (round.kind == RoundKind::kRelax && round.iteration == 0))
    direct->Build(input_.bodies, input_.poses, elapsed);
  if (round.kind != RoundKind::kWarmStart) direct->Solve(input_.bodies, pass);
}

void IslandSolver::SetupDirectSolvers(Group& group, JobState& job) {
  const IslandBuilder& islands = *input_.islands;
  std::uint32_t offset = 0;
  for (std::uint32_t island = group.first_island; island < group.end_island; ++island) {
    const std::uint32_t count = islands.constraint_count(island, island + 1);
    group.direct_solvers[island - group.first_island] = DirectContactSolver::Create(
        job.arena, std::span<SolverContact* const>(group.sequential_contacts + offset, count), input_.bodies,
        context_.weight_per_impulse);
    offset += count;
  }
}

IslandSolver::BatchResult IslandSolver::TryRunWholeGroup(Group& group, JobState& job) {
  std::uint64_t status = group.status.load(std::memory_order_acquire);
  const std::uint64_t done = static_cast<std::uint64_t>(group.round_count) << 32;
  if (status == done || !group.status.compare_exchange_strong(status, done, std::memory_order_acq_rel))
    return BatchResult::kDone;
  if (group.free) {
    RunFreeGroup(group);  // the same work as its rounds, without describing each
  } else {
    // The rounds in their order, each whole, as single batches would have run them.
    for (std::uint32_t round_index = 0; round_index < group.round_count; ++round_index) {
      const Round round = Describe(group, round_index);
      const std::uint32_t items = RoundItems(group, round);
      if (items > 0) RunBatch(group, round, 0, items, job);
    }
  }
  groups_finished_.fetch_add(1, std::memory_order_release);
  return BatchResult::kRan;
}

IslandSolver::BatchResult IslandSolver::TryRunBatch(Group& group, JobState& job) {
  if (group.one_job) return TryRunWholeGroup(group, job);
  std::uint64_t status = group.status.load(std::memory_order_acquire);
  while (true) {
    const auto round_index = static_cast<std::uint32_t>(status >> 32);
    if (round_index >= group.round_count) return BatchResult::kDone;
    const Round round = Describe(group, round_index);
    const std::uint32_t items = RoundItems(group, round);
    const auto item = static_cast<std::uint32_t>(status);
    if (items == 0) {
      // Nothing to do in this round (a group without constraints has no setup): step over it.
      const std::uint64_t next = static_cast<std::uint64_t>(round_index + 1) << 32;
      if (group.status.compare_exchange_weak(status, next, std::memory_order_acq_rel,
                                             std::memory_order_acquire) &&
          round_index + 1 == group.round_count)
        groups_finished_.fetch_add(1, std::memory_order_release);
      continue;
    }
    if (item >= items) return BatchResult::kWaiting;  // every batch of this round is taken
    const bool per_body = round.kind == RoundKind::kIntegrate || round.kind == RoundKind::kAddForces;
    const std::uint32_t batch = per_body ? kBodyBatch : kBundleBatch;
    const std::uint32_t take = std::min(batch, items - item);
    if (!group.status.compare_exchange_weak(status, status + take, std::memory_order_acquire,
                                            std::memory_order_acquire))
      continue;
    RunBatch(group, round, item, item + take, job);
    // The last batch of a round opens the next one; the release publishes every batch's writes to it.
    if (group.processed.fetch_add(take, std::memory_order_acq_rel) + take == items) {
      group.processed.store(0, std::memory_order_relaxed);
      const std::uint32_t next = round_index + 1;
      group.status.store(static_cast<std::uint64_t>(next) << 32, std::memory_order_release);
      if (next == group.round_count) groups_finished_.fetch_add(1, std::memory_order_release);
    }
    return BatchResult::kRan;
  }
}

void IslandSolver::SolveJob(std::uint32_t job_index) {
  JobState& job = jobs_[job_index];
  if (group_count_ == 0) return;
  // Jobs start spread over the groups and stay on a group while it has work, so they rarely meet.
  const auto job_count = static_cast<std::uint32_t>(jobs_.size());
  std::uint32_t cursor = static_cast<std::uint32_t>(static_cast<std::uint64_t>(job_index % job_count) *
                                                    group_count_ / job_count);
  std::uint32_t idle_visits = 0;
  std::uint32_t idle_laps = 0;
  while (groups_finished_.load(std::memory_order_acquire) < group_count_) {
    const BatchResult result = TryRunBatch(groups_[cursor], job);
    if (result == BatchResult::kRan) {
      idle_visits = idle_laps = 0;
      continue;
    }
    cursor = cursor + 1 == group_count_ ? 0 : cursor + 1;
    if (++idle_visits < group_count_) continue;
    // A full lap with nothing to take: only rounds other running jobs hold are left, and they end soon,
    // unless the thread holding one was preempted; then give it the core instead of spinning on.
    idle_visits = 0;
    if (++idle_laps < kSpinsBeforeYield)
      CpuRelax();
    else
      std::this_thread::yield();
  }
}

std::size_t IslandSolver::arena_bytes() const {
  std::size_t total = 0;
  for (const JobState& job : jobs_) total += job.arena.bytes_in_use();
  return total;
}

float IslandSolver::deepest_penetration() const {
  float deepest = 0.0f;
  for (const JobState& job : jobs_) deepest = std::min(deepest, job.deepest);
  return deepest;
}

std::uint32_t IslandSolver::direct_island_count() const {
  return static_cast<std::uint32_t>(std::count(island_direct_.begin(), island_direct_.end(), 1));
}

std::uint32_t IslandSolver::merged_group_count() const {
  std::uint32_t merged = 0;
  for (std::uint32_t i = 0; i < group_count_; ++i)
    merged += groups_[i].end_island - groups_[i].first_island > 1;
  return merged;
}

std::uint32_t IslandSolver::max_split_count() const {
  std::uint32_t most = 0;
  for (std::uint32_t i = 0; i < group_count_; ++i) most = std::max(most, groups_[i].splits.split_count);
  return most;
}

}  // namespace strata
