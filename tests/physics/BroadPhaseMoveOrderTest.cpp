// BroadPhaseMoveOrder: a move's bounds reach the broad phase only if no later move of the body got there
// first, updates of one body never overlap, and a retired body takes no earlier move's bounds.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "physics/body/BroadPhaseMoveOrder.h"

namespace strata::test {
namespace {

TEST(BroadPhaseMoveOrder, AnEarlierMoveThatArrivesLateChangesNothing) {
  BroadPhaseMoveOrder order(4);
  const std::uint64_t first = order.Issue(2), second = order.Issue(2);
  EXPECT_LT(first, second);
  int bounds = 0;
  EXPECT_TRUE(order.Apply(2, second, [&] { bounds = 2; }));
  EXPECT_FALSE(order.Apply(2, first, [&] { bounds = 1; }));
  EXPECT_FALSE(order.Apply(2, second, [&] { bounds = 3; }));  // once per ticket
  EXPECT_EQ(bounds, 2);
  // Slots are independent.
  EXPECT_TRUE(order.Apply(3, order.Issue(3), [&] { bounds = 4; }));
  EXPECT_EQ(bounds, 4);
}

TEST(BroadPhaseMoveOrder, RetiringMakesEveryMoveIssuedSoFarStale) {
  BroadPhaseMoveOrder order(1);
  const std::uint64_t first = order.Issue(0), second = order.Issue(0);
  order.Retire(0);
  int updates = 0;
  EXPECT_FALSE(order.Apply(0, second, [&] { ++updates; }));
  EXPECT_FALSE(order.Apply(0, first, [&] { ++updates; }));
  EXPECT_EQ(updates, 0);
  EXPECT_TRUE(order.Apply(0, order.Issue(0), [&] { ++updates; }));  // a move after it (back in the world)
  EXPECT_EQ(updates, 1);
}

// Threads move bodies under per-body mutexes (the body locks) and apply the bounds after unlocking, with a
// random pause in between so that later moves often get there first. A move is named by its place in its
// body's lock order. The oracle: what a body's broad phase holds only ever moves forward in that order and
// ends at the body's last move; the updates of one body never overlap.
TEST(BroadPhaseMoveOrderThreads, EachBodyEndsWithItsLastMoveWhateverOrderTheyArriveIn) {
  constexpr int kBodies = 3, kThreads = 4, kMoves = 2000;
  BroadPhaseMoveOrder order(kBodies);
  std::array<std::mutex, kBodies> locks;
  std::array<int, kBodies> moves_made{};   // under the body's lock
  std::array<int, kBodies> broad_phase{};  // written only inside Apply
  std::array<std::atomic<int>, kBodies> inside{};
  std::atomic<int> overlaps{0}, backwards{0}, skipped{0};
  auto mover = [&](int thread) {
    std::mt19937 random(static_cast<unsigned>(3 + thread));
    for (int m = 0; m < kMoves; ++m) {
      const auto body = static_cast<std::uint32_t>(random() % kBodies);
      int move = 0;
      std::uint64_t ticket = 0;
      {
        const std::lock_guard lock(locks[body]);
        move = ++moves_made[body];
        ticket = order.Issue(body);
      }
      if (random() % 4 == 0) std::this_thread::yield();
      const auto pause = std::chrono::nanoseconds(random() % 2000);
      for (const auto until = std::chrono::steady_clock::now() + pause;
           std::chrono::steady_clock::now() < until;) {
      }
      const bool ran = order.Apply(body, ticket, [&] {
        if (inside[body].fetch_add(1) != 0) ++overlaps;
        if (move < broad_phase[body]) ++backwards;
        broad_phase[body] = move;
        inside[body].fetch_sub(1);
      });
      skipped += ran ? 0 : 1;
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back(mover, t);
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(overlaps.load(), 0);
  EXPECT_EQ(backwards.load(), 0);
  for (int body = 0; body < kBodies; ++body)
    EXPECT_EQ(broad_phase[body], moves_made[body]) << "body " << body;
  // The pauses did reorder moves (else this test would show nothing).
  EXPECT_GT(skipped.load(), 0);
}

TEST(BroadPhaseMoveOrderThreads, RetiringWaitsForAnUpdateThatIsRunning) {
  BroadPhaseMoveOrder order(1);
  const std::uint64_t ticket = order.Issue(0);
  std::atomic<bool> started{false}, finished{false};
  std::thread mover([&] {
    order.Apply(0, ticket, [&] {
      started = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      finished = true;
    });
  });
  while (!started) std::this_thread::yield();
  order.Retire(0);
  EXPECT_TRUE(finished.load());
  mover.join();
}

}  // namespace
}  // namespace strata::test
