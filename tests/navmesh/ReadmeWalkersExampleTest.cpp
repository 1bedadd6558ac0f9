// The top README's walkers example, compiled and run as written: tests/CMakeLists.txt copies its code block
// (the one after `<!-- compiled as a test: walkers -->`) into ReadmeWalkersExample.inc at configure time.
#include <thread>

#include "NavMeshTestWorld.h"
#include "navmesh/AgentProfile.h"
#include "navmesh/Crowd.h"

namespace strata::test {
namespace {

TEST(ReadmeExample, WalkersRunAsWritten) {
  auto world = MakeWorld();
  AddSlab(*world, -20.0f, 20.0f, -20.0f, 20.0f, 0.0f);
  // What the example's game loop calls: a frame's wait, shortened (the background needs only milliseconds).
  const auto wait_for_next_frame = [] { std::this_thread::sleep_for(std::chrono::milliseconds(2)); };
#include "ReadmeWalkersExample.inc"
  ASSERT_GE(walker, 0) << "the ground around the spawn was never built";
  EXPECT_EQ(*people->state(walker), navmesh::CrowdAgentState::kArrived);
  const Vec3 at = *people->position(walker);
  EXPECT_NEAR(at.x(), target.x(), 0.6f);
  EXPECT_NEAR(at.z(), target.z(), 0.6f);
  // The machine's navmesh was built around the spawn from the same gathers.
  EXPECT_GT(service->navmesh(*service->FindProfile("machine")).polygon_count(), 0);
}

}  // namespace
}  // namespace strata::test
