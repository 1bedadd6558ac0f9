// The quad-tree broad phase and the world under concurrent use (run under ThreadSanitizer in CI): threads
// add batches, remove, move, ray cast and overlap while another thread rebuilds or steps. Each worker owns
// its bodies, so after each of its own calls it knows exactly what every query must (not) report.
#include <atomic>
#include <mutex>
#include <random>
#include <thread>

#include "TestWorld.h"
#include "physics/broadphase/QuadTreeBroadPhase.h"

namespace strata::test {
namespace {

// Counts violations and keeps the first message.
class Violations {
 public:
  void Report(const std::string& what) {
    if (count_.fetch_add(1) == 0) {
      std::lock_guard lock(mutex_);
      first_ = what;
    }
  }
  int count() const { return count_.load(); }
  std::string first() const {
    std::lock_guard lock(mutex_);
    return first_;
  }

 private:
  std::atomic<int> count_{0};
  mutable std::mutex mutex_;
  std::string first_;
};

bool Contains(const std::vector<BodyID>& ids, BodyID id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

struct Owned {
  BodyID id;
  AABB bounds;
};

void BroadPhaseUnderConcurrentChange(int workers, int iterations) {
  constexpr std::uint32_t kPerWorker = 300;
  auto layer_setup = std::make_shared<DefaultLayerSetup>();
  QuadTreeBroadPhase broad_phase(kPerWorker * static_cast<std::uint32_t>(workers), layer_setup);
  Violations violations;
  std::atomic<int> workers_left{workers};
  std::vector<std::vector<Owned>> final_sets(static_cast<std::size_t>(workers));

  auto worker = [&](int w) {
    std::mt19937 random(static_cast<unsigned>(100 + w));
    std::uniform_real_distribution<float> coordinate(-200.0f, 200.0f), extent(0.2f, 3.0f);
    auto random_box = [&] {
      const Vec3 center(coordinate(random), coordinate(random) * 0.1f, coordinate(random));
      return AABB::FromCenterHalfExtents(center, Vec3(extent(random), extent(random), extent(random)));
    };
    const std::uint32_t first = static_cast<std::uint32_t>(w) * kPerWorker;
    std::vector<std::uint32_t> generation(kPerWorker, 0);
    std::vector<Owned> present;
    std::vector<std::uint32_t> absent;
    for (std::uint32_t i = 0; i < kPerWorker; ++i) absent.push_back(first + i);
    for (int iteration = 0; iteration < iterations; ++iteration) {
      const int kind = static_cast<int>(random() % 8);
      if (kind <= 1 && !absent.empty()) {  // a streamed batch
        std::vector<BodyID> ids;
        std::vector<AABB> bounds;
        std::vector<ObjectLayer> layers;
        for (std::size_t n = 1 + random() % 25; n > 0 && !absent.empty(); --n) {
          const std::uint32_t index = absent.back();
          absent.pop_back();
          ids.push_back({index, ++generation[index - first]});
          bounds.push_back(random_box());
          layers.push_back(random() % 4 ? layers::kMoving : layers::kNonMoving);
        }
        Result<AddBatch> batch = broad_phase.AddBodiesPrepare(ids, bounds, layers);
        const Status added = batch.ok() ? broad_phase.AddBodiesFinalize(*batch) : batch.status();
        if (!added.ok()) {
          // Report and stop this worker, but record what it holds (the final check is per body) and count it
          // out, or the rebuilder would spin forever.
          violations.Report("batch add failed: " + added.message());
          final_sets[static_cast<std::size_t>(w)] = present;
          workers_left.fetch_sub(1);
          return;
        }
        for (std::size_t i = 0; i < ids.size(); ++i) present.push_back({ids[i], bounds[i]});
        std::vector<BodyID> found;
        broad_phase.CollideAABB(bounds.front(), {}, found);
        if (!Contains(found, ids.front())) violations.Report("a just-added body was not found");
      } else if (kind == 2 && !present.empty()) {  // remove one or two
        std::vector<BodyID> ids;
        std::vector<AABB> boxes;
        for (std::size_t n = 1 + random() % 2; n > 0 && !present.empty(); --n) {
          const std::size_t pick = random() % present.size();
          ids.push_back(present[pick].id);
          boxes.push_back(present[pick].bounds);
          absent.push_back(present[pick].id.index);
          present.erase(present.begin() + static_cast<std::ptrdiff_t>(pick));
        }
        if (!broad_phase.RemoveBodies(ids).ok()) violations.Report("remove failed");
        for (std::size_t i = 0; i < ids.size(); ++i) {
          std::vector<BodyID> found;
          broad_phase.CollideAABB(boxes[i], {}, found);
          if (Contains(found, ids[i])) violations.Report("a removed body was returned after its removal");
        }
      } else if (kind <= 5 && !present.empty()) {  // move, then find it where it is now
        Owned& body = present[random() % present.size()];
        body.bounds = random() % 2 ? random_box() : body.bounds.Expanded(0.5f);
        if (!broad_phase.UpdateBody(body.id, body.bounds).ok()) violations.Report("move failed");
        std::vector<BodyID> found;
        broad_phase.CollideAABB(body.bounds, {}, found);
        if (!Contains(found, body.id))
          violations.Report("a moved body was missed by a box query of its bounds");
        const Vec3 center = body.bounds.Center();
        std::vector<BroadPhaseRayHit> hits;
        broad_phase.CastRay(center + Vec3(0, 50, 0), Vec3(0, -100, 0), {}, hits);
        if (std::none_of(hits.begin(), hits.end(),
                         [&](const BroadPhaseRayHit& h) { return h.id == body.id; }))
          violations.Report("a moved body was missed by a ray through it");
        found.clear();
        broad_phase.CollideSphere(center, 0.1f, {}, found);
        if (!Contains(found, body.id)) violations.Report("a moved body was missed by a sphere at its centre");
      } else {  // queries over other workers' bodies, only for the races
        std::vector<BodyID> found;
        const AABB block = AABB::FromCenterHalfExtents(random_box().Center(), Vec3(6.4f, 10.0f, 6.4f));
        broad_phase.CollideAABB(block, {}, found);
        std::vector<BroadPhaseRayHit> hits;
        broad_phase.CastRay(block.Center(), Vec3(coordinate(random), 0, coordinate(random)), {}, hits);
      }
    }
    final_sets[static_cast<std::size_t>(w)] = present;
    workers_left.fetch_sub(1);
  };

  std::thread rebuilder([&] {
    std::vector<BodyPair> pairs;
    std::vector<std::uint8_t> flags(kPerWorker * static_cast<std::size_t>(workers), 0);
    std::vector<BodyID> active;
    int round = 0;
    BroadPhasePin held;
    while (workers_left.load() > 0) {
      // Hold a pin over a few rebuilds now and then, reading through it.
      if (round % 7 == 0) held = broad_phase.Pin();
      round % 10 == 9 ? broad_phase.Optimize() : broad_phase.Update();
      std::vector<BodyID> all;
      class Collect final : public BroadPhaseCollector {
       public:
        void AddHit(BodyID, float) override { ++count; }
        int count = 0;
      } collector;
      broad_phase.CollideAABB(held, AABB(Vec3::Constant(-300), Vec3::Constant(300)), {}, collector);
      pairs.clear();
      broad_phase.FindPairs(active, flags, *layer_setup, pairs);
      if (round % 7 == 3) held.Release();
      ++round;
    }
  });
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(worker, w);
  for (std::thread& thread : threads) thread.join();
  rebuilder.join();

  EXPECT_EQ(violations.count(), 0) << violations.first();
  std::size_t expected = 0;
  for (const auto& set : final_sets) expected += set.size();
  EXPECT_EQ(broad_phase.body_count(), expected);
  broad_phase.Update();
  std::vector<BodyID> everything;
  broad_phase.CollideAABB(AABB(Vec3::Constant(-1e4f), Vec3::Constant(1e4f)), {}, everything);
  EXPECT_EQ(everything.size(), expected);
  for (const auto& set : final_sets)
    for (const Owned& body : set) EXPECT_TRUE(Contains(everything, body.id));
  EXPECT_EQ(broad_phase.stats().retired_nodes, 0u);
}

TEST(QuadTreeBroadPhaseThreads, BatchesRemovesMovesAndQueriesWhileRebuilding) {
  BroadPhaseUnderConcurrentChange(3, 5000);
}

// A reader that pins a generation through many full rebuilds keeps every old tree's nodes: with a small
// pool they run out, rebuilds are skipped, and a batch then waits for the pin to go (and a rebuild to free
// the nodes) instead of failing.
TEST(QuadTreeBroadPhaseThreads, ABatchWaitsForNodesThatPinnedGenerationsHold) {
  constexpr std::uint32_t kBodies = 256;
  QuadTreeBroadPhase broad_phase(kBodies, std::make_shared<DefaultLayerSetup>(), /*max_nodes=*/400);
  std::mt19937 random(5);
  std::uniform_real_distribution<float> coordinate(-50.0f, 50.0f);
  auto random_box = [&] {
    return AABB::FromCenterHalfExtents(Vec3(coordinate(random), 0, coordinate(random)), Vec3::Constant(0.5f));
  };
  const auto batch_of = [&](std::uint32_t first, std::uint32_t count) {
    std::vector<BodyID> ids;
    std::vector<AABB> bounds;
    for (std::uint32_t i = first; i < first + count; ++i)
      ids.push_back({i, 1}), bounds.push_back(random_box());
    return std::pair{ids, bounds};
  };
  const auto [placed, placed_bounds] = batch_of(0, 120);
  const std::vector<ObjectLayer> moving(120, layers::kMoving);
  Result<AddBatch> first = broad_phase.AddBodiesPrepare(placed, placed_bounds, moving);
  ASSERT_TRUE(first.ok() && broad_phase.AddBodiesFinalize(*first).ok());
  BroadPhasePin pin = broad_phase.Pin();
  for (int rebuild = 0; rebuild < 20; ++rebuild) {
    for (const BodyID id : placed) ASSERT_TRUE(broad_phase.UpdateBody(id, random_box()).ok());
    broad_phase.Optimize();
  }
  ASSERT_GT(broad_phase.stats().rebuilds_skipped, 0u) << "the pool should have run short under the pin";
  std::thread reader([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    pin.Release();
    broad_phase.Update();  // what a step does: frees the nodes no generation needs any more
  });
  const auto [late, late_bounds] = batch_of(120, 100);
  Result<AddBatch> waited =
      broad_phase.AddBodiesPrepare(late, late_bounds, std::vector<ObjectLayer>(100, layers::kMoving));
  reader.join();
  ASSERT_TRUE(waited.ok()) << waited.error().message;
  ASSERT_TRUE(broad_phase.AddBodiesFinalize(*waited).ok());
  std::vector<BodyID> found;
  broad_phase.CollideAABB(AABB(Vec3::Constant(-100), Vec3::Constant(100)), {}, found);
  EXPECT_EQ(found.size(), 220u);
  for (const BodyID id : late) EXPECT_TRUE(Contains(found, id));
}

TEST(QuadTreeBroadPhaseThreadsStress, BatchesRemovesMovesAndQueriesWhileRebuildingLong) {
  BroadPhaseUnderConcurrentChange(8, 40000);
}

// The same at world level: streamed batches (prepare on the worker, finalize), teleports, removals and
// queries while another thread steps. Workers' bodies are static or kinematic at rest, so they stay where
// the worker put them and the worker knows what its queries must see.
void WorldUnderConcurrentChange(int workers, int iterations) {
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(workers * 200 + 16);
  config.thread_count = 2;
  auto world = std::move(*PhysicsSystem::Create(config));
  Add(*world, Static(Box(300, 1, 300), Vec3(0, -1, 0)));
  std::vector<BodyID> rolling;
  for (int i = 0; i < 20; ++i)
    rolling.push_back(Add(*world, Dynamic(Sphere(0.5f), Vec3(float(i) * 3 - 30, 2, 0))));
  Violations violations;
  std::atomic<bool> stop{false};
  std::atomic<int> in_world{21};
  BodyInterface& bodies = world->bodies();

  std::vector<std::vector<BodyID>> final_sets(static_cast<std::size_t>(workers));
  auto worker = [&](int w) {
    std::mt19937 random(static_cast<unsigned>(7 + w));
    std::uniform_real_distribution<float> coordinate(-100.0f, 100.0f);
    std::vector<BodyID> present;
    for (int iteration = 0; iteration < iterations; ++iteration) {
      const int kind = static_cast<int>(random() % 6);
      if (kind == 0 && present.size() < 150) {
        std::vector<BodyID> batch_ids;
        for (int n = 0; n < 8; ++n) {
          BodyCreationSettings settings = n % 2 ? Static(Box(0.5f, 0.5f, 0.5f), Vec3::Zero())
                                                : Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3::Zero());
          if (n % 2 == 0) settings.motion_type = MotionType::kKinematic;
          settings.position = Vec3(coordinate(random), 5.0f + float(n), coordinate(random));
          auto id = bodies.CreateBody(settings);
          if (!id.ok()) {
            final_sets[static_cast<std::size_t>(w)] = present;
            return violations.Report("create failed: " + id.error().message);
          }
          batch_ids.push_back(*id);
        }
        Result<BodyAddBatch> batch = bodies.AddBodiesPrepare(batch_ids);
        if (!batch.ok() || !bodies.AddBodiesFinalize(*batch).ok()) {
          final_sets[static_cast<std::size_t>(w)] = present;
          return violations.Report("batch add failed");
        }
        present.insert(present.end(), batch_ids.begin(), batch_ids.end());
        in_world.fetch_add(static_cast<int>(batch_ids.size()));
      } else if (kind == 1 && !present.empty()) {
        const std::size_t pick = random() % present.size();
        const BodyID id = present[pick];
        const AABB bounds = *bodies.GetWorldBounds(id);
        if (!bodies.RemoveAndDestroyBody(id).ok()) violations.Report("remove failed");
        present.erase(present.begin() + static_cast<std::ptrdiff_t>(pick));
        in_world.fetch_sub(1);
        const auto found = world->query().CollideAABB(bounds);
        if (!found.ok() || Contains(*found, id))
          violations.Report("a removed body was returned after removal");
      } else if (kind <= 3 && !present.empty()) {
        const BodyID id = present[random() % present.size()];
        const Vec3 target(coordinate(random), 4.0f, coordinate(random));
        if (!bodies.SetPosition(id, target).ok()) violations.Report("teleport failed");
        const auto found = world->query().CollideAABB(*bodies.GetWorldBounds(id));
        if (!found.ok() || !Contains(*found, id))
          violations.Report("a teleported body was missed at its new bounds");
        const auto hits = world->query().CastRayAll(target + Vec3(0, 20, 0), Vec3(0, -40, 0));
        if (!hits.ok() ||
            std::none_of(hits->begin(), hits->end(), [&](const RayCastHit& h) { return h.body == id; }))
          violations.Report("a ray through a teleported body missed it");
      } else {
        const auto hits =
            world->query().CastRayAll(Vec3(coordinate(random), 30, coordinate(random)), Vec3(0, -60, 0));
        if (!hits.ok() || hits->empty()) violations.Report("a ray down onto the floor hit nothing");
      }
    }
    final_sets[static_cast<std::size_t>(w)] = present;
  };
  std::thread stepper([&] {
    while (!stop.load()) (void)world->Step(1.0f / 60.0f);
  });
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(worker, w);
  for (std::thread& thread : threads) thread.join();
  stop = true;
  stepper.join();
  EXPECT_EQ(violations.count(), 0) << violations.first();
  EXPECT_EQ(world->body_count_in_world(), static_cast<std::size_t>(in_world.load()));
  EXPECT_EQ(world->broad_phase().body_count(), static_cast<std::size_t>(in_world.load()));
  // Per body: the world holds exactly the floor, the rolling spheres and what each worker kept.
  std::vector<BodyID> expected = rolling;
  for (const auto& set : final_sets) expected.insert(expected.end(), set.begin(), set.end());
  std::vector<BodyID> in_world_now = world->BodiesInWorld();
  ASSERT_EQ(in_world_now.size(), expected.size() + 1);
  for (const BodyID id : expected) EXPECT_TRUE(Contains(in_world_now, id));
  EXPECT_EQ(world->broad_phase().body_count(), static_cast<std::size_t>(in_world.load()));
}

TEST(PhysicsSystemThreads, StreamedBatchesTeleportsRemovalsAndQueriesWhileStepping) {
  WorldUnderConcurrentChange(3, 1000);
}

TEST(PhysicsSystemThreadsStress, StreamedBatchesTeleportsRemovalsAndQueriesWhileSteppingLong) {
  WorldUnderConcurrentChange(8, 6000);
}

}  // namespace
}  // namespace strata::test
