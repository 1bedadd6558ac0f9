// ThreadPoolJobSystem: a JobSystem on plain std::threads, for builds without oneTBB (and the
// ThreadSanitizer build, which cannot see inside the uninstrumented oneTBB library).
// ParallelFor may be called from one thread at a time; the caller works on chunks too.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "physics/core/JobSystem.h"

namespace strata {

/// Fixed pool of `thread_count - 1` workers plus the calling thread.
class ThreadPoolJobSystem final : public JobSystem {
 public:
  explicit ThreadPoolJobSystem(int thread_count = 0);
  ~ThreadPoolJobSystem() override;
  ThreadPoolJobSystem(const ThreadPoolJobSystem&) = delete;
  ThreadPoolJobSystem& operator=(const ThreadPoolJobSystem&) = delete;

  void ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function) override;
  int ThreadCount() const override { return static_cast<int>(workers_.size()) + 1; }

 private:
  struct Loop {
    const RangeFunction* function = nullptr;
    std::size_t count = 0;
    std::size_t grain = 1;
  };

  void WorkerLoop();
  void RunChunks(const Loop& loop);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  Loop loop_;                         // the current loop (guarded by mutex_)
  std::atomic<std::size_t> next_{0};  // first index not yet claimed
  std::uint64_t generation_ = 0;      // bumped per loop so sleeping workers see new work
  int busy_workers_ = 0;
  bool stopping_ = false;
};

}  // namespace strata
