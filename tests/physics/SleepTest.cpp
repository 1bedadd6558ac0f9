// Sleeping: resting islands sleep after 0.5 s, contacts and API calls wake them.
#include "TestWorld.h"

namespace strata::test {
namespace {

TEST(Sleep, RestingBoxSleepsAfterHalfASecondNotBefore) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
  StepFor(*world, 20);  // 0.33 s of rest
  EXPECT_TRUE(*world->bodies().IsActive(box));
  StepFor(*world, 40);
  EXPECT_FALSE(*world->bodies().IsActive(box));
  EXPECT_EQ(world->last_step_stats().active_bodies, 0u);
}

TEST(Sleep, BodiesThatMayNotSleepStayAwake) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
  StepFor(*world, 120);
  EXPECT_TRUE(*world->bodies().IsActive(box));
}

TEST(Sleep, IslandSleepsAndWakesTogether) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  std::vector<BodyID> stack;
  for (int i = 0; i < 3; ++i)
    stack.push_back(Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f + i, 0))));
  StepFor(*world, 90);
  for (const BodyID id : stack) EXPECT_FALSE(*world->bodies().IsActive(id));
  // Pushing the top box wakes the whole stack on the next step.
  ASSERT_TRUE(world->bodies().AddImpulse(stack[2], Vec3(100, 0, 0)).ok());
  EXPECT_TRUE(*world->bodies().IsActive(stack[2]));
  StepFor(*world, 1);
  for (const BodyID id : stack) EXPECT_TRUE(*world->bodies().IsActive(id));
}

TEST(Sleep, FallingBodyWakesSleepingBody) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID resting = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
  StepFor(*world, 60);
  ASSERT_FALSE(*world->bodies().IsActive(resting));
  Add(*world, Dynamic(Sphere(0.3f), Vec3(0.2f, 3.0f, 0)));
  bool woke = false;
  for (int step = 0; step < 60 && !woke; ++step) {
    StepFor(*world, 1);
    woke = *world->bodies().IsActive(resting);
  }
  EXPECT_TRUE(woke);
}

TEST(Sleep, RemovingWhatHoldsASleepingBodyWakesIt) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID shelf = Add(*world, Static(Box(1, 0.1f, 1), Vec3(0, 2, 0)));
  const BodyID box = Add(*world, Dynamic(Box(0.3f, 0.3f, 0.3f), Vec3(0, 2.4f, 0)));
  StepFor(*world, 60);
  ASSERT_FALSE(*world->bodies().IsActive(box));
  ASSERT_TRUE(world->bodies().RemoveBody(shelf).ok());
  StepFor(*world, 90);
  EXPECT_NEAR(Position(*world, box).y(), 0.3f, 0.02f);  // fell to the floor
}

TEST(Sleep, SleepingBodiesKeepTheirPlace) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
  StepFor(*world, 60);
  const Vec3 asleep = Position(*world, box);
  StepFor(*world, 300);
  EXPECT_EQ(Position(*world, box), asleep);
}

}  // namespace
}  // namespace strata::test
