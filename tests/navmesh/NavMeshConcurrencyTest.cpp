// The service under load (label tsan; the long version is under stress): background jobs gather and build
// tiles while other threads add, remove and move thousands of bodies, the world steps and agents request
// tiles and query paths. No race, no failure, every requested tile ends ready.
#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <thread>

#include "NavMeshTestWorld.h"

namespace strata::test {
namespace {

constexpr float kTile = 12.8f;
constexpr int kTiles = 3;

/// A box inside one tile, touching none of its neighbours.
AABB OneTile(int x, int z) {
  const Vec3 corner(static_cast<float>(x) * kTile, -1.0f, static_cast<float>(z) * kTile);
  return {corner + Vec3(0.1f, 0.0f, 0.1f), corner + Vec3(kTile - 0.1f, 2.0f, kTile - 0.1f)};
}

// Streams bodies in and out and teleports them (crates that count, debris that does not): at least
// `operations` changes, and on until the world has stepped `min_steps` times, so jobs overlap the changes.
void MutateBodies(PhysicsSystem& world, unsigned seed, int operations, int min_steps,
                  const std::atomic<int>& steps) {
  const float extent = kTiles * kTile;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> across(1.0f, extent - 1.0f);
  std::vector<BodyID> mine;
  for (int op = 0; op < operations || steps.load() < min_steps; ++op) {
    const int action = static_cast<int>(random() % 4);
    if ((action <= 1 && mine.size() < 150) || mine.size() < 4) {
      const float half = (random() % 2) ? 1.0f : 0.15f;
      auto settings = Dynamic(Box(half, half, half), Vec3(across(random), half + 0.01f, across(random)));
      if (auto id = world.bodies().CreateAndAddBody(settings)) mine.push_back(*id);
    } else if (action == 2) {
      const std::size_t pick = random() % mine.size();
      EXPECT_TRUE(world.bodies().RemoveAndDestroyBody(mine[pick]).ok());
      mine[pick] = mine.back();
      mine.pop_back();
    } else {
      EXPECT_TRUE(world.bodies()
                      .SetPosition(mine[random() % mine.size()], Vec3(across(random), 1.2f, across(random)))
                      .ok());
    }
  }
}

// Dirty tracking kept up: the live navmesh is the one a fresh build of the final world gives, over the same
// tiles (the agent's requests reach a tile past the floor, where crates pushed over its edge stand).
void ExpectSameAsAFreshBuild(PhysicsSystem& world, navmesh::NavMeshService& service) {
  const auto fresh = MakeService(world, FastServiceConfig(1));
  for (int z = -1; z <= kTiles; ++z) {
    for (int x = -1; x <= kTiles; ++x) {
      if (service.GetTileState({x, z}) != navmesh::TileState::kReady) continue;
      ASSERT_TRUE(fresh->RequestBox(OneTile(x, z)).ok());
    }
  }
  ASSERT_TRUE(fresh->WaitUntilIdle(std::chrono::seconds(120)));
  EXPECT_EQ(fresh->navmesh().Tiles(), service.navmesh().Tiles());
  EXPECT_EQ(service.navmesh().polygon_count(), fresh->navmesh().polygon_count());
  EXPECT_EQ(service.navmesh().WalkableArea(), fresh->navmesh().WalkableArea());
}

void RunServiceUnderLoad(int operations_per_thread, int min_steps) {
  auto world = MakeWorld({}, 8192);
  AddFloor(*world, kTiles);
  navmesh::NavMeshServiceConfig config = FastServiceConfig(2);
  config.move_threshold = 0.0f;  // any move makes a tile stale, so the end state must match a fresh build
  const auto service = MakeService(*world, config);
  std::atomic<bool> stop{false};
  std::atomic<int> steps{0};
  const float extent = kTiles * kTile;
  std::thread mutator_a([&] { MutateBodies(*world, 1u, operations_per_thread, min_steps, steps); });
  std::thread mutator_b([&] { MutateBodies(*world, 2u, operations_per_thread, min_steps, steps); });
  std::thread stepper([&] {
    while (!stop.load()) {
      ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
      ++steps;
    }
  });
  // An agent asks for tiles around where it is and queries paths on whatever is published so far.
  std::thread agent([&] {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> across(1.0f, extent - 1.0f);
    const auto query = MakeQuery(service->navmesh());
    while (!stop.load()) {
      const Vec3 position(across(random), 0.0f, across(random));
      ASSERT_TRUE(service->RequestAround(position, kTile).ok());
      (void)query->FindPath(position, Vec3(across(random), 0.0f, across(random)));
      std::this_thread::yield();
    }
  });
  mutator_a.join();
  mutator_b.join();
  stop = true;
  stepper.join();
  agent.join();
  ASSERT_TRUE(service->RequestBox(TileArea(kTiles)).ok());
  // The world is frozen now: the scanner sees the last changes and the rebuilds finish.
  ASSERT_TRUE(WaitUntilSettled(*service, std::chrono::seconds(120)));
  EXPECT_EQ(service->stats().failures, 0u) << service->last_error();
  for (int z = 0; z < kTiles; ++z)
    for (int x = 0; x < kTiles; ++x)
      EXPECT_EQ(service->GetTileState({x, z}), navmesh::TileState::kReady) << x << ", " << z;
  EXPECT_GT(service->stats().rebuilds, 0u);
  ExpectSameAsAFreshBuild(*world, *service);
}

// The step takes every body lock at its start and end; a job that needed one would hold the step up. With
// every body lock held here, the service must still gather, scan and publish a whole area.
TEST(NavMeshServiceThreads, JobsBuildTilesWhileEveryBodyLockIsHeld) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  Add(*world, Static(Box(0.5f, 1.0f, 4.0f), Vec3(kTile, 1.0f, kTile)));
  Add(*world, Dynamic(Box(1.0f, 1.0f, 1.0f), Vec3(4.0f, 1.0f, 4.0f)));
  const auto service = MakeService(*world, FastServiceConfig(2));
  world->body_manager().LockAll();
  const bool built =
      service->RequestBox(TileArea(2)).ok() && service->WaitUntilIdle(std::chrono::seconds(60));
  const std::size_t scans = service->stats().scans;
  const bool scanned =
      WaitForScans(*service, scans + 2, std::chrono::steady_clock::now() + std::chrono::seconds(60));
  world->body_manager().UnlockAll();
  ASSERT_TRUE(built) << "jobs waited on body locks";
  EXPECT_TRUE(scanned) << "the dirty scan waited on body locks";
  EXPECT_EQ(service->stats().ready, 4u);
  EXPECT_EQ(service->stats().failures, 0u) << service->last_error();
  // The wall and the crate are in the tiles: the walkable area is the bare floor's minus theirs.
  const auto bare_world = MakeWorld();
  AddFloor(*bare_world, 2);
  const auto bare = BuildArea(*bare_world, TileArea(2));
  EXPECT_LT(service->navmesh().WalkableArea(), bare->navmesh().WalkableArea() - 10.0);
}

TEST(NavMeshServiceThreads, JobsRunWhileWorldChanges) {
  RunServiceUnderLoad(1500, 60);
}

TEST(NavMeshServiceThreadsStress, JobsRunWhileWorldChangesLong) {
  RunServiceUnderLoad(20000, 1200);
}

}  // namespace
}  // namespace strata::test
