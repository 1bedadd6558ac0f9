// TbbJobSystem: the default JobSystem, a oneTBB task arena with a fixed number of threads; each Run is one
// tbb::task_group in that arena, so concurrent Runs from several threads (several worlds) stay apart.
// This is the only place in physics/ that includes oneTBB (only in its .cpp); it is compiled only when
// STRATA_WITH_TBB is on.
#pragma once

#include <memory>

#include "physics/core/JobSystem.h"

namespace strata {

/// JobSystem on a oneTBB arena of `thread_count` threads (0 = all hardware threads).
class TbbJobSystem final : public JobSystem {
 public:
  explicit TbbJobSystem(int thread_count = 0);
  ~TbbJobSystem() override;

  void Run(StartFunction start, void* context) override;
  int ThreadCount() const override { return thread_count_; }

 private:
  struct Arena;
  std::unique_ptr<Arena> arena_;
  int thread_count_;
};

}  // namespace strata
