#include "physics/solver/ConstraintSolver.h"

#include <algorithm>
#include <cassert>
#include <thread>

#include "physics/body/BodyMotion.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace strata {

namespace {

// Items of a split claimed at once, at least: a kind's item is a bundle of contacts (two make about sixteen)
// or a whole sequential split.
constexpr std::uint32_t kConstraintBatch = 2;
// Claims a job makes of a round, about: every claim is a locked operation on a line all the jobs share, and a
// round ends at a barrier, so few jobs take larger batches and many take smaller ones to share the work out.
constexpr std::uint32_t kClaimsPerJob = 2;
constexpr std::uint32_t kBodyBatch = 64;
// A group of at most 1 / kGroupsPerJob of one job's share of the step's work runs on one job: the jobs then
// end within about that much of each other.
constexpr std::uint64_t kGroupsPerJob = 4;
// Idle laps (a pause each, about a microsecond in all) before a waiting job yields its core.
constexpr std::uint32_t kSpinsBeforeYield = 64;

void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

}  // namespace

ConstraintSolver::ConstraintSolver(BlockPool& pool, std::initializer_list<ConstraintKind*> kinds)
    : pool_(pool) {
  assert(kinds.size() <= kMaxKinds);
  for (ConstraintKind* kind : kinds) kinds_[kind_count_++] = kind;
}

void ConstraintSolver::ResetBodies(std::uint32_t active_count) {
  bodies_.resize(active_count + 1);
  poses_.resize(active_count + 1);
  velocity_steps_.resize(active_count + 1);
  start_rotations_.resize(active_count + 1);
  bodies_[0] = SolverBody();
  poses_[0] = SolverPose();
  velocity_steps_[0] = SolverVelocityStep();
  start_rotations_[0] = Mat3::Identity();
}

void ConstraintSolver::BeginStep(const Input& input, std::uint32_t job_count) {
  input_ = input;
  substep_dt_ = input.dt / static_cast<float>(input.settings->substeps);
  SolverStep step;
  step.islands = input.islands;
  step.bodies = bodies_.data();
  step.poses = poses_.data();
  step.solver_body_count = static_cast<std::uint32_t>(bodies_.size());
  step.dt = input.dt;
  step.substep_dt = substep_dt_;
  step.settings = input.settings;
  for (std::uint32_t u = 0; u < kind_count_; ++u) kinds_[u]->BeginStep(step, job_count);
  // An island is exact when every kind with work in it wants that (contacts of a resting pile; joints never).
  const std::uint32_t island_count = input.islands->island_count();
  island_exact_.resize(island_count);
  island_work_.resize(island_count);
  island_kinds_.resize(island_count);
  for (std::uint32_t island = 0; island < island_count; ++island) {
    std::uint32_t work = 0;
    std::uint8_t kinds = 0;
    bool exact = false;
    for (std::uint32_t u = 0; u < kind_count_; ++u) {
      const std::uint32_t kind_work = kinds_[u]->IslandWork(island);
      if (kind_work == 0) continue;
      exact = (work == 0 || exact) && kinds_[u]->WantsExactIsland(island);
      work += kind_work;
      ++kinds;
    }
    island_work_[island] = work;
    island_kinds_[island] = kinds;
    island_exact_[island] = exact ? 1 : 0;
  }
  FormGroups();
  for (std::uint32_t u = 0; u < kind_count_; ++u) kinds_[u]->BeginGroups(group_islands_);
  groups_finished_.store(0, std::memory_order_relaxed);
  if (jobs_.size() < job_count) {
    jobs_.resize(job_count);
    for (JobState& job : jobs_) job.arena.SetPool(pool_);
  }
  for (JobState& job : jobs_) job.arena.Recycle();
}

void ConstraintSolver::FormGroups() {
  // Groups: a large island alone, or consecutive small islands of one kind (exact or not) until they hold
  // kGroupWork. Work counts every kind's constraints (joint-only islands, ragdolls in flight, must not all
  // gather in one group).
  const std::uint32_t island_count = input_.islands->island_count();
  auto work = [&](std::uint32_t island) { return island_work_[island]; };
  auto form_groups = [&](auto&& add) {
    std::uint32_t island = 0;
    while (island < island_count) {
      const std::uint32_t first = island;
      if (work(island) >= LargeIslandSplitter::kMinConstraintsToSplit) {
        add(first, ++island, false);
        continue;
      }
      const bool exact = island_exact_[island] != 0;
      std::uint32_t total = 0;
      while (island < island_count && total < kGroupWork &&
             work(island) < LargeIslandSplitter::kMinConstraintsToSplit &&
             (island_exact_[island] != 0) == exact)
        total += work(island), ++island;
      add(first, island, exact);
    }
  };
  std::uint32_t count = 0;
  form_groups([&](std::uint32_t, std::uint32_t, bool) { ++count; });
  if (count > group_capacity_) {
    group_capacity_ = count;
    groups_ = std::make_unique<Group[]>(group_capacity_);
  }
  group_count_ = 0;
  group_islands_.clear();
  form_groups([&](std::uint32_t first, std::uint32_t end, bool exact) { AddGroup(first, end, exact); });
  total_work_ = 0;
  for (std::uint32_t g = 0; g < group_count_; ++g) {
    for (std::uint32_t island = groups_[g].islands.first_island; island < groups_[g].islands.end_island;
         ++island)
      groups_[g].work += work(island);
    total_work_ += groups_[g].work;
  }
}

void ConstraintSolver::AddGroup(std::uint32_t first_island, std::uint32_t end_island, bool exact) {
  Group& group = groups_[group_count_];
  // Both copies from the value in registers: re-reading group.islands whole right after its fields were
  // stored one by one stalls on the stores.
  const bool one_kind_per_island =
      std::all_of(island_kinds_.begin() + first_island, island_kinds_.begin() + end_island,
                  [](std::uint8_t kinds) { return kinds <= 1; });
  const SolverGroup islands{group_count_, first_island, end_island, exact, one_kind_per_island};
  group.islands = islands;
  group.work = 0;
  group_islands_.push_back(islands);
  ++group_count_;
}

void ConstraintSolver::PrepareGroup(std::uint32_t group_index, std::uint32_t job_index) {
  Group& group = groups_[group_index];
  const std::uint32_t bodies = static_cast<std::uint32_t>(
      input_.islands->bodies(group.islands.first_island, group.islands.end_island).size());
  const auto substeps = static_cast<std::uint32_t>(input_.settings->substeps);
  group.split_count = 0;
  group.bounces = group.positions = false;
  group.free = group.work == 0;
  if (group.free) {
    // Per substep its forces (but the first's) and its integration: the rounds of a group without splits.
    group.split_begin.fill(0);
    group.setup_begin.fill(0);
    group.round_count = 1 + 2 * substeps;
    group.one_job = bodies <= kBodyBatch;
  } else {
    bool parallel = false;
    for (std::uint32_t u = 0; u < kind_count_; ++u) {
      const GroupLayout layout = kinds_[u]->PrepareGroup(group.islands, jobs_[job_index].arena, job_index);
      group.split_begin[u] = group.split_count;
      group.split_count += layout.splits;
      group.setup_begin[u + 1] = group.setup_begin[u] + kinds_[u]->SetupItems(group_index);
      parallel = parallel || layout.parallel;
      group.bounces = group.bounces || layout.bounces;
      group.positions = group.positions || layout.positions;
    }
    group.split_begin[kind_count_] = group.split_count;
    const PhysicsSettings& settings = *input_.settings;
    const std::uint32_t per_substep =
        group.split_count *
            static_cast<std::uint32_t>(1 + settings.velocity_iterations + settings.relax_iterations) +
        2;
    group.round_count =
        1 + substeps * per_substep +
        (group.bounces ? group.split_count * static_cast<std::uint32_t>(settings.restitution_iterations)
                       : 0) +
        (group.positions ? group.split_count : 0);
    // Whole rounds and batches do the same work in the same order (RunRoundsInOrder), so which way a group
    // runs changes its time, never its result.
    const std::uint64_t share_of_a_job = total_work_ / (kGroupsPerJob * jobs_.size());
    group.one_job = (!parallel && bodies <= kBodyBatch) || group.work <= share_of_a_job;
  }
  group.processed.store(0, std::memory_order_relaxed);
  group.status.store(0, std::memory_order_release);
}

void ConstraintSolver::RunFreeGroup(const Group& group) {
  const std::span<const std::uint32_t> bodies =
      input_.islands->bodies(group.islands.first_island, group.islands.end_island);
  for (int substep = 0; substep < input_.settings->substeps; ++substep) {
    if (substep > 0)
      for (const std::uint32_t body : bodies) AddForces(body);
    for (const std::uint32_t body : bodies) Integrate(body);
  }
}

ConstraintSolver::Round ConstraintSolver::Describe(const Group& group, std::uint32_t round) const {
  const std::uint32_t splits = group.split_count;
  if (round == 0) return {RoundKind::kSetup};
  round -= 1;
  const PhysicsSettings& settings = *input_.settings;
  const auto velocity = static_cast<std::uint32_t>(settings.velocity_iterations);
  const auto relax = static_cast<std::uint32_t>(settings.relax_iterations);
  const std::uint32_t per_substep = splits * (1 + velocity + relax) + 2;
  const auto substeps = static_cast<std::uint32_t>(settings.substeps);
  if (round >= substeps * per_substep) {
    round -= substeps * per_substep;
    // Bounces first, then positions: a position step after them keeps what they push apart.
    const std::uint32_t restitution =
        group.bounces ? splits * static_cast<std::uint32_t>(settings.restitution_iterations) : 0;
    if (round >= restitution) return {RoundKind::kPositions, round - restitution};
    return {RoundKind::kRestitution, round % splits, static_cast<int>(round / splits)};
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

bool ConstraintSolver::IsLastSolvePass(const Round& round) const {
  const PhysicsSettings& settings = *input_.settings;
  if (round.substep + 1 != settings.substeps) return false;
  if (settings.relax_iterations > 0)
    return round.kind == RoundKind::kRelax && round.iteration + 1 == settings.relax_iterations;
  return round.kind == RoundKind::kVelocity && round.iteration + 1 == settings.velocity_iterations;
}

std::uint32_t ConstraintSolver::KindOf(const Group& group, std::uint32_t split) const {
  std::uint32_t kind = 0;
  while (split >= group.split_begin[kind + 1]) ++kind;
  return kind;
}

SolverPass ConstraintSolver::PassFor(const Group& group, const Round& round, std::uint32_t kind) const {
  SolverPass pass;
  pass.split = round.split - group.split_begin[kind];
  pass.iteration = round.iteration;
  pass.substep = round.substep;
  const int relax = round.kind == RoundKind::kRelax ? 1 : 0;
  // Velocity passes see the poses at the substep's start, relax passes those after its integration, the
  // rounds after the last substep the step's end.
  pass.elapsed = substep_dt_ * static_cast<float>(round.substep + relax);
  pass.pose_version = round.substep + relax;
  // Alternate the order constraints are visited in from pass to pass (and substep to substep), so a stack
  // does not lean towards the side solved first and a chain carries its load both ways.
  pass.reverse = ((round.iteration + round.substep + relax) & 1) != 0;
  pass.last_solve_pass = IsLastSolvePass(round);
  const int restitution_iterations = input_.settings->restitution_iterations;
  switch (round.kind) {
    case RoundKind::kWarmStart:
      pass.kind = SolverPassKind::kWarmStart;
      break;
    case RoundKind::kVelocity:
      pass.kind = SolverPassKind::kVelocity;
      break;
    case RoundKind::kRelax:
      pass.kind = SolverPassKind::kRelax;
      break;
    case RoundKind::kRestitution:
      pass.kind = SolverPassKind::kRestitution;
      pass.elapsed = input_.dt;
      pass.pose_version = input_.settings->substeps;
      break;
    default:
      pass.kind = SolverPassKind::kPositions;
      pass.elapsed = input_.dt;
      pass.pose_version = input_.settings->substeps;
      break;
  }
  // The impulses a next step warm-starts from are those after restitution, where there is one.
  pass.keeps_impulses =
      group.bounces ? round.kind == RoundKind::kRestitution && round.iteration + 1 == restitution_iterations
                    : pass.last_solve_pass;
  return pass;
}

std::uint32_t ConstraintSolver::RoundItems(const Group& group, const Round& round) const {
  switch (round.kind) {
    case RoundKind::kSetup:
      return group.setup_begin[kind_count_];
    case RoundKind::kAddForces:
      // The first substep's share was added before the solve.
      if (round.substep == 0) return 0;
      [[fallthrough]];
    case RoundKind::kIntegrate:
      return static_cast<std::uint32_t>(
          input_.islands->bodies(group.islands.first_island, group.islands.end_island).size());
    default: {
      const std::uint32_t kind = KindOf(group, round.split);
      return kinds_[kind]->Items(group.islands.index, PassFor(group, round, kind));
    }
  }
}

void ConstraintSolver::Integrate(std::uint32_t island_body) {
  const std::uint32_t index = island_body + 1;
  // Kinematic bodies were moved before the solve began; contacts follow them by their velocity.
  if (bodies_[index].inverse_mass <= 0.0f) return;
  IntegrateSubstep(bodies_[index], poses_[index], substep_dt_);
}

void ConstraintSolver::AddForces(std::uint32_t island_body) {
  const std::uint32_t index = island_body + 1;
  AddSubstepForces(bodies_[index], velocity_steps_[index], poses_[index].rotation, substep_dt_);
}

void ConstraintSolver::RunSetup(Group& group, std::uint32_t begin, std::uint32_t end, JobState& job) {
  for (std::uint32_t u = 0; u < kind_count_ && begin < end; ++u) {
    const std::uint32_t first = group.setup_begin[u], last = group.setup_begin[u + 1];
    if (begin >= last) continue;
    const std::uint32_t until = std::min(end, last);
    kinds_[u]->Setup(group.islands.index, begin - first, until - first, job.arena);
    begin = until;
  }
}

void ConstraintSolver::RunBatch(Group& group, const Round& round, std::uint32_t begin, std::uint32_t end,
                                JobState& job, std::uint32_t job_index) {
  if (round.kind == RoundKind::kSetup) {
    RunSetup(group, begin, end, job);
    return;
  }
  if (round.kind == RoundKind::kIntegrate || round.kind == RoundKind::kAddForces) {
    const std::span<const std::uint32_t> bodies =
        input_.islands->bodies(group.islands.first_island, group.islands.end_island);
    if (round.kind == RoundKind::kIntegrate)
      for (std::uint32_t i = begin; i < end; ++i) Integrate(bodies[i]);
    else
      for (std::uint32_t i = begin; i < end; ++i) AddForces(bodies[i]);
    return;
  }
  const std::uint32_t kind = KindOf(group, round.split);
  kinds_[kind]->Run(group.islands.index, PassFor(group, round, kind), begin, end, job_index);
}

ConstraintSolver::BatchResult ConstraintSolver::TryRunWholeGroup(Group& group, JobState& job,
                                                                 std::uint32_t job_index) {
  std::uint64_t status = group.status.load(std::memory_order_acquire);
  const std::uint64_t done = static_cast<std::uint64_t>(group.round_count) << 32;
  if (status == done || !group.status.compare_exchange_strong(status, done, std::memory_order_acq_rel))
    return BatchResult::kDone;
  if (group.free)
    RunFreeGroup(group);  // the same work as its rounds, without describing each
  else
    RunRoundsInOrder(group, job, job_index);
  groups_finished_.fetch_add(1, std::memory_order_release);
  return BatchResult::kRan;
}

void ConstraintSolver::RunRoundsInOrder(Group& group, JobState& job, std::uint32_t job_index) {
  // The rounds Describe numbers, in its order, each whole, as single batches would have run them; walked
  // directly, since describing a round by its number takes integer divisions and a small island's step is
  // mostly such fixed costs.
  auto run = [&](const Round& round) {
    const std::uint32_t items = RoundItems(group, round);
    if (items > 0) RunBatch(group, round, 0, items, job, job_index);
  };
  // A constraint round's pass is described once, for its item count and its run.
  auto run_split = [&](RoundKind round_kind, std::uint32_t split, int iteration, int substep) {
    const Round round{round_kind, split, iteration, substep};
    const std::uint32_t kind = KindOf(group, split);
    const SolverPass pass = PassFor(group, round, kind);
    const std::uint32_t items = kinds_[kind]->Items(group.islands.index, pass);
    if (items > 0) kinds_[kind]->Run(group.islands.index, pass, 0, items, job_index);
  };
  const PhysicsSettings& settings = *input_.settings;
  const std::uint32_t splits = group.split_count;
  run({RoundKind::kSetup});
  for (int substep = 0; substep < settings.substeps; ++substep) {
    run({RoundKind::kAddForces, 0, 0, substep});
    for (std::uint32_t split = 0; split < splits; ++split)
      run_split(RoundKind::kWarmStart, split, 0, substep);
    for (int iteration = 0; iteration < settings.velocity_iterations; ++iteration)
      for (std::uint32_t split = 0; split < splits; ++split)
        run_split(RoundKind::kVelocity, split, iteration, substep);
    run({RoundKind::kIntegrate, 0, 0, substep});
    for (int iteration = 0; iteration < settings.relax_iterations; ++iteration)
      for (std::uint32_t split = 0; split < splits; ++split)
        run_split(RoundKind::kRelax, split, iteration, substep);
  }
  if (group.bounces)
    for (int iteration = 0; iteration < settings.restitution_iterations; ++iteration)
      for (std::uint32_t split = 0; split < splits; ++split)
        run_split(RoundKind::kRestitution, split, iteration, 0);
  if (group.positions)
    for (std::uint32_t split = 0; split < splits; ++split) run_split(RoundKind::kPositions, split, 0, 0);
}

ConstraintSolver::BatchResult ConstraintSolver::TryRunBatch(Group& group, JobState& job,
                                                            std::uint32_t job_index, std::uint32_t width) {
  if (group.one_job) return TryRunWholeGroup(group, job, job_index);
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
    const std::uint32_t batch =
        per_body ? kBodyBatch : std::max(kConstraintBatch, items / (kClaimsPerJob * width));
    const std::uint32_t take = std::min(batch, items - item);
    if (!group.status.compare_exchange_weak(status, status + take, std::memory_order_acquire,
                                            std::memory_order_acquire))
      continue;
    RunBatch(group, round, item, item + take, job, job_index);
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

void ConstraintSolver::SolveJob(std::uint32_t job_index, std::uint32_t width) {
  JobState& job = jobs_[job_index];
  if (group_count_ == 0) return;
  if (width == 1) {
    // The rounds a job would take one batch at a time, without the claims: each is a locked operation,
    // and a small world's step has a few.
    for (std::uint32_t g = 0; g < group_count_; ++g) {
      if (groups_[g].free)
        RunFreeGroup(groups_[g]);
      else
        RunRoundsInOrder(groups_[g], job, job_index);
    }
    return;
  }
  // Jobs start spread over the groups and stay on a group while it has work, so they rarely meet.
  const auto job_count = static_cast<std::uint32_t>(jobs_.size());
  std::uint32_t cursor = static_cast<std::uint32_t>(static_cast<std::uint64_t>(job_index % job_count) *
                                                    group_count_ / job_count);
  std::uint32_t idle_visits = 0;
  std::uint32_t idle_laps = 0;
  while (groups_finished_.load(std::memory_order_acquire) < group_count_) {
    const BatchResult result = TryRunBatch(groups_[cursor], job, job_index, width);
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

std::size_t ConstraintSolver::arena_bytes() const {
  std::size_t total = 0;
  for (const JobState& job : jobs_) total += job.arena.bytes_in_use();
  return total;
}

std::uint32_t ConstraintSolver::exact_island_count() const {
  return static_cast<std::uint32_t>(std::count(island_exact_.begin(), island_exact_.end(), 1));
}

std::uint32_t ConstraintSolver::merged_group_count() const {
  std::uint32_t merged = 0;
  for (std::uint32_t i = 0; i < group_count_; ++i)
    merged += groups_[i].islands.end_island - groups_[i].islands.first_island > 1;
  return merged;
}

}  // namespace strata
