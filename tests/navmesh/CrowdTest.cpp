// Crowds: agents of a profile walk to targets on tiles not built when they set out, asking for the tiles
// ahead and waiting at the edge of what is built; they keep walking, never on a replaced tile's polygon and
// never off the navmesh, while another thread makes the service rebuild tiles and the budget evicts those
// left behind (suite CrowdThreads: also under ThreadSanitizer).
#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <thread>

#include "NavMeshTestWorld.h"
#include "navmesh/Crowd.h"

namespace strata::test {
namespace {

using navmesh::Crowd;
using navmesh::CrowdAgentState;

navmesh::NavMeshServiceConfig PersonService(int max_tiles) {
  navmesh::NavMeshServiceConfig config = FastServiceConfig(1);
  config.profiles = {navmesh::AgentProfile::Person()};
  config.max_tiles = max_tiles;
  return config;
}

// Updates the crowd at 30 Hz until every agent has arrived or `seconds` of wall time pass; true if all did.
// `after_update` runs on this thread after each update.
bool WalkUntilArrived(
    Crowd& crowd, const std::vector<int>& agents, double seconds,
    const std::function<void()>& after_update = [] {}) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    EXPECT_TRUE(crowd.Update(1.0f / 30.0f).ok());
    after_update();
    if (std::all_of(agents.begin(), agents.end(),
                    [&](int agent) { return *crowd.state(agent) == CrowdAgentState::kArrived; }))
      return true;
    std::this_thread::sleep_for(std::chrono::microseconds(500));  // the service's thread builds meanwhile
  }
  return false;
}

std::vector<int> AddRow(Crowd& crowd, float x, float first_z, int count, const Vec3& target_offset) {
  std::vector<int> agents;
  for (int i = 0; i < count; ++i) {
    const Vec3 start(x, 0.0f, first_z + 1.5f * static_cast<float>(i));
    const Result<int> agent = crowd.AddAgent(start);
    EXPECT_TRUE(agent.ok()) << agent.error().message;
    if (!agent) continue;
    EXPECT_TRUE(crowd.SetTarget(*agent, start + target_offset).ok());
    agents.push_back(*agent);
  }
  return agents;
}

// Six agents to targets 55 m east, round a wall, on tiles built as they go; the corridor reaches `reach`
// metres along the way at a time (the rest is a route of corners it moves along).
void WalkRoundTheWallOnTilesNotBuilt(float reach) {
  auto world = MakeWorld();
  AddSlab(*world, 0.0f, 5 * 12.8f, 0.0f, 12.8f, 0.0f);
  AddSlab(*world, 30.0f, 31.0f, 0.0f, 9.0f, 3.0f);  // a wall to walk round
  auto service = MakeService(*world, PersonService(64));
  ASSERT_TRUE(service->RequestAround(Vec3(3, 0, 6), 4.0f).ok());
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(30)));
  navmesh::CrowdConfig config;
  config.corridor_reach = reach;
  auto crowd = std::move(*Crowd::Create(*service, 0, config));
  const std::vector<int> agents = AddRow(*crowd, 3.0f, 2.0f, 6, Vec3(55.0f, 0.0f, 0.0f));
  ASSERT_EQ(agents.size(), 6u);
  EXPECT_TRUE(WalkUntilArrived(*crowd, agents, 60.0));
  for (int agent : agents) EXPECT_NEAR(crowd->position(agent)->x(), 58.0f, 0.6f);
  EXPECT_EQ(crowd->stats().off_mesh, 0u);
  EXPECT_EQ(crowd->stats().stuck_agents, 0u);
  EXPECT_GE(service->navmesh(0).tile_count(), 5);  // asked for ahead of them
}

TEST(Crowd, AgentsWalkToTargetsOnTilesNotBuiltWhenTheySetOut) {
  WalkRoundTheWallOnTilesNotBuilt(navmesh::CrowdConfig().corridor_reach);
}

TEST(Crowd, AShortCorridorFollowsTheRouteRoundCorners) {
  WalkRoundTheWallOnTilesNotBuilt(5.0f);
}

TEST(Crowd, ATargetInsideARockIsReachedAtTheGroundNearestIt) {
  auto world = MakeWorld();
  AddSlab(*world, 0.0f, 12.8f, 0.0f, 12.8f, 0.0f);
  AddSlab(*world, 8.0f, 9.0f, 5.0f, 6.0f, 2.0f);  // a rock 1 m across: its middle is 0.9 m from any ground
  auto service = BuildArea(*world, TileArea(1), PersonService(16));
  auto crowd = std::move(*Crowd::Create(*service, 0));
  const int agent = *crowd->AddAgent(Vec3(2, 0, 5.5f));
  ASSERT_TRUE(crowd->SetTarget(agent, Vec3(8.5f, 0, 5.5f)).ok());
  for (int frame = 0; frame < 30 * 6 && *crowd->state(agent) != CrowdAgentState::kArrived; ++frame)
    ASSERT_TRUE(crowd->Update(1.0f / 30.0f).ok());
  EXPECT_EQ(*crowd->state(agent), CrowdAgentState::kArrived);
  // At the navmesh's edge by the rock's west face (its radius and a cell off the rock), within
  // arrive_distance.
  EXPECT_GT(crowd->position(agent)->x(), 6.8f);
  EXPECT_LT(crowd->position(agent)->x(), 7.8f);
  EXPECT_FALSE(*crowd->stuck(agent));
}

TEST(Crowd, AnAgentWhoseTargetIsWalledOffIsStuckAndOneWaitingForTilesIsNot) {
  auto world = MakeWorld();
  AddSlab(*world, 0.0f, 2 * 12.8f, 0.0f, 12.8f, 0.0f);
  AddSlab(*world, 12.0f, 13.0f, 0.0f, 12.8f, 3.0f);  // a wall across the floor, end to end
  auto service = BuildArea(*world, TileArea(2), PersonService(16));
  auto crowd = std::move(*Crowd::Create(*service, 0));
  const int walled_off = *crowd->AddAgent(Vec3(6, 0, 6));
  ASSERT_TRUE(crowd->SetTarget(walled_off, Vec3(20, 0, 6)).ok());
  const int waiting = *crowd->AddAgent(Vec3(6, 0, 8));
  ASSERT_TRUE(crowd->SetTarget(waiting, Vec3(-40, 0, 8)).ok());  // tiles no one builds in this test
  EXPECT_FALSE(*crowd->stuck(walled_off));
  // Four seconds to the wall, then more than five without getting nearer.
  for (int frame = 0; frame < 30 * 10; ++frame) ASSERT_TRUE(crowd->Update(1.0f / 30.0f).ok());
  EXPECT_TRUE(*crowd->stuck(walled_off));
  EXPECT_LT(crowd->position(walled_off)->x(), 12.0f);
  EXPECT_FALSE(*crowd->stuck(waiting));
  EXPECT_EQ(*crowd->state(waiting), CrowdAgentState::kWaiting);
  EXPECT_FALSE(crowd->stuck(99).ok());
}

TEST(Crowd, BadAgentsAndCallsAreRefused) {
  auto world = MakeWorld();
  AddFloor(*world, 1);
  auto service = BuildArea(*world, TileArea(1), PersonService(16));
  EXPECT_FALSE(Crowd::Create(*service, 3).ok());
  navmesh::CrowdConfig no_reach;
  no_reach.corridor_reach = 0.0f;
  EXPECT_FALSE(Crowd::Create(*service, 0, no_reach).ok());
  auto crowd = std::move(*Crowd::Create(*service, 0));
  EXPECT_FALSE(crowd->AddAgent(Vec3(100, 0, 100)).ok());  // off the built navmesh
  EXPECT_FALSE(crowd->AddAgent(Vec3(std::nanf(""), 0, 1)).ok());
  const int agent = *crowd->AddAgent(Vec3(5, 0, 5));
  EXPECT_FALSE(crowd->SetTarget(agent + 1, Vec3(6, 0, 6)).ok());
  EXPECT_FALSE(crowd->SetTarget(agent, Vec3(6, std::nanf(""), 6)).ok());
  EXPECT_FALSE(crowd->Update(0.0f).ok());
  ASSERT_TRUE(crowd->RemoveAgent(agent).ok());
  EXPECT_FALSE(crowd->RemoveAgent(agent).ok());
  // A removed or never-made agent's id is an error, not another agent's data.
  EXPECT_FALSE(crowd->position(agent).ok());
  EXPECT_FALSE(crowd->state(agent).ok());
  EXPECT_FALSE(crowd->velocity(-1).ok());
  EXPECT_FALSE(crowd->position(1 << 20).ok());
  EXPECT_EQ(crowd->agent_count(), 0);
}

// A long corridor of tiles on a small budget: tiles behind the agents are evicted, and a thread keeps
// invalidating the tiles under and just ahead of them (as a body moving there would), so those are rebuilt
// (their polygons replaced) again and again while the agents walk on them.
TEST(CrowdThreads, AgentsKeepWalkingWhileTheirTilesAreRebuiltAndEvicted) {
  auto world = MakeWorld();
  AddSlab(*world, 0.0f, 8 * 12.8f, 0.0f, 12.8f, 0.0f);
  auto service = MakeService(*world, PersonService(5));
  ASSERT_TRUE(service->RequestAround(Vec3(3, 0, 6), 4.0f).ok());
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(30)));
  navmesh::CrowdConfig config;
  config.lookahead = 20.0f;
  auto crowd = std::move(*Crowd::Create(*service, 0, config));
  const std::vector<int> agents = AddRow(*crowd, 3.0f, 2.0f, 6, Vec3(95.0f, 0.0f, 0.0f));
  ASSERT_EQ(agents.size(), 6u);
  std::atomic<bool> stop{false};
  std::atomic<float> front{3.0f};  // where the agents are: the game thread's own record, shared by value
  std::thread invalidator([&] {
    while (!stop.load()) {
      const float x = front.load();
      EXPECT_TRUE(service->Invalidate(AABB(Vec3(x - 6.0f, -1, 0), Vec3(x + 12.8f, 1, 12.8f))).ok());
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  const bool arrived =
      WalkUntilArrived(*crowd, agents, 120.0, [&] { front = crowd->position(agents[0])->x(); });
  stop = true;
  invalidator.join();
  EXPECT_TRUE(arrived);
  const navmesh::CrowdStats& stats = crowd->stats();
  EXPECT_EQ(stats.off_mesh, 0u);  // every agent on a valid polygon after every update
  EXPECT_GT(stats.replans, 0u);   // corridors through replaced tiles were found and replanned
  EXPECT_GT(service->stats().rebuilds, 0u);
  EXPECT_GT(service->stats().evictions, 0u);
  EXPECT_EQ(service->stats().failures, 0u);
}

}  // namespace
}  // namespace strata::test
