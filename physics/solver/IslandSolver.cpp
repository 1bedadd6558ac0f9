#include "physics/solver/IslandSolver.h"

#include <algorithm>

#include "physics/core/Atomics.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace strata {

namespace {

constexpr std::uint32_t kNotLarge = 0xffffffffu;
constexpr std::uint32_t kBundleBatch = 16 / ContactBundle::kLanes;  // sixteen constraints
constexpr std::uint32_t kBodyBatch = 64;

void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

}  // namespace

void IslandSolver::BeginStep(const Input& input, std::uint32_t job_count) {
  input_ = input;
  const IslandBuilder& islands = *input.islands;
  const std::uint32_t island_count = islands.island_count();
  ordered_.resize(input.constraints.size());
  body_masks_.resize(input.solver_body_count);
  large_of_island_.assign(island_count, kNotLarge);
  small_islands_.clear();
  large_count_ = 0;
  for (std::uint32_t island = 0; island < island_count; ++island) {
    if (islands.constraints(island).size() >= LargeIslandSplitter::kMinConstraintsToSplit)
      large_of_island_[island] = large_count_++;
    else
      small_islands_.push_back(island);
  }
  if (large_count_ > large_capacity_) {
    large_capacity_ = large_count_;
    large_ = std::make_unique<SplitIsland[]>(large_capacity_);
  }
  next_small_.store(0, std::memory_order_relaxed);
  large_finished_.store(0, std::memory_order_relaxed);
  if (jobs_.size() < job_count) jobs_.resize(job_count);
  for (JobState& job : jobs_) {
    job.arena.Reset();
    job.deepest = 0.0f;
  }
}

std::span<ContactConstraint*> IslandSolver::OrderedConstraints(std::uint32_t island) {
  return std::span(ordered_).subspan(input_.islands->constraint_offset(island),
                                     input_.islands->constraints(island).size());
}

void IslandSolver::PrepareIsland(std::uint32_t island, std::uint32_t job_index) {
  const std::span<const std::uint32_t> indices = input_.islands->constraints(island);
  const std::span<ContactConstraint*> ordered = OrderedConstraints(island);
  for (std::size_t k = 0; k < indices.size(); ++k) ordered[k] = input_.constraints[indices[k]];
  const std::uint32_t large_index = large_of_island_[island];
  if (large_index == kNotLarge) return;

  JobState& job = jobs_[job_index];
  for (const std::uint32_t body : input_.islands->bodies(island)) body_masks_[body + 1] = 0;
  SplitIsland& split = large_[large_index];
  split.island = island;
  split.splits = LargeIslandSplitter::Split(ordered, body_masks_.data(), job.split_of, job.scratch);
  const std::uint32_t splits = split.splits.split_count;
  const std::uint32_t parallel_splits = splits - (split.splits.last_is_sequential ? 1 : 0);
  // Bundles of consecutive constraints of a parallel split; set up later, in the setup round.
  split.bundle_count = 0;
  for (std::uint32_t s = 0; s < parallel_splits; ++s)
    split.bundle_count += (split.splits.begin[s + 1] - split.splits.begin[s] + ContactBundle::kLanes - 1) /
                          ContactBundle::kLanes;
  split.bundles = job.arena.AllocateArray<ContactBundle*>(split.bundle_count);
  std::uint32_t bundle = 0;
  for (std::uint32_t s = 0; s < parallel_splits; ++s) {
    split.bundle_begin[s] = bundle;
    for (std::uint32_t k = split.splits.begin[s]; k < split.splits.begin[s + 1]; k += ContactBundle::kLanes) {
      const std::uint32_t end = std::min(k + ContactBundle::kLanes, split.splits.begin[s + 1]);
      split.bundles[bundle++] = AllocateBundle(job.arena, ordered.subspan(k, end - k));
    }
  }
  split.bundle_begin[parallel_splits] = bundle;
  split.sequential_count = 0;
  if (split.splits.last_is_sequential) {
    split.sequential = ordered.data() + split.splits.begin[parallel_splits];
    split.sequential_count = split.splits.begin[splits] - split.splits.begin[parallel_splits];
    split.sequential_contacts = job.arena.AllocateArray<SolverContact*>(split.sequential_count);
  }
  split.has_bounce = std::any_of(ordered.begin(), ordered.end(),
                                 [](const ContactConstraint* c) { return c->bounce_shift > 0.0f; });
  const auto velocity = static_cast<std::uint32_t>(input_.settings->velocity_iterations);
  const auto position = static_cast<std::uint32_t>(input_.settings->position_iterations);
  split.round_count =
      1 + splits + velocity * splits + 1 + (split.has_bounce ? splits : 0) + position * splits;
  split.processed.store(0, std::memory_order_relaxed);
  split.status.store(0, std::memory_order_release);
}

IslandSolver::Round IslandSolver::Describe(const SplitIsland& split, std::uint32_t round) const {
  const std::uint32_t splits = split.splits.split_count;
  if (round == 0) return {RoundKind::kSetup, 0, 0};
  round -= 1;
  // Warm starting is a pass of its own (as in Jolt): folding it into each split's first velocity pass lets
  // the first splits solve against velocities that lack the later splits' warm impulses, and stacks sag.
  if (round < splits) return {RoundKind::kWarmStart, round, 0};
  round -= splits;
  const auto velocity = static_cast<std::uint32_t>(input_.settings->velocity_iterations);
  if (round < velocity * splits)
    return {RoundKind::kVelocity, round % splits, static_cast<int>(round / splits)};
  round -= velocity * splits;
  if (round == 0) return {RoundKind::kIntegrate, 0, 0};
  round -= 1;
  if (split.has_bounce) {
    if (round < splits) return {RoundKind::kBounce, round, 0};
    round -= splits;
  }
  return {RoundKind::kPosition, round % splits, static_cast<int>(round / splits)};
}

std::uint32_t IslandSolver::RoundItems(const SplitIsland& split, const Round& round) const {
  switch (round.kind) {
    case RoundKind::kSetup:
      return split.bundle_count + (split.sequential_count > 0 ? 1 : 0);
    case RoundKind::kIntegrate:
      return static_cast<std::uint32_t>(input_.islands->bodies(split.island).size());
    default:
      // The sequential split is one item: its constraints share bodies, so one thread takes them in order.
      return IsSequential(split, round.split)
                 ? 1
                 : split.bundle_begin[round.split + 1] - split.bundle_begin[round.split];
  }
}

void IslandSolver::Integrate(std::uint32_t island_body) const {
  const std::uint32_t index = island_body + 1;
  const SolverBody& body = input_.bodies[index];
  // Kinematic bodies were moved before the solve began (position passes read their final pose).
  if (body.inverse_mass <= 0.0f) return;
  SolverPose& pose = input_.poses[index];
  const float dt = input_.dt;
  pose.center_of_mass += body.linear_velocity * dt;
  const Vec4 turn = body.angular_velocity * dt;
  const Quat delta(0.0f, 0.5f * turn.x(), 0.5f * turn.y(), 0.5f * turn.z());
  pose.rotation.coeffs() += (delta * pose.rotation).coeffs();
  pose.rotation.normalize();
}

void IslandSolver::SolveSmallIsland(std::uint32_t island, JobState& job) {
  const PhysicsSettings& settings = *input_.settings;
  const std::span<ContactConstraint*> constraints = OrderedConstraints(island);
  SolverBody* bodies = input_.bodies;
  SolverContact** contacts = job.arena.AllocateArray<SolverContact*>(constraints.size());
  for (std::size_t k = 0; k < constraints.size(); ++k)
    contacts[k] = SetupSolverContact(job.arena, *constraints[k], bodies);
  const std::span<SolverContact*> set_up(contacts, constraints.size());
  for (const SolverContact* c : set_up) WarmStartContact(*c, bodies);
  for (int pass = 0; pass < settings.velocity_iterations; ++pass)
    for (SolverContact* c : set_up) SolveContactVelocity(*c, bodies, (pass & 1) != 0);
  for (const SolverContact* c : set_up) StoreContactImpulses(*c);
  for (const std::uint32_t body : input_.islands->bodies(island)) Integrate(body);
  for (const ContactConstraint* c : constraints) ApplyContactBounceShift(*c, bodies, input_.poses);
  for (int pass = 0; pass < settings.position_iterations; ++pass) {
    float deepest = 0.0f;
    for (const ContactConstraint* c : constraints)
      deepest = std::min(deepest, SolveContactPosition(*c, bodies, input_.poses, settings));
    if (pass + 1 == settings.position_iterations) job.deepest = std::min(job.deepest, deepest);
  }
}

void IslandSolver::RunBatch(SplitIsland& split, const Round& round, std::uint32_t begin, std::uint32_t end,
                            JobState& job) {
  const PhysicsSettings& settings = *input_.settings;
  SolverBody* bodies = input_.bodies;
  SolverPose* poses = input_.poses;
  if (round.kind == RoundKind::kSetup) {
    for (std::uint32_t i = begin; i < end; ++i) {
      if (i < split.bundle_count) {
        SetupBundle(*split.bundles[i], bodies);
        continue;
      }
      for (std::uint32_t k = 0; k < split.sequential_count; ++k)
        split.sequential_contacts[k] = SetupSolverContact(job.arena, *split.sequential[k], bodies);
    }
    return;
  }
  if (round.kind == RoundKind::kIntegrate) {
    const std::span<const std::uint32_t> island_bodies = input_.islands->bodies(split.island);
    for (std::uint32_t i = begin; i < end; ++i) Integrate(island_bodies[i]);
    return;
  }
  const bool last_velocity_pass = round.iteration + 1 == settings.velocity_iterations;
  const bool last_position_pass = round.iteration + 1 == settings.position_iterations;
  const bool reverse = (round.iteration & 1) != 0;
  if (IsSequential(split, round.split)) {
    const std::span<SolverContact*> contacts(split.sequential_contacts, split.sequential_count);
    const std::span<ContactConstraint* const> constraints(split.sequential, split.sequential_count);
    float deepest = 0.0f;
    switch (round.kind) {
      case RoundKind::kWarmStart:
        for (const SolverContact* c : contacts) WarmStartContact(*c, bodies);
        break;
      case RoundKind::kVelocity:
        for (SolverContact* c : contacts) SolveContactVelocity(*c, bodies, reverse);
        if (last_velocity_pass)
          for (const SolverContact* c : contacts) StoreContactImpulses(*c);
        break;
      case RoundKind::kBounce:
        for (const ContactConstraint* c : constraints) ApplyContactBounceShift(*c, bodies, poses);
        break;
      case RoundKind::kPosition:
        for (const ContactConstraint* c : constraints)
          deepest = std::min(deepest, SolveContactPosition(*c, bodies, poses, settings));
        if (last_position_pass) job.deepest = std::min(job.deepest, deepest);
        break;
      default:
        break;
    }
    return;
  }
  ContactBundle* const* bundles = split.bundles + split.bundle_begin[round.split];
  float deepest = 0.0f;
  for (std::uint32_t i = begin; i < end; ++i) {
    ContactBundle& bundle = *bundles[i];
    switch (round.kind) {
      case RoundKind::kWarmStart:
        WarmStartBundle(bundle, bodies);
        break;
      case RoundKind::kVelocity:
        SolveBundleVelocity(bundle, bodies, reverse);
        if (last_velocity_pass) StoreBundleImpulses(bundle);
        break;
      case RoundKind::kBounce:
        for (const ContactConstraint* c : bundle.constraints)
          if (c != nullptr) ApplyContactBounceShift(*c, bodies, poses);
        break;
      case RoundKind::kPosition:
        deepest = std::min(deepest, SolveBundlePosition(bundle, bodies, poses, settings));
        break;
      default:
        break;
    }
  }
  if (round.kind == RoundKind::kPosition && last_position_pass) job.deepest = std::min(job.deepest, deepest);
}

bool IslandSolver::TryRunBatch(SplitIsland& split, JobState& job) {
  std::uint64_t status = split.status.load(std::memory_order_acquire);
  while (true) {
    const auto round_index = static_cast<std::uint32_t>(status >> 32);
    if (round_index >= split.round_count) return false;
    const Round round = Describe(split, round_index);
    const std::uint32_t items = RoundItems(split, round);
    const auto item = static_cast<std::uint32_t>(status);
    if (item >= items) return false;  // every batch of this round is taken; wait for the round to end
    const std::uint32_t batch = round.kind == RoundKind::kIntegrate ? kBodyBatch : kBundleBatch;
    const std::uint32_t take = std::min(batch, items - item);
    if (!split.status.compare_exchange_weak(status, status + take, std::memory_order_acquire,
                                            std::memory_order_acquire))
      continue;
    RunBatch(split, round, item, item + take, job);
    // The last batch of a round opens the next one; the release publishes every batch's writes to it.
    if (split.processed.fetch_add(take, std::memory_order_acq_rel) + take == items) {
      split.processed.store(0, std::memory_order_relaxed);
      const std::uint32_t next = round_index + 1;
      split.status.store(static_cast<std::uint64_t>(next) << 32, std::memory_order_release);
      if (next == split.round_count) large_finished_.fetch_add(1, std::memory_order_release);
    }
    return true;
  }
}

void IslandSolver::SolveJob(std::uint32_t job_index) {
  JobState& job = jobs_[job_index];
  const auto small_count = static_cast<std::uint32_t>(small_islands_.size());
  while (true) {
    bool worked = false;
    for (std::uint32_t i = 0; i < large_count_ && !worked; ++i) worked = TryRunBatch(large_[i], job);
    if (worked) continue;
    const std::uint32_t next = next_small_.load(std::memory_order_relaxed) < small_count
                                   ? next_small_.fetch_add(1, std::memory_order_relaxed)
                                   : small_count;
    if (next < small_count) {
      SolveSmallIsland(small_islands_[next], job);
      continue;
    }
    if (large_finished_.load(std::memory_order_acquire) == large_count_) return;
    // Only batches other running jobs have claimed are left: their rounds end soon.
    CpuRelax();
  }
}

float IslandSolver::deepest_penetration() const {
  float deepest = 0.0f;
  for (const JobState& job : jobs_) deepest = std::min(deepest, job.deepest);
  return deepest;
}

std::uint32_t IslandSolver::max_split_count() const {
  std::uint32_t most = 0;
  for (std::uint32_t i = 0; i < large_count_; ++i) most = std::max(most, large_[i].splits.split_count);
  return most;
}

}  // namespace strata
