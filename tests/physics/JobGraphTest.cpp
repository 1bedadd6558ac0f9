// Job systems and the stage graph: every job runs exactly once, a stage starts only after every stage it
// waits for has finished, a width set by an earlier stage is honoured, and Runs from several threads on one
// pool stay apart. Each on the serial system, the std::thread pool and the default (oneTBB) system.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "physics/core/Atomics.h"
#include "physics/core/JobGraph.h"
#include "physics/core/ThreadPoolJobSystem.h"

namespace strata::test {
namespace {

std::vector<std::shared_ptr<JobSystem>> AllJobSystems() {
  return {std::make_shared<SerialJobSystem>(), std::make_shared<ThreadPoolJobSystem>(4),
          MakeDefaultJobSystem(3)};
}

TEST(JobSystemThreads, ParallelForVisitsEveryIndexOnce) {
  for (const auto& jobs : AllJobSystems()) {
    std::vector<std::atomic<int>> visits(10007);
    jobs->ParallelFor(visits.size(), 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) visits[i].fetch_add(1);
    });
    for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i;
  }
}

TEST(JobSystemThreads, JobsPushedFromJobsAllRunBeforeRunReturns) {
  struct Tree {
    std::atomic<int> ran{0};
    JobQueue* queue = nullptr;
  };
  // Each job pushes two children until depth 10: 2047 jobs in all, most pushed from running jobs.
  for (const auto& jobs : AllJobSystems()) {
    Tree tree;
    // Jobs are plain function pointers, so the recursion is a named function.
    struct Recurse {
      static void Run(void* context, std::uint32_t depth) {
        auto& t = *static_cast<Tree*>(context);
        t.ran.fetch_add(1);
        if (depth == 10) return;
        for (int child = 0; child < 2; ++child) t.queue->Push({&Recurse::Run, context, depth + 1});
      }
    };
    jobs->Run(
        [](void* context, JobQueue& queue) {
          auto& t = *static_cast<Tree*>(context);
          t.queue = &queue;
          queue.Push({&Recurse::Run, context, 0});
        },
        &tree);
    EXPECT_EQ(tree.ran.load(), 2047);
  }
}

// A diamond of stages (a -> b, a -> c, b + c -> d) whose jobs record what had finished when they ran.
struct Diamond {
  std::atomic<int> finished[4] = {};
  std::atomic<int> ran[4] = {};
  std::atomic<int> violations{0};
  std::atomic<std::uint32_t> widest_job{0};
  JobGraph graph;
  JobGraph::StageId stages[4] = {};
  std::uint32_t width_for_d = 1;

  template <int kStage>
  static void Stage(void* context, std::uint32_t job, std::uint32_t width) {
    auto& self = *static_cast<Diamond*>(context);
    const auto expected_before = [&](int stage, int jobs) {
      if (self.finished[stage].load(std::memory_order_acquire) != jobs) self.violations.fetch_add(1);
    };
    if (kStage == 1 || kStage == 2) expected_before(0, 3);
    if (kStage == 3) expected_before(1, 5), expected_before(2, 2);
    if (kStage == 2 && job == 0) self.graph.SetWidth(self.stages[3], self.width_for_d);  // d waits for c
    if (kStage == 3) AtomicMax(self.widest_job, job + 1);  // d's jobs may run side by side
    if (job >= width) self.violations.fetch_add(1);
    self.ran[kStage].fetch_add(1);
    self.finished[kStage].fetch_add(1, std::memory_order_release);
  }

  Diamond() {
    stages[0] = graph.Add("a", &Stage<0>, this);
    stages[1] = graph.Add("b", &Stage<1>, this, {stages[0]});
    stages[2] = graph.Add("c", &Stage<2>, this, {stages[0]});
    stages[3] = graph.Add("d", &Stage<3>, this, {stages[1], stages[2]});
    graph.SetWidth(stages[0], 3);
    graph.SetWidth(stages[1], 5);
    graph.SetWidth(stages[2], 2);
  }
  void Reset() {
    for (int s = 0; s < 4; ++s) finished[s] = 0, ran[s] = 0;
    violations = 0;
    widest_job = 0;
  }
};

TEST(JobGraphThreads, StagesRunAfterWhatTheyWaitForWithTheirWidth) {
  for (const auto& jobs : AllJobSystems()) {
    Diamond diamond;
    for (std::uint32_t run = 0; run < 50; ++run) {
      diamond.Reset();
      diamond.width_for_d = 1 + run % 7;
      diamond.graph.Run(*jobs);
      EXPECT_EQ(diamond.violations.load(), 0);
      EXPECT_EQ(diamond.ran[0].load(), 3);
      EXPECT_EQ(diamond.ran[1].load(), 5);
      EXPECT_EQ(diamond.ran[2].load(), 2);
      EXPECT_EQ(diamond.ran[3].load(), static_cast<int>(diamond.width_for_d));
      EXPECT_EQ(diamond.widest_job.load(), diamond.width_for_d);
    }
    const StageTiming d = diamond.graph.timing(diamond.stages[3]);
    EXPECT_STREQ(d.name, "d");
    EXPECT_EQ(d.width, diamond.width_for_d);
  }
}

TEST(JobGraph, StagesGivenAWidthReportThemselvesParallel) {
  JobGraph graph;
  std::atomic<int> calls{0};
  auto count = [](void* context, std::uint32_t, std::uint32_t) {
    static_cast<std::atomic<int>*>(context)->fetch_add(1);
  };
  const JobGraph::StageId serial = graph.Add("serial", count, &calls);
  const JobGraph::StageId narrowed = graph.Add("narrowed", count, &calls, {serial});
  graph.SetWidth(narrowed, 1);  // parallel by kind even when one job is all it gets
  SerialJobSystem jobs;
  graph.Run(jobs);
  EXPECT_EQ(calls.load(), 2);
  EXPECT_FALSE(graph.timing(serial).parallel);
  EXPECT_TRUE(graph.timing(narrowed).parallel);
  EXPECT_EQ(graph.timing(narrowed).width, 1u);
}

TEST(JobGraph, UntimedGraphsRunEveryStageAndReportNoTimes) {
  for (const bool timed : {true, false}) {
    JobGraph graph;
    graph.set_timed(timed);
    std::atomic<int> calls{0};
    auto count = [](void* context, std::uint32_t, std::uint32_t) {
      static_cast<std::atomic<int>*>(context)->fetch_add(1);
    };
    // The first stage measures itself on the profiler's clock: what the graph records for it must cover that
    // (an order between two readings of one clock, no speed asserted).
    struct Measured {
      std::atomic<int>* calls;
      double ms = 0.0;
    } measured{&calls};
    auto count_and_measure = [](void* context, std::uint32_t, std::uint32_t) {
      auto& self = *static_cast<Measured*>(context);
      const auto start = std::chrono::steady_clock::now();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      self.calls->fetch_add(1);
      self.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    };
    const JobGraph::StageId first = graph.Add("first", count_and_measure, &measured);
    const JobGraph::StageId second = graph.Add("second", count, &calls, {first});
    graph.SetWidth(second, 3);
    SerialJobSystem jobs;
    graph.Run(jobs);
    EXPECT_EQ(calls.load(), 4);
    const StageTiming before = graph.timing(first), after = graph.timing(second);
    EXPECT_EQ(after.width, 3u);
    if (timed) {
      // Recorded, and in the order the stages ran.
      EXPECT_GE(before.busy_ms, measured.ms);
      EXPECT_GE(before.end_ms - before.start_ms, measured.ms);
      EXPECT_LE(before.end_ms, after.start_ms);
      EXPECT_LE(after.start_ms, after.end_ms);
    } else {
      EXPECT_EQ(before.end_ms, 0.0);
      EXPECT_EQ(after.end_ms, 0.0);
      EXPECT_EQ(after.busy_ms, 0.0);
    }
  }
}

TEST(JobGraphThreads, GraphsRunFromSeveralThreadsOnOnePoolStayApart) {
  auto pool = std::make_shared<ThreadPoolJobSystem>(3);
  std::atomic<int> failures{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 3; ++t)
    threads.emplace_back([&] {
      Diamond diamond;
      for (int run = 0; run < 100; ++run) {
        diamond.Reset();
        diamond.graph.Run(*pool);
        if (diamond.violations.load() != 0 || diamond.ran[3].load() != 1 || diamond.ran[1].load() != 5)
          failures.fetch_add(1);
      }
    });
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(failures.load(), 0);
}

}  // namespace
}  // namespace strata::test
