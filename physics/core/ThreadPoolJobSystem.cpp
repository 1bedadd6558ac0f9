#include "physics/core/ThreadPoolJobSystem.h"

#include <algorithm>

namespace strata {

ThreadPoolJobSystem::ThreadPoolJobSystem(int thread_count) {
  if (thread_count <= 0) thread_count = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (int i = 1; i < thread_count; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPoolJobSystem::~ThreadPoolJobSystem() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void ThreadPoolJobSystem::RunChunks(const Loop& loop) {
  // Chunks are claimed with one atomic add each; which thread runs a chunk does not matter because
  // callers write results per index.
  while (true) {
    const std::size_t begin = next_.fetch_add(loop.grain, std::memory_order_relaxed);
    if (begin >= loop.count) return;
    (*loop.function)(begin, std::min(begin + loop.grain, loop.count));
  }
}

void ThreadPoolJobSystem::WorkerLoop() {
  std::uint64_t seen = 0;
  while (true) {
    Loop loop;
    {
      // Take the loop under the lock: the caller cannot return (and a new loop cannot start) until
      // this worker is no longer counted as busy.
      std::unique_lock lock(mutex_);
      work_ready_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) return;
      seen = generation_;
      loop = loop_;
      ++busy_workers_;
    }
    RunChunks(loop);
    {
      std::lock_guard lock(mutex_);
      --busy_workers_;
    }
    work_done_.notify_all();
  }
}

void ThreadPoolJobSystem::ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function) {
  if (count == 0) return;
  grain = std::max<std::size_t>(1, grain);
  if (workers_.empty() || count <= grain) {
    function(0, count);
    return;
  }
  const Loop loop{&function, count, grain};
  {
    std::lock_guard lock(mutex_);
    loop_ = loop;
    next_.store(0, std::memory_order_relaxed);
    ++generation_;
  }
  work_ready_.notify_all();
  RunChunks(loop);
  // Wait until no worker is still inside a chunk of this loop; late workers find no chunk left.
  std::unique_lock lock(mutex_);
  work_done_.wait(lock, [&] { return busy_workers_ == 0; });
}

}  // namespace strata
