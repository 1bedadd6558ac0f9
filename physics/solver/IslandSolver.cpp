#include "physics/solver/IslandSolver.h"

#include <algorithm>
#include <thread>

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
  const IslandBuilder& islands = *input.islands;
  const std::uint32_t island_count = islands.island_count();
  ordered_.resize(input.constraints.size());
  body_masks_.resize(input.solver_body_count);
  // Groups: a large island alone, or consecutive small islands until they hold kGroupConstraints.
  auto form_groups = [&](auto&& add) {
    std::uint32_t island = 0;
    while (island < island_count) {
      const std::uint32_t first = island;
      if (islands.constraint_count(island, island + 1) >= LargeIslandSplitter::kMinConstraintsToSplit) {
        add(first, ++island);
        continue;
      }
      std::uint32_t total = 0;
      while (island < island_count && total < kGroupConstraints &&
             islands.constraint_count(island, island + 1) < LargeIslandSplitter::kMinConstraintsToSplit)
        total += islands.constraint_count(island, island + 1), ++island;
      add(first, island);
    }
  };
  std::uint32_t count = 0;
  form_groups([&](std::uint32_t, std::uint32_t) { ++count; });
  if (count > group_capacity_) {
    group_capacity_ = count;
    groups_ = std::make_unique<Group[]>(group_capacity_);
  }
  group_count_ = 0;
  form_groups([&](std::uint32_t first, std::uint32_t end) { AddGroup(first, end); });
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
    job.arena.Reset();
    job.split_of.reserve(largest);
    job.scratch.reserve(largest);
    job.deepest = 0.0f;
  }
}

void IslandSolver::AddGroup(std::uint32_t first_island, std::uint32_t end_island) {
  Group& group = groups_[group_count_++];
  group.first_island = first_island;
  group.end_island = end_island;
  group.first_constraint = input_.islands->constraint_offset(first_island);
}

void IslandSolver::PrepareGroup(std::uint32_t group_index, std::uint32_t job_index) {
  Group& group = groups_[group_index];
  const IslandBuilder& islands = *input_.islands;
  const std::uint32_t constraint_count = islands.constraint_count(group.first_island, group.end_island);
  const std::span<ContactConstraint*> ordered =
      std::span(ordered_).subspan(group.first_constraint, constraint_count);
  std::size_t k = 0;
  for (std::uint32_t island = group.first_island; island < group.end_island; ++island)
    for (const std::uint32_t index : islands.constraints(island)) ordered[k++] = input_.constraints[index];

  JobState& job = jobs_[job_index];
  for (const std::uint32_t body : islands.bodies(group.first_island, group.end_island))
    body_masks_[body + 1] = 0;
  group.splits = LargeIslandSplitter::Split(ordered, body_masks_.data(), job.split_of, job.scratch);
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
  group.has_bounce = std::any_of(ordered.begin(), ordered.end(),
                                 [](const ContactConstraint* c) { return c->bounce_shift > 0.0f; });
  const auto velocity = static_cast<std::uint32_t>(input_.settings->velocity_iterations);
  const auto position = static_cast<std::uint32_t>(input_.settings->position_iterations);
  group.round_count =
      1 + splits + velocity * splits + 1 + (group.has_bounce ? splits : 0) + position * splits;
  group.processed.store(0, std::memory_order_relaxed);
  group.status.store(0, std::memory_order_release);
}

IslandSolver::Round IslandSolver::Describe(const Group& split, std::uint32_t round) const {
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

std::uint32_t IslandSolver::RoundItems(const Group& split, const Round& round) const {
  switch (round.kind) {
    case RoundKind::kSetup:
      return split.bundle_count + (split.sequential_count > 0 ? 1 : 0);
    case RoundKind::kIntegrate:
      return static_cast<std::uint32_t>(input_.islands->bodies(split.first_island, split.end_island).size());
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

void IslandSolver::RunBatch(Group& split, const Round& round, std::uint32_t begin, std::uint32_t end,
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
    const std::span<const std::uint32_t> island_bodies =
        input_.islands->bodies(split.first_island, split.end_island);
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
        deepest = std::min(deepest, SolveBundlePosition(bundle, poses, settings));
        break;
      default:
        break;
    }
  }
  if (round.kind == RoundKind::kPosition && last_position_pass) job.deepest = std::min(job.deepest, deepest);
}

IslandSolver::BatchResult IslandSolver::TryRunBatch(Group& group, JobState& job) {
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
    const std::uint32_t batch = round.kind == RoundKind::kIntegrate ? kBodyBatch : kBundleBatch;
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
