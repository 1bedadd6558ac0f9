#include "physics/constraints/ContactConstraintKind.h"

#include <algorithm>

namespace strata {

void ContactConstraintKind::BeginStep(const SolverStep& step, std::uint32_t job_count) {
  step_ = step;
  const PhysicsSettings& settings = *step.settings;
  const float h = step.substep_dt;
  // The springs and rates depend on the substep and three settings only: worked out again when one of them
  // changed (their divisions and square root were a fair share of a small world's step).
  const RateInputs inputs{h, settings.contact_hertz, settings.contact_damping_ratio, settings.gravity};
  if (!(inputs == rate_inputs_)) {
    rate_inputs_ = inputs;
    // Contacts stiffer than a quarter of the substep rate would ring; contacts with a fixed body may be
    // twice as stiff, since only one side moves.
    const float hertz = std::min(settings.contact_hertz, 0.25f / h);
    context_.between_moving = MakeSoftSpring(hertz, settings.contact_damping_ratio, h);
    context_.against_fixed = MakeSoftSpring(2.0f * hertz, settings.contact_damping_ratio, h);
    context_.inverse_h = 1.0f / h;
    const float gravity = settings.gravity.norm();
    context_.weight_per_impulse = gravity > 0.0f ? 1.0f / (gravity * h) : 0.0f;
  }
  context_.max_push_velocity = settings.contact_push_max_velocity;
  context_.restitution_threshold = settings.min_velocity_for_restitution;
  context_.elapsed = 0.0f;
  ordered_.resize(contacts_.size());
  body_masks_.resize(step.solver_body_count);
  if (jobs_.size() < job_count) jobs_.resize(job_count);
  for (JobScratch& job : jobs_) job.deepest = 0.0f;
}

std::uint32_t ContactConstraintKind::IslandWork(std::uint32_t island) const {
  return step_.islands->constraint_count(island, island + 1);
}

bool ContactConstraintKind::WantsExactIsland(std::uint32_t island) const {
  // Worth it where sequential passes fall short and affordable: bodies resting on each other (a single body
  // on the ground gains nothing), few points per body (a body on many mesh triangles has far more rows than
  // its six motions; they would make the solve cost the cube of that), and at rest (a landing pile changes
  // which rows push every pass, and moving piles show no sag).
  if (!step_.settings->exact_small_islands) return false;
  const IslandBuilder& islands = *step_.islands;
  const std::span<const std::uint32_t> bodies = islands.bodies(island, island + 1);
  // A load passes through a body only between two contacts; two bodies touching each other and nothing else
  // (spheres that met in flight) gain nothing from it either.
  if (bodies.size() < 2 || islands.constraint_count(island, island + 1) < 2) return false;
  std::uint32_t points = 0;
  for (const std::uint32_t index : islands.constraints(island)) points += contacts_[index]->point_count;
  if (points == 0 || points > ExactContactSolver::kMaxPoints ||
      points > kExactMaxPointsPerBody * bodies.size())
    return false;
  constexpr float kRest2 = kExactRestSpeed * kExactRestSpeed;
  return std::all_of(bodies.begin(), bodies.end(), [&](std::uint32_t body) {
    const SolverBody& b = step_.bodies[body + 1];
    return b.linear_velocity.squaredNorm() <= kRest2 && b.angular_velocity.squaredNorm() <= kRest2;
  });
}

void ContactConstraintKind::BeginGroups(std::span<const SolverGroup> groups) {
  const IslandBuilder& islands = *step_.islands;
  groups_.resize(groups.size());
  std::uint32_t largest = 0;
  for (const SolverGroup& g : groups) {
    Group& group = groups_[g.index];
    group.first_island = g.first_island;
    group.end_island = g.end_island;
    group.exact = g.exact;
    group.first_contact = islands.constraint_offset(g.first_island);
    // A group without constraints is never prepared: it must not show last step's layout.
    group.splits.SetSequential(0);
    group.bundle_count = 0;
    group.sequential_count = 0;
    largest = std::max(largest, islands.constraint_count(g.first_island, g.end_island));
  }
  // Any job may prepare any group: size every job's splitting buffers for the largest.
  for (JobScratch& job : jobs_) {
    job.split_of.reserve(largest);
    job.scratch.reserve(largest);
  }
}

GroupLayout ContactConstraintKind::PrepareGroup(const SolverGroup& solver_group, BlockArena& arena,
                                                std::uint32_t job_index) {
  Group& group = groups_[solver_group.index];
  const IslandBuilder& islands = *step_.islands;
  const std::uint32_t count = islands.constraint_count(group.first_island, group.end_island);
  const std::span<ContactConstraint*> ordered = std::span(ordered_).subspan(group.first_contact, count);
  std::size_t k = 0;
  for (std::uint32_t island = group.first_island; island < group.end_island; ++island)
    for (const std::uint32_t index : islands.constraints(island)) ordered[k++] = contacts_[index];

  // One sequential split in island order: for an exact group, whose islands' rows are solved together, and
  // for a group too small for any parallel split (the splitter would merge each into the sequential one).
  if (group.exact || count < LargeIslandSplitter::kMinSplitSize) {
    group.splits.SetSequential(count);
  } else {
    for (const std::uint32_t body : islands.bodies(group.first_island, group.end_island))
      body_masks_[body + 1] = 0;
    JobScratch& job = jobs_[job_index];
    group.splits = LargeIslandSplitter::Split(ordered, body_masks_.data(), job.split_of, job.scratch);
  }
  if (group.exact)
    group.exact_solvers = arena.AllocateArray<ExactContactSolver*>(group.end_island - group.first_island);
  const std::uint32_t splits = group.splits.split_count;
  const std::uint32_t parallel_splits = splits - (group.splits.last_is_sequential ? 1 : 0);
  // Bundles of consecutive contacts of a parallel split; set up later, in the setup round.
  group.bundle_count = 0;
  for (std::uint32_t s = 0; s < parallel_splits; ++s)
    group.bundle_count += (group.splits.begin[s + 1] - group.splits.begin[s] + ContactBundle::kLanes - 1) /
                          ContactBundle::kLanes;
  group.bundles = arena.AllocateArray<ContactBundle*>(group.bundle_count);
  std::uint32_t bundle = 0;
  for (std::uint32_t s = 0; s < parallel_splits; ++s) {
    group.bundle_begin[s] = bundle;
    for (std::uint32_t c = group.splits.begin[s]; c < group.splits.begin[s + 1]; c += ContactBundle::kLanes) {
      const std::uint32_t end = std::min<std::uint32_t>(c + ContactBundle::kLanes, group.splits.begin[s + 1]);
      group.bundles[bundle++] = AllocateBundle(arena, ordered.subspan(c, end - c));
    }
  }
  group.bundle_begin[parallel_splits] = bundle;
  for (std::uint32_t b = 0; b < group.bundle_count; ++b) AllocateReportedImpulses(arena, *group.bundles[b]);
  group.sequential_count = 0;
  if (group.splits.last_is_sequential) {
    group.sequential = ordered.data() + group.splits.begin[parallel_splits];
    group.sequential_count = group.splits.begin[splits] - group.splits.begin[parallel_splits];
    group.sequential_contacts = arena.AllocateArray<SolverContact*>(group.sequential_count);
  }
  const float threshold = -step_.settings->min_velocity_for_restitution;
  GroupLayout layout;
  layout.splits = splits;
  layout.parallel = group.bundle_count > 0;
  layout.bounces = std::any_of(ordered.begin(), ordered.end(), [&](const ContactConstraint* c) {
    if (c->restitution <= 0.0f) return false;
    const auto points = std::span(c->points(), c->point_count);
    return std::any_of(points.begin(), points.end(),
                       [&](const ContactConstraintPoint& p) { return p.normal_velocity < threshold; });
  });
  return layout;
}

std::uint32_t ContactConstraintKind::SetupItems(std::uint32_t group_index) const {
  const Group& group = groups_[group_index];
  return group.bundle_count + (group.sequential_count > 0 ? 1 : 0);
}

void ContactConstraintKind::Setup(std::uint32_t group_index, std::uint32_t begin, std::uint32_t end,
                                  BlockArena& arena) {
  Group& group = groups_[group_index];
  for (std::uint32_t i = begin; i < end; ++i) {
    if (i < group.bundle_count) {
      SetupBundle(*group.bundles[i], step_.bodies, context_);
      continue;
    }
    for (std::uint32_t k = 0; k < group.sequential_count; ++k)
      group.sequential_contacts[k] =
          SetupSolverContact(arena, *group.sequential[k], step_.bodies, context_, !group.exact);
    if (group.exact) SetupExactSolvers(group, arena);
  }
}

void ContactConstraintKind::SetupExactSolvers(Group& group, BlockArena& arena) {
  const IslandBuilder& islands = *step_.islands;
  std::uint32_t offset = 0;
  for (std::uint32_t island = group.first_island; island < group.end_island; ++island) {
    const std::uint32_t count = islands.constraint_count(island, island + 1);
    group.exact_solvers[island - group.first_island] = ExactContactSolver::Create(
        arena, std::span<SolverContact* const>(group.sequential_contacts + offset, count), step_.bodies,
        context_.weight_per_impulse);
    offset += count;
  }
}

std::uint32_t ContactConstraintKind::Items(std::uint32_t group_index, const SolverPass& pass) const {
  const Group& group = groups_[group_index];
  if (pass.kind == SolverPassKind::kPositions) return 0;  // contacts correct positions by their velocity
  // The sequential split is one item: its contacts share bodies, so one thread takes them in order.
  if (IsSequential(group, pass.split)) return 1;
  return group.bundle_begin[pass.split + 1] - group.bundle_begin[pass.split];
}

void ContactConstraintKind::Run(std::uint32_t group_index, const SolverPass& pass, std::uint32_t begin,
                                std::uint32_t end, std::uint32_t job) {
  Group& group = groups_[group_index];
  float deepest = 0.0f;
  float* const measure = pass.last_solve_pass ? &deepest : nullptr;
  if (IsSequential(group, pass.split))
    RunSequential(group, pass, measure);
  else
    RunBundles(group, pass, begin, end, measure);
  if (measure != nullptr) jobs_[job].deepest = std::min(jobs_[job].deepest, deepest);
}

void ContactConstraintKind::RunSequential(Group& group, const SolverPass& pass, float* deepest) {
  SubstepContext context = context_;
  context.elapsed = pass.elapsed;
  const bool use_bias = pass.kind == SolverPassKind::kVelocity;
  const std::span<SolverContact*> contacts(group.sequential_contacts, group.sequential_count);
  SolverBody* const bodies = step_.bodies;
  const bool solve = pass.kind == SolverPassKind::kVelocity || pass.kind == SolverPassKind::kRelax;
  // An exact group's contacts have no friction rows per point: its solvers warm start and solve them.
  if (group.exact && (solve || pass.kind == SolverPassKind::kWarmStart)) {
    for (std::uint32_t island = 0; island < group.end_island - group.first_island; ++island)
      if (solve)
        group.exact_solvers[island]->Solve(bodies, context, use_bias, deepest);
      else
        group.exact_solvers[island]->WarmStart(bodies);
    if (pass.kind == SolverPassKind::kWarmStart && pass.substep > 0)
      for (const SolverContact* c : contacts)
        if (c->reports) AddReportedImpulses(*c);
    if (pass.keeps_impulses)
      for (const SolverContact* c : contacts) StoreContactImpulses(*c);
    return;
  }
  for (SolverContact* c : contacts) {
    if (pass.kind == SolverPassKind::kWarmStart) {
      WarmStartContact(*c, bodies);
      // What the last substep ended with is applied again now: a substep's worth of impulse (see
      // AddReportedImpulses).
      if (c->reports && pass.substep > 0) AddReportedImpulses(*c);
    } else if (solve)
      SolveContactVelocity(*c, bodies, context, use_bias, pass.reverse, deepest);
    else if (pass.kind == SolverPassKind::kRestitution)
      ApplyContactRestitution(*c, bodies, context);
    if (pass.keeps_impulses) StoreContactImpulses(*c);
  }
}

void ContactConstraintKind::RunBundles(Group& group, const SolverPass& pass, std::uint32_t begin,
                                       std::uint32_t end, float* deepest) {
  SubstepContext context = context_;
  context.elapsed = pass.elapsed;
  const bool use_bias = pass.kind == SolverPassKind::kVelocity;
  SolverBody* const bodies = step_.bodies;
  ContactBundle* const* bundles = group.bundles + group.bundle_begin[pass.split];
  for (std::uint32_t i = begin; i < end; ++i) {
    ContactBundle& bundle = *bundles[i];
    switch (pass.kind) {
      case SolverPassKind::kWarmStart:
        WarmStartBundle(bundle, bodies);
        if (bundle.reports && pass.substep > 0) AddBundleReportedImpulses(bundle);
        break;
      case SolverPassKind::kVelocity:
      case SolverPassKind::kRelax:
        SolveBundleVelocity(bundle, bodies, context, use_bias, pass.reverse, deepest);
        break;
      case SolverPassKind::kRestitution:
        ApplyBundleRestitution(bundle, bodies, context);
        break;
      case SolverPassKind::kPositions:
        break;
    }
    if (pass.keeps_impulses) StoreBundleImpulses(bundle);
  }
}

float ContactConstraintKind::deepest_penetration() const {
  float deepest = 0.0f;
  for (const JobScratch& job : jobs_) deepest = std::min(deepest, job.deepest);
  return deepest;
}

std::uint32_t ContactConstraintKind::max_split_count() const {
  std::uint32_t most = 0;
  for (const Group& group : groups_) most = std::max(most, group.splits.split_count);
  return most;
}

}  // namespace strata
