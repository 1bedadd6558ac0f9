#include "physics/core/TbbJobSystem.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <thread>

namespace strata {

namespace {

int ResolveThreadCount(int requested) {
  if (requested > 0) return requested;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware == 0 ? 1 : static_cast<int>(hardware);
}

// Jobs become tasks of one task_group; oneTBB takes task memory from its own pools, not from operator new.
class GroupQueue final : public JobQueue {
 public:
  explicit GroupQueue(tbb::task_group& group) : group_(group) {}
  void Push(const Job& job) override {
    group_.run([job] { job(); });
  }

 private:
  tbb::task_group& group_;
};

}  // namespace

struct TbbJobSystem::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

TbbJobSystem::TbbJobSystem(int thread_count)
    : arena_(std::make_unique<Arena>(ResolveThreadCount(thread_count))),
      thread_count_(ResolveThreadCount(thread_count)) {}

TbbJobSystem::~TbbJobSystem() = default;

void TbbJobSystem::Run(StartFunction start, void* context) {
  arena_->arena.execute([&] {
    tbb::task_group group;
    GroupQueue queue(group);
    start(context, queue);
    group.wait();
  });
}

}  // namespace strata
