// The top README's gameplay example, compiled and run as written: tests/CMakeLists.txt copies its code block
// (the one after `<!-- compiled as a test: gameplay -->`) into ReadmeGameplayExample.inc at configure time.
#include "TestWorld.h"
#include "physics/character/Character.h"

namespace strata::test {
namespace {

TEST(ReadmeExample, GameplayRunsAsWritten) {
  auto world = MakeWorld();
  Add(*world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
  // What the example's game code calls.
  int impacts = 0, entries = 0, hits = 0;
  BodyID entered_sensor, visitor, hit_body;
  Vec3 hit_point = Vec3::Zero();
  const auto play_impact = [&](const Vec3& point, float impulse) {
    ++impacts;
    EXPECT_NEAR(point.y(), 0.0f, 0.2f);
    EXPECT_GT(impulse, 0.0f);
  };
  const auto on_enter = [&](BodyID sensor, BodyID body) {
    ++entries;
    entered_sensor = sensor;
    visitor = body;
  };
  const auto on_hit = [&](BodyID body, const Vec3& point, const Vec3&) {
    ++hits;
    hit_body = body;
    hit_point = point;
  };
#include "ReadmeGameplayExample.inc"
  EXPECT_EQ(impacts, 1);  // the crate lands once, at 5.4 m/s
  EXPECT_EQ(entries, 1);
  EXPECT_EQ(entered_sensor, gate_id);
  EXPECT_EQ(visitor, crate_id);
  EXPECT_EQ(hits, 1);
  EXPECT_EQ(hit_body, crate_id);             // the sensor in the way is no obstacle
  EXPECT_NEAR(hit_point.z(), -0.5f, 0.05f);  // its near face (it may settle a little askew)
  EXPECT_TRUE(grounded);
  EXPECT_NEAR(player->feet().x(), 5.0f, 0.1f);
}

}  // namespace
}  // namespace strata::test
