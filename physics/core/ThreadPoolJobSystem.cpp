#include "physics/core/ThreadPoolJobSystem.h"

#include <algorithm>
#include <thread>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace strata {

namespace {
void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}
}  // namespace

// One Run's view of the pool: pushing counts the job as unfinished; the job's completion uncounts it.
class ThreadPoolJobSystem::RunQueue final : public JobQueue {
 public:
  explicit RunQueue(ThreadPoolJobSystem& pool) : pool_(pool) {}
  void Push(const Job& job) override {
    unfinished.fetch_add(1, std::memory_order_relaxed);
    pool_.Push({job, this});
  }
  std::atomic<std::int64_t> unfinished{0};

 private:
  ThreadPoolJobSystem& pool_;
};

ThreadPoolJobSystem::ThreadPoolJobSystem(int thread_count) {
  if (thread_count <= 0) thread_count = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (int i = 1; i < thread_count; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPoolJobSystem::~ThreadPoolJobSystem() {
  stopping_.store(true, std::memory_order_seq_cst);
  wake_epoch_.fetch_add(1, std::memory_order_seq_cst);
  wake_epoch_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void ThreadPoolJobSystem::Push(const Entry& entry) {
  if (!queue_.TryPush(entry)) {
    // Full: running it here keeps the job's order guarantees (none) and needs no allocation.
    entry.job();
    entry.run->unfinished.fetch_sub(1, std::memory_order_acq_rel);
    return;
  }
  // Both sides read-modify-write sleepers_, so the two are ordered: either this reads the worker's
  // increment and wakes it, or the worker's increment reads this (acquire) and its check sees the job.
  // (An RMW instead of a fence pair: ThreadSanitizer does not model fences.)
  if (sleepers_.fetch_add(0, std::memory_order_acq_rel) > 0) {
    wake_epoch_.fetch_add(1, std::memory_order_release);
    wake_epoch_.notify_one();
  }
}

bool ThreadPoolJobSystem::RunOne() {
  Entry entry;
  if (!queue_.TryPop(entry)) return false;
  entry.job();
  entry.run->unfinished.fetch_sub(1, std::memory_order_acq_rel);
  return true;
}

void ThreadPoolJobSystem::WorkerLoop() {
  while (!stopping_.load(std::memory_order_relaxed)) {
    if (RunOne()) continue;
    bool found = false;
    for (int spin = 0; spin < kSpinsBeforeSleep && !found; ++spin) {
      CpuRelax();
      found = !queue_.LooksEmpty();
    }
    if (found) continue;
    // Either Push sees this sleeper and bumps the epoch, or this sees the job (see Push); reading a bumped
    // epoch (acquire) also makes the job visible.
    sleepers_.fetch_add(1, std::memory_order_acq_rel);
    const std::uint32_t epoch = wake_epoch_.load(std::memory_order_acquire);
    if (queue_.LooksEmpty() && !stopping_.load(std::memory_order_seq_cst))
      wake_epoch_.wait(epoch, std::memory_order_acquire);
    sleepers_.fetch_sub(1, std::memory_order_relaxed);
  }
}

void ThreadPoolJobSystem::Run(StartFunction start, void* context) {
  RunQueue run(*this);
  start(context, run);
  // The caller works until its own jobs are done; it may run other Runs' jobs meanwhile. Waiting for jobs
  // another thread runs, it spins briefly, then yields in case that thread is waiting for a core.
  int idle = 0;
  while (run.unfinished.load(std::memory_order_acquire) > 0) {
    if (RunOne()) {
      idle = 0;
    } else if (++idle < kSpinsBeforeYield) {
      CpuRelax();
    } else {
      std::this_thread::yield();
    }
  }
}

}  // namespace strata
