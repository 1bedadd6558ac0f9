#include "physics/core/TbbJobSystem.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <thread>

namespace strata {

namespace {
int ResolveThreadCount(int requested) {
  if (requested > 0) return requested;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware == 0 ? 1 : static_cast<int>(hardware);
}
}  // namespace

struct TbbJobSystem::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

TbbJobSystem::TbbJobSystem(int thread_count)
    : arena_(std::make_unique<Arena>(ResolveThreadCount(thread_count))),
      thread_count_(ResolveThreadCount(thread_count)) {}

TbbJobSystem::~TbbJobSystem() = default;

void TbbJobSystem::ParallelFor(std::size_t count, std::size_t grain, const RangeFunction& function) {
  if (count == 0) return;
  if (thread_count_ == 1 || count <= grain) {
    function(0, count);
    return;
  }
  arena_->arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, count, grain == 0 ? 1 : grain),
        [&](const tbb::blocked_range<std::size_t>& range) { function(range.begin(), range.end()); });
  });
}

}  // namespace strata
