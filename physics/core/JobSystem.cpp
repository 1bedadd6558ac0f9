#include "physics/core/JobSystem.h"

#include <algorithm>
#include <atomic>

#include "physics/core/ThreadPoolJobSystem.h"
#ifdef STRATA_HAVE_TBB
#include "physics/core/TbbJobSystem.h"
#endif

namespace strata {

namespace {

// The jobs a SerialJobSystem::Run has queued but not run, per thread so concurrent Runs on different threads
// stay apart; the vector keeps its capacity, so a warm Run allocates nothing.
class SerialQueue final : public JobQueue {
 public:
  void Push(const Job& job) override { pending.push_back(job); }
  std::vector<Job> pending;
};

struct ParallelForContext {
  const JobSystem::RangeFunction* function;
  std::size_t count;
  std::size_t grain;
  std::atomic<std::size_t> next{0};
};

void RunParallelForChunks(void* context, std::uint32_t) {
  auto& loop = *static_cast<ParallelForContext*>(context);
  // Chunks are claimed with one atomic add each, so a slow thread takes fewer of them.
  while (true) {
    const std::size_t begin = loop.next.fetch_add(loop.grain, std::memory_order_relaxed);
    if (begin >= loop.count) return;
    (*loop.function)(begin, std::min(begin + loop.grain, loop.count));
  }
}

}  // namespace

void SerialJobSystem::Run(StartFunction start, void* context) {
  thread_local SerialQueue queue;
  // A job that runs a nested Run on this thread sees the outer jobs below `floor` and leaves them alone.
  const std::size_t floor = queue.pending.size();
  start(context, queue);
  while (queue.pending.size() > floor) {
    const Job job = queue.pending.back();
    queue.pending.pop_back();
    job();
  }
}

void JobSystem::ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function) {
  if (count == 0) return;
  grain = std::max<std::size_t>(1, grain);
  const std::size_t chunks = (count + grain - 1) / grain;
  const auto workers = static_cast<std::uint32_t>(std::min<std::size_t>(chunks, ThreadCount()));
  if (workers <= 1) {
    function(0, count);
    return;
  }
  ParallelForContext loop{&function, count, grain};
  struct Start {
    ParallelForContext* loop;
    std::uint32_t workers;
  } seed{&loop, workers};
  Run(
      [](void* context, JobQueue& queue) {
        const auto& s = *static_cast<Start*>(context);
        for (std::uint32_t i = 0; i < s.workers; ++i) queue.Push({&RunParallelForChunks, s.loop, i});
      },
      &seed);
}

std::unique_ptr<JobSystem> MakeDefaultJobSystem(int thread_count) {
#ifdef STRATA_HAVE_TBB
  return std::make_unique<TbbJobSystem>(thread_count);
#else
  return std::make_unique<ThreadPoolJobSystem>(thread_count);
#endif
}

}  // namespace strata
