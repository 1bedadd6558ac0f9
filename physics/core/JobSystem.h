// JobSystem: the interface the physics step uses to spread work over threads. A game plugs in its own
// scheduler by implementing it; Strata ships a oneTBB-backed default and a single-threaded one.
// ParallelFor may be called from one thread at a time per JobSystem; the body runs on any worker.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace strata {

/// Runs index ranges of a loop on worker threads and returns when all of them are done.
class JobSystem {
 public:
  /// Work over the half-open range [begin, end).
  using RangeFunction = std::function<void(std::size_t begin, std::size_t end)>;

  virtual ~JobSystem() = default;

  /// Splits [0, count) into chunks of about `grain` items and runs `function` on each; blocks until done.
  /// Results must be written to per-index slots so the outcome does not depend on scheduling.
  virtual void ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function) = 0;

  /// Number of threads that may run chunks at once (including the caller).
  virtual int ThreadCount() const = 0;
};

/// Runs everything on the calling thread; the reference for determinism checks.
class SerialJobSystem final : public JobSystem {
 public:
  void ParallelFor(std::size_t count, std::size_t /*grain*/, const RangeFunction& function) override {
    if (count > 0) function(0, count);
  }
  int ThreadCount() const override { return 1; }
};

/// The job system a PhysicsSystem uses when the caller gives none: TbbJobSystem when built with oneTBB,
/// else ThreadPoolJobSystem. `thread_count` 0 = all hardware threads.
std::unique_ptr<JobSystem> MakeDefaultJobSystem(int thread_count = 0);

}  // namespace strata
