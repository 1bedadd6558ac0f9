// JobSystem: the interface the physics step uses to spread work over threads. A game plugs in its own
// scheduler by implementing Run; Strata ships a oneTBB-backed default, a std::thread pool and a serial one.
// Run may be called from several threads at once (each call waits for its own jobs only); jobs run on any
// worker and may push more jobs. A job is a function pointer plus context, so queuing one allocates nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace strata {

/// One unit of work: `function(context, index)`.
struct Job {
  using Function = void (*)(void* context, std::uint32_t index);
  Function function = nullptr;
  void* context = nullptr;
  std::uint32_t index = 0;

  void operator()() const { function(context, index); }
};

/// Where the start function and running jobs of one JobSystem::Run put more work.
class JobQueue {
 public:
  /// Queues `job`; it runs on some thread of the job system before that Run returns.
  virtual void Push(const Job& job) = 0;

 protected:
  ~JobQueue() = default;
};

/// Runs jobs on worker threads.
class JobSystem {
 public:
  /// Seeds a Run with its first jobs.
  using StartFunction = void (*)(void* context, JobQueue& queue);
  /// Work over the half-open range [begin, end).
  using RangeFunction = std::function<void(std::size_t begin, std::size_t end)>;

  virtual ~JobSystem() = default;

  /// Calls `start(context, queue)`, then runs every job pushed to `queue` (jobs may push more) and returns
  /// when all of them have finished. The calling thread runs jobs too. Jobs must not block on each other
  /// except on work another running job has already claimed.
  virtual void Run(StartFunction start, void* context) = 0;

  /// Number of threads that may run jobs at once (including the caller).
  virtual int ThreadCount() const = 0;

  /// Splits [0, count) into chunks of about `grain` items and runs `function` on each; blocks until done.
  /// Results must be written to per-index slots so the outcome does not depend on scheduling.
  void ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function);
};

/// Runs everything on the calling thread; the reference for determinism checks.
class SerialJobSystem final : public JobSystem {
 public:
  void Run(StartFunction start, void* context) override;
  int ThreadCount() const override { return 1; }
};

/// The job system a PhysicsSystem uses when the caller gives none: TbbJobSystem when built with oneTBB,
/// else ThreadPoolJobSystem. `thread_count` 0 = all hardware threads.
std::unique_ptr<JobSystem> MakeDefaultJobSystem(int thread_count = 0);

}  // namespace strata
