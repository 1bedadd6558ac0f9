#include "physics/core/JobGraph.h"

#include <algorithm>
#include <cassert>
#include <chrono>

#include "physics/core/Atomics.h"

namespace strata {

namespace {
constexpr std::uint32_t kJobBits = 20;
constexpr std::uint32_t kJobMask = (1u << kJobBits) - 1;
}  // namespace

JobGraph::StageId JobGraph::Add(const char* name, StageFunction function, void* context,
                                std::initializer_list<StageId> after) {
  const auto id = static_cast<StageId>(stages_.size());
  assert(id < (1u << (32 - kJobBits)));
  stages_.emplace_back(name, function, context);
  for (const StageId before : after) {
    assert(before < id);
    stages_[before].successors.push_back(id);
    ++stages_[id].dependency_count;
  }
  return id;
}

std::int64_t JobGraph::NowNs() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
             .count() -
         run_start_ns_;
}

void JobGraph::Release(StageId id) {
  Stage& stage = stages_[id];
  const std::uint32_t width = std::min(stage.width.load(std::memory_order_relaxed), kJobMask + 1);
  stage.last_width = width;
  stage.unfinished_jobs.store(width, std::memory_order_relaxed);
  for (std::uint32_t job = 0; job < width; ++job)
    queue_->Push({&JobGraph::RunJob, this, (id << kJobBits) | job});
}

void JobGraph::RunJob(void* graph, std::uint32_t packed) {
  auto& self = *static_cast<JobGraph*>(graph);
  const StageId id = packed >> kJobBits;
  Stage& stage = self.stages_[id];
  if (self.timed_) {
    const std::int64_t start = self.NowNs();
    stage.function(stage.context, packed & kJobMask, stage.last_width);
    const std::int64_t end = self.NowNs();
    AtomicMin(stage.start_ns, start);
    AtomicMax(stage.end_ns, end);
    stage.busy_ns.fetch_add(end - start, std::memory_order_relaxed);
  } else {
    stage.function(stage.context, packed & kJobMask, stage.last_width);
  }
  // acq_rel: the stages released below see everything every job of this stage wrote.
  if (stage.unfinished_jobs.fetch_sub(1, std::memory_order_acq_rel) != 1) return;
  for (const StageId next : stage.successors)
    if (self.stages_[next].waiting_for.fetch_sub(1, std::memory_order_acq_rel) == 1) self.Release(next);
}

void JobGraph::Run(JobSystem& jobs) {
  run_start_ns_ = 0;
  if (timed_) run_start_ns_ = NowNs();
  if (jobs.ThreadCount() <= 1) {
    RunInOrder();
    return;
  }
  for (Stage& stage : stages_) {
    stage.waiting_for.store(stage.dependency_count, std::memory_order_relaxed);
    stage.start_ns.store(timed_ ? INT64_MAX : 0, std::memory_order_relaxed);
    stage.end_ns.store(0, std::memory_order_relaxed);
    stage.busy_ns.store(0, std::memory_order_relaxed);
  }
  jobs.Run(
      [](void* graph, JobQueue& queue) {
        auto& self = *static_cast<JobGraph*>(graph);
        self.queue_ = &queue;
        for (StageId id = 0; id < self.stages_.size(); ++id)
          if (self.stages_[id].dependency_count == 0) self.Release(id);
      },
      this);
  queue_ = nullptr;
}

void JobGraph::RunInOrder() {
  // Stages were added after the stages they wait for, so index order is a valid order; with one thread a
  // queue would only add a push and a pop per job (a small world's step is mostly such overhead).
  for (Stage& stage : stages_) {
    const std::uint32_t width = std::min(stage.width.load(std::memory_order_relaxed), kJobMask + 1);
    stage.last_width = width;
    if (!timed_) {
      for (std::uint32_t job = 0; job < width; ++job) stage.function(stage.context, job, width);
      continue;
    }
    const std::int64_t start = NowNs();
    for (std::uint32_t job = 0; job < width; ++job) stage.function(stage.context, job, width);
    const std::int64_t end = NowNs();
    stage.start_ns.store(start, std::memory_order_relaxed);
    stage.end_ns.store(end, std::memory_order_relaxed);
    stage.busy_ns.store(end - start, std::memory_order_relaxed);
  }
}

StageTiming JobGraph::timing(StageId id) const {
  const Stage& stage = stages_[id];
  StageTiming timing;
  timing.name = stage.name;
  timing.width = stage.last_width;
  timing.parallel = stage.parallel;
  const std::int64_t start = stage.start_ns.load(std::memory_order_relaxed);
  if (start == INT64_MAX) return timing;
  timing.start_ms = 1e-6 * static_cast<double>(start);
  timing.end_ms = 1e-6 * static_cast<double>(stage.end_ns.load(std::memory_order_relaxed));
  timing.busy_ms = 1e-6 * static_cast<double>(stage.busy_ns.load(std::memory_order_relaxed));
  return timing;
}

}  // namespace strata
