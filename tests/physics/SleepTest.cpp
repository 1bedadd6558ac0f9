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

// A 4 m bar turning slowly in place, with no gravity: its centre stays put, its ends move 8 cm/s.
BodyID AddTurningBar(PhysicsSystem& world) {
  BodyCreationSettings bar = Dynamic(Box(2.0f, 0.1f, 0.1f), Vec3(0, 5, 0));
  bar.gravity_factor = 0.0f;
  bar.angular_damping = 0.0f;
  const BodyID id = Add(world, bar);
  EXPECT_TRUE(world.bodies().SetAngularVelocity(id, Vec3(0, 0.04f, 0)).ok());
  return id;
}

TEST(Sleep, ThePointMovementRuleWatchesABodysEndsAsJoltDoes) {
  // By speeds, 0.04 rad/s is under the 0.05 rad/s limit: the bar sleeps turning. By its points' movement
  // (Jolt's rule), its ends leave a 1.5 cm sphere within 0.2 s: it stays awake.
  auto by_speed = MakeWorld();
  const BodyID turning_by_speed = AddTurningBar(*by_speed);
  StepFor(*by_speed, 60);
  EXPECT_FALSE(*by_speed->bodies().IsActive(turning_by_speed));

  PhysicsSettings settings;
  settings.sleep_rule = SleepRule::kPointMovement;
  auto by_points = MakeWorld(settings);
  const BodyID turning_by_points = AddTurningBar(*by_points);
  StepFor(*by_points, 120);
  EXPECT_TRUE(*by_points->bodies().IsActive(turning_by_points));

  // A box resting on the floor still sleeps by the point rule, after the same half second.
  Add(*by_points, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID box = Add(*by_points, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(8, 0.5f, 0)));
  StepFor(*by_points, 20);
  EXPECT_TRUE(*by_points->bodies().IsActive(box));
  StepFor(*by_points, 40);
  EXPECT_FALSE(*by_points->bodies().IsActive(box));
  EXPECT_TRUE(*by_points->bodies().IsActive(turning_by_points));
}

TEST(Sleep, SleepSpheresGrowToHoldEveryPlaceAndStartAgainWhenTooWide) {
  SleepSpheres record;
  const std::array<Vec3, 3> start{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)};
  EXPECT_FALSE(record.StayedWithin(start, 0.01f));  // no record yet: it starts one
  std::array<Vec3, 3> moved = start;
  moved[1].x() += 0.015f;  // 1.5 cm out: the smallest sphere holding both places has a radius of 0.75 cm
  EXPECT_TRUE(record.StayedWithin(moved, 0.01f));
  EXPECT_NEAR(record.spheres[1].radius, 0.0075f, 1e-6f);
  EXPECT_NEAR(record.spheres[1].center.x(), 1.0075f, 1e-6f);
  EXPECT_TRUE(record.StayedWithin(start, 0.01f));  // back inside: jitter within the sphere is rest
  moved[1].x() = 0.98f;                            // 2.75 cm from the far side: a radius of 1.375 cm
  EXPECT_FALSE(record.StayedWithin(moved, 0.01f));
  EXPECT_EQ(record.spheres[1].radius, 0.0f);  // started again from where the points are now
  EXPECT_EQ(record.spheres[1].center, moved[1]);
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
