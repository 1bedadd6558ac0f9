// JobGraph: a fixed set of named stages with dependencies, run on a JobSystem. A stage starts as soon as
// every stage it waits for has finished (no global barrier), as `width` jobs that run in parallel; its last
// job to finish releases the stages that wait for it. Built once, then Run any number of times with no
// allocation. Build it from one thread; one Run at a time; stage functions run on any worker.
#pragma once

#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "physics/core/JobSystem.h"

namespace strata {

/// Wall-clock figures of one stage in the last Run (ms since the Run began), for profiles.
struct StageTiming {
  const char* name = "";
  double start_ms = 0.0;  ///< first job started
  double end_ms = 0.0;    ///< last job finished
  double busy_ms = 0.0;   ///< summed over the stage's jobs
  std::uint32_t width = 0;
  bool parallel = false;  ///< may run as more than one job (see JobGraph::SetWidth)
};

/// Stages with dependencies; each stage runs as `width` jobs.
class JobGraph {
 public:
  /// `function(context, job, width)` runs once for each job in [0, width).
  using StageFunction = void (*)(void* context, std::uint32_t job, std::uint32_t width);
  using StageId = std::uint32_t;

  /// Adds a stage that starts after every stage in `after` (ids from earlier Add calls).
  StageId Add(const char* name, StageFunction function, void* context,
              std::initializer_list<StageId> after = {});

  /// Makes `stage` a parallel stage and sets how many jobs it runs as (at least 1). Set it before Run, or
  /// from a stage that `stage` waits for: the width is read when the stage becomes ready. A stage that never
  /// gets a width is serial: one job.
  void SetWidth(StageId stage, std::uint32_t width) {
    stages_[stage].parallel = true;
    stages_[stage].width.store(width == 0 ? 1 : width, std::memory_order_relaxed);
  }

  /// Runs every stage once, each after the stages it waits for; returns when all are done. With a one-thread
  /// job system the stages run in the order they were added, on the calling thread.
  void Run(JobSystem& jobs);

  std::size_t stage_count() const { return stages_.size(); }
  /// Whether Run times each job (two clock reads a job); untimed, timing() reports zeros.
  void set_timed(bool timed) {
    timed_ = timed;
    for (Stage& stage : stages_) {
      stage.start_ns.store(0, std::memory_order_relaxed);
      stage.end_ns.store(0, std::memory_order_relaxed);
      stage.busy_ns.store(0, std::memory_order_relaxed);
    }
  }
  bool timed() const { return timed_; }
  /// Figures of the last Run.
  StageTiming timing(StageId stage) const;

 private:
  struct Stage {
    const char* name;
    StageFunction function;
    void* context;
    std::vector<StageId> successors;
    int dependency_count = 0;
    std::atomic<int> waiting_for{0};
    std::atomic<std::uint32_t> width{1};
    std::atomic<std::uint32_t> unfinished_jobs{0};
    std::atomic<std::int64_t> start_ns{0};
    std::atomic<std::int64_t> end_ns{0};
    std::atomic<std::int64_t> busy_ns{0};
    std::uint32_t last_width = 0;
    bool parallel = false;

    Stage(const char* n, StageFunction f, void* c) : name(n), function(f), context(c) {}
    // Only for building the graph (vector growth); atomics carry no run state yet except the width.
    Stage(Stage&& other) noexcept
        : name(other.name),
          function(other.function),
          context(other.context),
          successors(std::move(other.successors)),
          dependency_count(other.dependency_count),
          width(other.width.load(std::memory_order_relaxed)),
          parallel(other.parallel) {}
  };

  static void RunJob(void* graph, std::uint32_t packed);
  void RunInOrder();
  void Release(StageId stage);
  std::int64_t NowNs() const;

  std::vector<Stage> stages_;
  JobQueue* queue_ = nullptr;  // the queue of the Run in progress
  std::int64_t run_start_ns_ = 0;
  bool timed_ = true;
};

}  // namespace strata
