// BodyInterface: bad input is rejected with a clear error and leaves the world unchanged; thread safety.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <random>
#include <thread>

#include "TestWorld.h"

namespace strata::test {
namespace {

// Everything a failed call must leave untouched.
struct WorldSnapshot {
  std::vector<BodyID> in_world;
  std::vector<Vec3> positions;
  std::uint32_t created;
  std::size_t broad_phase;

  static WorldSnapshot Of(PhysicsSystem& world) {
    WorldSnapshot snapshot{
        world.BodiesInWorld(), {}, world.body_manager().body_count(), world.broad_phase().body_count()};
    for (const BodyID id : snapshot.in_world) snapshot.positions.push_back(Position(world, id));
    return snapshot;
  }
  bool operator==(const WorldSnapshot&) const = default;
};

class BodyInterfaceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    world_ = MakeWorld({}, 8);
    floor_ = Add(*world_, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
    box_ = Add(*world_, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 2, 0)));
    before_ = WorldSnapshot::Of(*world_);
  }
  void ExpectUnchanged() { EXPECT_EQ(WorldSnapshot::Of(*world_), before_); }

  std::unique_ptr<PhysicsSystem> world_;
  BodyID floor_, box_;
  WorldSnapshot before_;
};

TEST_F(BodyInterfaceTest, StaleIdsAreRejected) {
  auto extra = world_->bodies().CreateAndAddBody(Dynamic(Sphere(0.5f), Vec3(3, 1, 0)));
  ASSERT_TRUE(extra.ok());
  ASSERT_TRUE(world_->bodies().RemoveAndDestroyBody(*extra).ok());
  before_ = WorldSnapshot::Of(*world_);
  for (const BodyID stale : {*extra, BodyID{}, BodyID{9999, 1}, BodyID{box_.index, box_.generation + 1}}) {
    const Status status = world_->bodies().SetPosition(stale, Vec3(1, 1, 1));
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, ErrorCode::kStaleBodyId);
    EXPECT_NE(status.message().find("body"), std::string::npos);
    EXPECT_FALSE(world_->bodies().GetPosition(stale).ok());
    EXPECT_FALSE(world_->bodies().AddBody(stale).ok());
    EXPECT_FALSE(world_->bodies().RemoveBody(stale).ok());
    EXPECT_FALSE(world_->bodies().DestroyBody(stale).ok());
  }
  // The slot was reused with a new generation; the old id must not reach the new body.
  auto reused = world_->bodies().CreateBody(Dynamic(Sphere(0.5f), Vec3(3, 1, 0)));
  ASSERT_TRUE(reused.ok());
  EXPECT_EQ(reused->index, extra->index);
  EXPECT_NE(reused->generation, extra->generation);
  EXPECT_FALSE(world_->bodies().GetPosition(*extra).ok());
  ASSERT_TRUE(world_->bodies().DestroyBody(*reused).ok());
  ExpectUnchanged();
}

TEST_F(BodyInterfaceTest, NonFiniteValuesAreRejected) {
  EXPECT_FALSE(world_->bodies().SetPosition(box_, Vec3(NAN, 0, 0)).ok());
  EXPECT_FALSE(world_->bodies().SetPosition(box_, Vec3(0, INFINITY, 0)).ok());
  EXPECT_FALSE(world_->bodies().SetRotation(box_, Quat(NAN, 0, 0, 0)).ok());
  EXPECT_FALSE(world_->bodies().SetLinearVelocity(box_, Vec3(0, NAN, 0)).ok());
  EXPECT_FALSE(world_->bodies().AddImpulse(box_, Vec3(INFINITY, 0, 0)).ok());
  EXPECT_FALSE(world_->bodies().AddForce(box_, Vec3(0, 0, NAN)).ok());
  EXPECT_FALSE(world_->Step(NAN).ok());
  EXPECT_FALSE(world_->Step(-1.0f).ok());
  auto created = world_->bodies().CreateAndAddBody(Dynamic(Sphere(1), Vec3(NAN, 0, 0)));
  ASSERT_FALSE(created.ok());
  EXPECT_EQ(created.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(created.error().message.find("position"), std::string::npos);
  ExpectUnchanged();
}

TEST_F(BodyInterfaceTest, BadMassAndShapesAreRejected) {
  BodyCreationSettings settings = Dynamic(Sphere(1), Vec3(0, 5, 0));
  settings.mass = 0.0f;
  EXPECT_FALSE(world_->bodies().CreateAndAddBody(settings).ok());
  settings.mass = -3.0f;
  EXPECT_FALSE(world_->bodies().CreateAndAddBody(settings).ok());
  settings.mass.reset();
  settings.density = 0.0f;
  EXPECT_FALSE(world_->bodies().CreateAndAddBody(settings).ok());
  settings = Dynamic(nullptr, Vec3::Zero());
  EXPECT_FALSE(world_->bodies().CreateAndAddBody(settings).ok());
  // A mesh cannot be dynamic.
  const std::vector<Vec3> vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)};
  const std::vector<TriangleMeshShape::Indices> triangles = {{0, 1, 2}};
  EXPECT_FALSE(world_->bodies()
                   .CreateAndAddBody(Dynamic(*TriangleMeshShape::Create(vertices, triangles), Vec3::Zero()))
                   .ok());
  settings = Dynamic(Sphere(1), Vec3::Zero());
  settings.object_layer = 77;
  EXPECT_FALSE(world_->bodies().CreateAndAddBody(settings).ok());
  settings = Dynamic(Sphere(1), Vec3::Zero());
  settings.restitution = 1.5f;
  EXPECT_FALSE(world_->bodies().CreateAndAddBody(settings).ok());
  ExpectUnchanged();
}

TEST_F(BodyInterfaceTest, WrongStatesAreRejected) {
  EXPECT_EQ(world_->bodies().AddBody(box_).error().code, ErrorCode::kInvalidState);      // already added
  EXPECT_EQ(world_->bodies().DestroyBody(box_).error().code, ErrorCode::kInvalidState);  // still in the world
  EXPECT_FALSE(world_->bodies().SetLinearVelocity(floor_, Vec3(1, 0, 0)).ok());          // static
  ASSERT_TRUE(world_->bodies().RemoveBody(box_).ok());
  EXPECT_EQ(world_->bodies().RemoveBody(box_).error().code, ErrorCode::kInvalidState);  // removed twice
  ASSERT_TRUE(world_->bodies().AddBody(box_).ok());
  ExpectUnchanged();
}

TEST_F(BodyInterfaceTest, BatchAddIsAllOrNothing) {
  auto a = world_->bodies().CreateBody(Dynamic(Sphere(0.5f), Vec3(3, 1, 0)));
  auto b = world_->bodies().CreateBody(Dynamic(Sphere(0.5f), Vec3(-3, 1, 0)));
  ASSERT_TRUE(a.ok() && b.ok());
  before_ = WorldSnapshot::Of(*world_);
  const std::vector<BodyID> with_present = {*a, box_, *b};
  EXPECT_FALSE(world_->bodies().AddBodies(with_present).ok());
  const std::vector<BodyID> with_duplicate = {*a, *b, *a};
  EXPECT_FALSE(world_->bodies().AddBodies(with_duplicate).ok());
  ExpectUnchanged();
  const std::vector<BodyID> good = {*a, *b};
  EXPECT_TRUE(world_->bodies().AddBodies(good).ok());
  EXPECT_EQ(world_->body_count_in_world(), 4u);
}

TEST_F(BodyInterfaceTest, CapacityIsEnforced) {
  std::vector<BodyID> created;
  for (int i = 0; i < 6; ++i)
    created.push_back(*world_->bodies().CreateBody(Dynamic(Sphere(0.1f), Vec3(0, 5, 0))));
  auto overflow = world_->bodies().CreateBody(Dynamic(Sphere(0.1f), Vec3(0, 5, 0)));
  ASSERT_FALSE(overflow.ok());
  EXPECT_EQ(overflow.error().code, ErrorCode::kCapacityExceeded);
  for (const BodyID id : created) ASSERT_TRUE(world_->bodies().DestroyBody(id).ok());
  ExpectUnchanged();
}

TEST_F(BodyInterfaceTest, SettersAndGettersRoundTrip) {
  ASSERT_TRUE(world_->bodies()
                  .SetPositionAndRotation(box_, Vec3(1, 2, 3), Quat(Eigen::AngleAxisf(0.5f, Vec3::UnitY())))
                  .ok());
  EXPECT_TRUE(Position(*world_, box_).isApprox(Vec3(1, 2, 3)));
  EXPECT_TRUE(world_->bodies().GetRotation(box_)->isApprox(Quat(Eigen::AngleAxisf(0.5f, Vec3::UnitY()))));
  ASSERT_TRUE(world_->bodies().SetLinearVelocity(box_, Vec3(1, 0, 0)).ok());
  ASSERT_TRUE(world_->bodies().AddImpulse(box_, Vec3(1000.0f, 0, 0)).ok());  // a 1 m cube of 1000 kg
  EXPECT_TRUE(Velocity(*world_, box_).isApprox(Vec3(2, 0, 0), 1e-5f));
  const AABB bounds = *world_->bodies().GetWorldBounds(box_);
  EXPECT_TRUE(bounds.Contains(Vec3(1, 2, 3)));
}

// A body keeps its shape's local bounds and whether they turn with it, so that moves read no shape: its
// world bounds after any move must still be the shape's own, and tight (a sphere's do not grow as it turns).
TEST(BodyBounds, AfterEveryMoveTheyAreTheShapesOwnAndTight) {
  auto world = MakeWorld();
  const std::vector<Vec3> tetra = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const std::vector<ShapeRef> shapes = {Box(0.5f, 1.0f, 2.0f), Sphere(0.7f), Capsule(1.0f, 0.3f),
                                        *ConvexHullShape::Create(tetra)};
  std::mt19937 random(17);
  std::uniform_real_distribution<float> coordinate(-50.0f, 50.0f), unit(-1.0f, 1.0f);
  for (const ShapeRef& shape : shapes) {
    const BodyID id = Add(*world, Dynamic(shape, Vec3(0, 10, 0)));
    for (int move = 0; move < 20; ++move) {
      const Vec3 position(coordinate(random), coordinate(random), coordinate(random));
      const Quat rotation = Quat(unit(random), unit(random), unit(random), unit(random)).normalized();
      ASSERT_TRUE(world->bodies().SetPositionAndRotation(id, position, rotation).ok());
      const Pose pose{position, *world->bodies().GetRotation(id)};
      const AABB bounds = *world->bodies().GetWorldBounds(id);
      const AABB expected = shape->WorldBounds(pose);
      EXPECT_EQ(bounds.min, expected.min);
      EXPECT_EQ(bounds.max, expected.max);
      // Tight: every face of the bounds is touched by the shape's farthest point that way.
      for (int axis = 0; axis < 3; ++axis) {
        const Vec3 direction = Vec3::Unit(axis);
        const ConvexShape& convex = static_cast<const ConvexShape&>(*shape);
        const float reach_max = pose.ToWorld(convex.Support(pose.rotation.conjugate() * direction))[axis];
        const float reach_min = pose.ToWorld(convex.Support(pose.rotation.conjugate() * -direction))[axis];
        // A box's and a sphere's bounds are exact; a capsule's and a hull's are their local box turned.
        const bool exact = shape->type() == ShapeType::kSphere || shape->type() == ShapeType::kBox;
        const float room = exact ? 1e-4f : 1.5f;
        EXPECT_LE(bounds.max[axis] - reach_max, room) << "shape " << static_cast<int>(shape->type());
        EXPECT_LE(reach_min - bounds.min[axis], room);
        EXPECT_GE(bounds.max[axis], reach_max - 1e-4f);
        EXPECT_LE(bounds.min[axis], reach_min + 1e-4f);
      }
      if (shape->type() == ShapeType::kSphere) {
        EXPECT_TRUE(bounds.max.isApprox(position + Vec3::Constant(0.7f), 1e-6f));
        EXPECT_TRUE(bounds.min.isApprox(position - Vec3::Constant(0.7f), 1e-6f));
      }
    }
  }
}

// Worker threads create, move, query and destroy bodies while another thread steps the world.
void ConcurrentCreateMoveQueryAndStep(int workers, int bodies_per_worker) {
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(workers * bodies_per_worker + 16);
  config.thread_count = 2;
  auto world = std::move(*PhysicsSystem::Create(config));
  Add(*world, Static(Box(100, 1, 100), Vec3(0, -1, 0)));
  std::atomic<bool> stop{false};
  std::atomic<int> failures{0};
  std::atomic<int> removed{0};
  auto worker = [&](int seed) {
    std::vector<BodyID> mine;
    for (int i = 0; i < bodies_per_worker; ++i) {
      const Vec3 position(seed * 5.0f - 40.0f, 1.0f + i % 7, (i % 10) * 1.0f);
      auto id = world->bodies().CreateAndAddBody(Dynamic(Sphere(0.3f), position));
      if (!id.ok()) {
        ++failures;
        continue;
      }
      mine.push_back(*id);
      if (!world->bodies().SetLinearVelocity(*id, Vec3(0.5f, 0, 0)).ok()) ++failures;
      auto hit = world->query().CastRay(position + Vec3(0, 10, 0), Vec3(0, -20, 0));
      if (!hit.ok() || !hit->has_value()) ++failures;  // the floor is always there
      if (i % 3 == 0) {
        if (!world->bodies().RemoveAndDestroyBody(mine.front()).ok()) ++failures;
        mine.erase(mine.begin());
        ++removed;
      }
    }
  };
  std::thread stepper([&] {
    while (!stop) (void)world->Step(1.0f / 60.0f);
  });
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(worker, w + 1);
  for (std::thread& thread : threads) thread.join();
  stop = true;
  stepper.join();
  EXPECT_EQ(failures.load(), 0);
  const std::size_t expected = 1 + static_cast<std::size_t>(workers * bodies_per_worker - removed.load());
  EXPECT_EQ(world->body_count_in_world(), expected);
  EXPECT_EQ(world->broad_phase().body_count(), expected);
  EXPECT_EQ(world->body_manager().body_count(), expected);
}

TEST(BodyInterfaceThreads, ConcurrentCreateMoveQueryAndStep) {
  ConcurrentCreateMoveQueryAndStep(3, 200);
}

TEST(BodyInterfaceThreadsStress, ConcurrentCreateMoveQueryAndStepLong) {
  ConcurrentCreateMoveQueryAndStep(8, 3000);
}

// Threads teleport the same few static bodies (the step never refreshes a static body's bounds) to places
// no two moves share, while a step runs. A move gives the broad phase its bounds after releasing the body's
// lock (BroadPhaseMoveOrderTest forces the reorderings that can cause); here the whole path runs beside the
// step: the broad phase must end with each body at its last move. Checked after a full rebuild, which sizes
// every leaf from the bounds it holds: each body is found where it is, and nowhere it only was.
bool Found(const std::vector<BodyID>& ids, BodyID id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

void ConcurrentMovesOfTheSameBodies(int workers, int moves_per_worker) {
  PhysicsSystemConfig config;
  config.max_bodies = 64;
  config.thread_count = 2;
  auto world = std::move(*PhysicsSystem::Create(config));
  BodyInterface& bodies = world->bodies();
  std::vector<BodyID> moved;
  for (int i = 0; i < 3; ++i) moved.push_back(Add(*world, Static(Box(0.5f, 0.5f, 0.5f), Vec3(0, -50, 0))));
  Add(*world, Dynamic(Sphere(0.5f), Vec3(0, 100, 500)));  // gives the step something to do
  // Move m of worker w goes to its own cell of a 4 m grid.
  auto place = [&](int w, int m) {
    return Vec3(4.0f * static_cast<float>(m), 0.0f, 4.0f * static_cast<float>(w));
  };
  std::atomic<int> failures{0};
  std::atomic<bool> stop{false};
  std::thread stepper([&] {
    while (!stop) (void)world->Step(1.0f / 60.0f);
  });
  auto worker = [&](int w) {
    std::mt19937 random(static_cast<unsigned>(11 + w));
    for (int m = 0; m < moves_per_worker; ++m)
      if (!bodies.SetPosition(moved[random() % moved.size()], place(w, m)).ok()) ++failures;
  };
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(worker, w);
  for (std::thread& thread : threads) thread.join();
  stop = true;
  stepper.join();
  ASSERT_EQ(failures.load(), 0);
  world->broad_phase().Optimize();
  for (const BodyID id : moved) {
    const Vec3 now = *bodies.GetPosition(id);
    const auto here = world->query().CollideAABB(*bodies.GetWorldBounds(id));
    ASSERT_TRUE(here.ok());
    EXPECT_TRUE(Found(*here, id)) << "body " << id.index << " is missing where it is";
    int stale = 0;
    for (int w = 0; w < workers; ++w)
      for (int m = 0; m < moves_per_worker; ++m) {
        const Vec3 was = place(w, m);
        if ((was - now).norm() < 1.0f) continue;
        const auto there =
            world->query().CollideAABB(AABB(was - Vec3::Constant(0.1f), was + Vec3::Constant(0.1f)));
        stale += there.ok() && Found(*there, id) ? 1 : 0;
      }
    EXPECT_EQ(stale, 0) << "body " << id.index << " is still found where an earlier move put it";
  }
}

TEST(BodyInterfaceThreads, MovesOfTheSameBodiesLeaveTheBroadPhaseAtEachBodysLastMove) {
  ConcurrentMovesOfTheSameBodies(4, 300);
}

TEST(BodyInterfaceThreadsStress, MovesOfTheSameBodiesLeaveTheBroadPhaseAtEachBodysLastMoveLong) {
  ConcurrentMovesOfTheSameBodies(8, 3000);
}

// The step's LockAll takes the mutexes that guard slots handed out so far: a small world's step takes as
// many as it has bodies, and once the slots wrap around the mutexes every one.
TEST(BodyManagerLocks, LockAllHoldsExactlyTheMutexesOfSlotsInUse) {
  BodyManager manager(64, 8);
  auto held = [&](std::uint32_t mutex) {
    bool taken = false;
    std::thread reader([&] {
      SpinningSharedMutex& m = manager.MutexFor(mutex);
      taken = !m.try_lock_shared();
      if (!taken) m.unlock_shared();
    });
    reader.join();
    return taken;
  };
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(manager.CreateBody(Dynamic(Sphere(1), Vec3(0, 0, 0))).ok());
  manager.LockAll();
  for (std::uint32_t m = 0; m < 8; ++m) EXPECT_EQ(held(m), m < 3) << "mutex " << m;
  manager.UnlockAll();
  for (std::uint32_t m = 0; m < 8; ++m) EXPECT_FALSE(held(m)) << "mutex " << m;
  for (int i = 0; i < 7; ++i) ASSERT_TRUE(manager.CreateBody(Dynamic(Sphere(1), Vec3(0, 0, 0))).ok());
  manager.LockAll();
  for (std::uint32_t m = 0; m < 8; ++m) EXPECT_TRUE(held(m)) << "mutex " << m;
  manager.UnlockAll();
  for (std::uint32_t m = 0; m < 8; ++m) EXPECT_FALSE(held(m)) << "mutex " << m;
}

// The per-thread lock counters the lock benchmarks report: every acquisition is counted, and one that finds
// the mutex taken is counted as contended; a free mutex adds no contention. (The writer lets go well after
// the reader has tried; nothing here asserts a duration.)
TEST(BodyManagerLocks, ContendedAcquisitionsAreCountedAndTimed) {
  BodyManager manager(8, 4);
  const BodyID body = *manager.CreateBody(Dynamic(Sphere(1), Vec3(0, 0, 0)));
  std::atomic<bool> holding{false}, release{false};
  std::thread writer([&] {
    BodyLockWrite lock(manager, body);
    holding.store(true);
    while (!release.load()) std::this_thread::yield();
  });
  while (!holding.load()) std::this_thread::yield();
  const BodyLockCounts before = ThreadBodyLockCounts();
  std::thread releaser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    release.store(true);
  });
  {
    BodyLockRead blocked(manager, body);  // waits for the writer
    EXPECT_TRUE(blocked.Succeeded());
  }
  const BodyLockCounts after_wait = ThreadBodyLockCounts();
  EXPECT_EQ(after_wait.acquisitions - before.acquisitions, 1u);
  EXPECT_EQ(after_wait.contended - before.contended, 1u);
  writer.join();
  releaser.join();
  { BodyLockRead free(manager, body); }
  const BodyLockCounts after_free = ThreadBodyLockCounts();
  EXPECT_EQ(after_free.acquisitions - after_wait.acquisitions, 1u);
  EXPECT_EQ(after_free.contended, after_wait.contended);
}

}  // namespace
}  // namespace strata::test
