// The published dtNavMesh is usable by Detour's own clients: a DetourCrowd agent walks across tiles the
// service built, around an obstacle, to its target.
#include <gtest/gtest.h>

#include <DetourCrowd.h>

#include "NavMeshTestWorld.h"

namespace strata::test {
namespace {

struct CrowdDeleter {
  void operator()(dtCrowd* crowd) const { dtFreeCrowd(crowd); }
};

TEST(NavMeshDetour, CrowdAgentWalksToItsTargetAcrossTiles) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  AddSlab(*world, 11.0f, 14.0f, 4.0f, 20.0f, 2.0f, 2.0f);  // a wall between start and target
  auto service = BuildArea(*world, TileArea(2));
  auto query = MakeQuery(service->navmesh());
  const Vec3 start(4.0f, 0.0f, 12.0f), target(21.0f, 0.0f, 12.0f);
  const auto goal = query->FindNearestPoly(target);
  ASSERT_TRUE(goal.ok());

  // No tiles are published while the crowd runs, so it may use the Detour mesh directly.
  std::unique_ptr<dtCrowd, CrowdDeleter> crowd(dtAllocCrowd());
  ASSERT_TRUE(crowd->init(4, 0.6f, &service->navmesh().detour()));
  dtCrowdAgentParams params{};
  params.radius = 0.6f;
  params.height = 2.0f;
  params.maxAcceleration = 8.0f;
  params.maxSpeed = 3.5f;
  params.collisionQueryRange = 6.0f;
  params.pathOptimizationRange = 15.0f;
  params.updateFlags = DT_CROWD_ANTICIPATE_TURNS | DT_CROWD_OPTIMIZE_VIS | DT_CROWD_OPTIMIZE_TOPO;
  const int agent = crowd->addAgent(start.data(), &params);
  ASSERT_GE(agent, 0);
  ASSERT_TRUE(crowd->requestMoveTarget(agent, goal->poly, goal->point.data()));
  float closest_to_wall = 1e9f;
  for (int tick = 0; tick < 60 * 30; ++tick) {
    crowd->update(1.0f / 60.0f, nullptr);
    const float* position = crowd->getAgent(agent)->npos;
    if (position[2] > 4.0f && position[2] < 20.0f)  // beside the wall's length: stay out of it
      closest_to_wall = std::min(closest_to_wall, std::max(11.0f - position[0], position[0] - 14.0f));
  }
  const float* end = crowd->getAgent(agent)->npos;
  EXPECT_NEAR(end[0], target.x(), 0.5f);
  EXPECT_NEAR(end[2], target.z(), 0.5f);
  EXPECT_GT(closest_to_wall, 0.0f);  // it went round the wall's end, never through it
}

}  // namespace
}  // namespace strata::test
