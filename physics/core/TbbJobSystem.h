// TbbJobSystem: the default JobSystem, a oneTBB task arena with a fixed number of threads.
// This is the only place in physics/ that includes oneTBB (only in its .cpp); it is compiled only when
// STRATA_WITH_TBB is on.
// Thread-safe to share between PhysicsSystems; ParallelFor calls from several threads are allowed.
#pragma once

#include <memory>

#include "physics/core/JobSystem.h"

namespace strata {

/// JobSystem on a oneTBB arena of `thread_count` threads (0 = all hardware threads).
class TbbJobSystem final : public JobSystem {
 public:
  explicit TbbJobSystem(int thread_count = 0);
  ~TbbJobSystem() override;

  void ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function) override;
  int ThreadCount() const override { return thread_count_; }

 private:
  struct Arena;
  std::unique_ptr<Arena> arena_;
  int thread_count_;
};

}  // namespace strata
