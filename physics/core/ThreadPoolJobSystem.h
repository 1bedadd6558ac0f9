// ThreadPoolJobSystem: a JobSystem on plain std::threads, for builds without oneTBB and for the
// ThreadSanitizer build (which cannot see inside the uninstrumented oneTBB library). Jobs go through one
// lock-free queue; idle workers spin briefly (stages of a step follow each other within microseconds) and
// then sleep on an atomic. Run may be called from several threads at once; the caller runs jobs too.
#pragma once

#include <atomic>
#include <thread>
#include <vector>

#include "physics/core/BoundedQueue.h"
#include "physics/core/JobSystem.h"

namespace strata {

/// Fixed pool of `thread_count - 1` workers plus the calling thread.
class ThreadPoolJobSystem final : public JobSystem {
 public:
  /// `thread_count` 0 = all hardware threads.
  explicit ThreadPoolJobSystem(int thread_count = 0);
  ~ThreadPoolJobSystem() override;
  ThreadPoolJobSystem(const ThreadPoolJobSystem&) = delete;
  ThreadPoolJobSystem& operator=(const ThreadPoolJobSystem&) = delete;

  void Run(StartFunction start, void* context) override;
  int ThreadCount() const override { return static_cast<int>(workers_.size()) + 1; }

 private:
  class RunQueue;
  // A queued job and the Run it belongs to (whose unfinished count it lowers when done).
  struct Entry {
    Job job;
    RunQueue* run = nullptr;
  };

  void Push(const Entry& entry);
  bool RunOne();
  void WorkerLoop();

  static constexpr std::size_t kQueueCapacity = 4096;
  // About 20-50 microseconds of polling before a worker sleeps.
  static constexpr int kSpinsBeforeSleep = 2000;
  // Pauses before a Run caller waiting for other threads' jobs yields its core.
  static constexpr int kSpinsBeforeYield = 256;

  BoundedQueue<Entry> queue_{kQueueCapacity};
  std::vector<std::thread> workers_;
  std::atomic<std::uint32_t> wake_epoch_{0};
  std::atomic<int> sleepers_{0};
  std::atomic<bool> stopping_{false};
};

}  // namespace strata
