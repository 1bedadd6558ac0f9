// BodySnapshotTable: off until a reader enables it; once on, every add, teleport and removal through
// BodyInterface is republished, stale ids read nothing, and readers copy while writers publish (label tsan).
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "TestWorld.h"

namespace strata::test {
namespace {

void ExpectMatchesBody(PhysicsSystem& world, BodyID id, const BodySnapshot& snapshot) {
  EXPECT_EQ(snapshot.id, id);
  EXPECT_EQ(snapshot.shape, *world.bodies().GetShape(id));
  EXPECT_EQ(snapshot.motion_type, *world.bodies().GetMotionType(id));
  EXPECT_TRUE(snapshot.pose.position.isApprox(*world.bodies().GetPosition(id)));
  const AABB bounds = *world.bodies().GetWorldBounds(id);
  EXPECT_EQ(snapshot.bounds.min, bounds.min);
  EXPECT_EQ(snapshot.bounds.max, bounds.max);
}

TEST(BodySnapshotTable, IsOffUntilEnabledThenHoldsTheBodiesAlreadyInTheWorld) {
  auto world = MakeWorld();
  const BodyID floor = Add(*world, Static(Box(10, 1, 10), Vec3(5, -1, 5)));
  const BodyID crate = Add(*world, Dynamic(Box(1, 1, 1), Vec3(0, 2, 0)));
  const BodySnapshotTable& table = world->body_snapshots();
  EXPECT_FALSE(table.enabled());
  EXPECT_FALSE(table.Read(floor).has_value());

  table.Enable(world->body_manager());
  table.Enable(world->body_manager());  // a second call changes nothing
  ASSERT_TRUE(table.enabled());
  const auto floor_snapshot = table.Read(floor);
  ASSERT_TRUE(floor_snapshot.has_value());
  ExpectMatchesBody(*world, floor, *floor_snapshot);
  EXPECT_EQ(floor_snapshot->object_layer, layers::kNonMoving);
  const auto crate_snapshot = table.Read(crate);
  ASSERT_TRUE(crate_snapshot.has_value());
  EXPECT_EQ(crate_snapshot->motion_type, MotionType::kDynamic);
}

TEST(BodySnapshotTable, FollowsAddsTeleportsAndRemovalsAndForgetsStaleIds) {
  auto world = MakeWorld();
  const BodySnapshotTable& table = world->body_snapshots();
  table.Enable(world->body_manager());

  auto created = world->bodies().CreateBody(Static(Box(1, 2, 3), Vec3(4, 5, 6)));
  ASSERT_TRUE(created.ok());
  const BodyID wall = *created;
  EXPECT_FALSE(table.Read(wall).has_value()) << "created but not in the world";
  ASSERT_TRUE(world->bodies().AddBody(wall).ok());
  ASSERT_TRUE(table.Read(wall).has_value());
  ExpectMatchesBody(*world, wall, *table.Read(wall));

  ASSERT_TRUE(world->bodies().SetPosition(wall, Vec3(-40, 5, 6)).ok());
  ExpectMatchesBody(*world, wall, *table.Read(wall));
  EXPECT_FLOAT_EQ(table.Read(wall)->bounds.min.x(), -41.0f);

  ASSERT_TRUE(world->bodies().RemoveBody(wall).ok());
  EXPECT_FALSE(table.Read(wall).has_value());
  ASSERT_TRUE(world->bodies().DestroyBody(wall).ok());
  // The slot comes back with a new generation: the old id must not read the new body.
  const BodyID reused = Add(*world, Static(Box(1, 1, 1), Vec3(0, 0, 0)));
  ASSERT_EQ(reused.index, wall.index);
  EXPECT_FALSE(table.Read(wall).has_value());
  EXPECT_TRUE(table.Read(reused).has_value());
}

TEST(BodySnapshotTable, TheStepLeavesSnapshotsAlone) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID ball = Add(*world, Dynamic(Sphere(0.5f), Vec3(0, 3, 0)));
  world->body_snapshots().Enable(world->body_manager());
  StepFor(*world, 30);
  ASSERT_LT(Position(*world, ball).y(), 2.5f);
  // A moving body's pose is the step's: the snapshot keeps the pose it was added at.
  EXPECT_FLOAT_EQ(world->body_snapshots().Read(ball)->pose.position.y(), 3.0f);
}

TEST(BodySnapshotTableThreads, ReadersCopyWhileWritersTeleportAndReadd) {
  auto world = MakeWorld({}, 256);
  const BodySnapshotTable& table = world->body_snapshots();
  table.Enable(world->body_manager());
  std::vector<BodyID> walls;
  for (int i = 0; i < 64; ++i) walls.push_back(Add(*world, Static(Box(1, 1, 1), Vec3(3.0f * i, 0, 0))));
  std::atomic<bool> stop{false};
  std::atomic<int> torn{0};
  std::thread reader([&] {
    while (!stop.load()) {
      for (const BodyID id : walls) {
        const auto snapshot = table.Read(id);
        if (!snapshot) continue;  // between a remove and the re-add
        // Every published wall's bounds start one metre below its z: a copy mixing two publishes would not.
        const float z = snapshot->pose.position.z();
        if (snapshot->bounds.min.z() != z - 1.0f || snapshot->shape == nullptr) ++torn;
      }
    }
  });
  for (int round = 0; round < 200; ++round) {
    for (std::size_t i = 0; i < walls.size(); ++i) {
      const float z = 7.0f * static_cast<float>((round + i) % 5);
      if ((round + i) % 3 == 0) {
        ASSERT_TRUE(world->bodies().RemoveBody(walls[i]).ok());
        ASSERT_TRUE(world->bodies().SetPosition(walls[i], Vec3(3.0f * i, 0, z)).ok());
        ASSERT_TRUE(world->bodies().AddBody(walls[i]).ok());
      } else {
        ASSERT_TRUE(world->bodies().SetPosition(walls[i], Vec3(3.0f * i, 0, z)).ok());
      }
    }
  }
  stop = true;
  reader.join();
  EXPECT_EQ(torn.load(), 0);
  for (std::size_t i = 0; i < walls.size(); ++i) ExpectMatchesBody(*world, walls[i], *table.Read(walls[i]));
}

}  // namespace
}  // namespace strata::test
