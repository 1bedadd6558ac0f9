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

constexpr std::uint32_t kPerWorker = 300;

// One worker's bodies, ids [first, first + kPerWorker), and the checks it makes after each of its own calls.
class BroadPhaseWorker {
 public:
  BroadPhaseWorker(QuadTreeBroadPhase& broad_phase, Violations& violations, int worker)
      : broad_phase_(broad_phase),
        violations_(violations),
        random_(static_cast<unsigned>(100 + worker)),
        first_(static_cast<std::uint32_t>(worker) * kPerWorker),
        generation_(kPerWorker, 0) {
    for (std::uint32_t i = 0; i < kPerWorker; ++i) absent_.push_back(first_ + i);
  }

  // Runs `iterations` random calls; false when an add failed and the worker stopped.
  bool Run(int iterations) {
    for (int iteration = 0; iteration < iterations; ++iteration) {
      const int kind = static_cast<int>(random_() % 8);
      if (kind <= 1 && !absent_.empty()) {
        if (!AddStreamedBatch()) return false;
      } else if (kind == 2 && !present_.empty()) {
        RemoveSome();
      } else if (kind <= 5 && !present_.empty()) {
        MoveOne();
      } else {
        QueryOthers();
      }
    }
    return true;
  }

  const std::vector<Owned>& present() const { return present_; }

 private:
  AABB RandomBox() {
    const Vec3 center(coordinate_(random_), coordinate_(random_) * 0.1f, coordinate_(random_));
    return AABB::FromCenterHalfExtents(center, Vec3(extent_(random_), extent_(random_), extent_(random_)));
  }

  // A streamed batch, then the first of it found where it was put.
  bool AddStreamedBatch() {
    std::vector<BodyID> ids;
    std::vector<AABB> bounds;
    std::vector<ObjectLayer> layers;
    for (std::size_t n = 1 + random_() % 25; n > 0 && !absent_.empty(); --n) {
      const std::uint32_t index = absent_.back();
      absent_.pop_back();
      ids.push_back({index, ++generation_[index - first_]});
      bounds.push_back(RandomBox());
      layers.push_back(random_() % 4 ? layers::kMoving : layers::kNonMoving);
    }
    Result<AddBatch> batch = broad_phase_.AddBodiesPrepare(ids, bounds, layers);
    const Status added = batch.ok() ? broad_phase_.AddBodiesFinalize(*batch) : batch.status();
    if (!added.ok()) {
      violations_.Report("batch add failed: " + added.message());
      return false;
    }
    for (std::size_t i = 0; i < ids.size(); ++i) present_.push_back({ids[i], bounds[i]});
    std::vector<BodyID> found;
    broad_phase_.CollideAABB(bounds.front(), {}, found);
    if (!Contains(found, ids.front())) violations_.Report("a just-added body was not found");
    return true;
  }

  // One or two removed, then not found where they were.
  void RemoveSome() {
    std::vector<BodyID> ids;
    std::vector<AABB> boxes;
    for (std::size_t n = 1 + random_() % 2; n > 0 && !present_.empty(); --n) {
      const std::size_t pick = random_() % present_.size();
      ids.push_back(present_[pick].id);
      boxes.push_back(present_[pick].bounds);
      absent_.push_back(present_[pick].id.index);
      present_.erase(present_.begin() + static_cast<std::ptrdiff_t>(pick));
    }
    if (!broad_phase_.RemoveBodies(ids).ok()) violations_.Report("remove failed");
    for (std::size_t i = 0; i < ids.size(); ++i) {
      std::vector<BodyID> found;
      broad_phase_.CollideAABB(boxes[i], {}, found);
      if (Contains(found, ids[i])) violations_.Report("a removed body was returned after its removal");
    }
  }

  // One moved, then found where it is now by a box, a ray and a sphere.
  void MoveOne() {
    Owned& body = present_[random_() % present_.size()];
    body.bounds = random_() % 2 ? RandomBox() : body.bounds.Expanded(0.5f);
    if (!broad_phase_.UpdateBody(body.id, body.bounds).ok()) violations_.Report("move failed");
    std::vector<BodyID> found;
    broad_phase_.CollideAABB(body.bounds, {}, found);
    if (!Contains(found, body.id)) violations_.Report("a moved body was missed by a box query of its bounds");
    const Vec3 center = body.bounds.Center();
    std::vector<BroadPhaseRayHit> hits;
    broad_phase_.CastRay(center + Vec3(0, 50, 0), Vec3(0, -100, 0), {}, hits);
    if (std::none_of(hits.begin(), hits.end(), [&](const BroadPhaseRayHit& h) { return h.id == body.id; }))
      violations_.Report("a moved body was missed by a ray through it");
    found.clear();
    broad_phase_.CollideSphere(center, 0.1f, {}, found);
    if (!Contains(found, body.id)) violations_.Report("a moved body was missed by a sphere at its centre");
  }

  // Queries over other workers' bodies, only for the races.
  void QueryOthers() {
    std::vector<BodyID> found;
    const AABB block = AABB::FromCenterHalfExtents(RandomBox().Center(), Vec3(6.4f, 10.0f, 6.4f));
    broad_phase_.CollideAABB(block, {}, found);
    std::vector<BroadPhaseRayHit> hits;
    broad_phase_.CastRay(block.Center(), Vec3(coordinate_(random_), 0, coordinate_(random_)), {}, hits);
  }

  QuadTreeBroadPhase& broad_phase_;
  Violations& violations_;
  std::mt19937 random_;
  std::uniform_real_distribution<float> coordinate_{-200.0f, 200.0f};
  std::uniform_real_distribution<float> extent_{0.2f, 3.0f};
  const std::uint32_t first_;
  std::vector<std::uint32_t> generation_;
  std::vector<Owned> present_;
  std::vector<std::uint32_t> absent_;
};

// Rebuilds, optimizes, finds pairs and reads through a held pin until every worker is done.
void RebuildWhileWorkersRun(QuadTreeBroadPhase& broad_phase, const LayerSetup& layer_setup, int workers,
                            const std::atomic<int>& workers_left) {
  std::vector<BodyPair> pairs;
  std::vector<std::uint8_t> flags(kPerWorker * static_cast<std::size_t>(workers), 0);
  std::vector<BodyID> active;
  int round = 0;
  BroadPhasePin held;
  while (workers_left.load() > 0) {
    // Hold a pin over a few rebuilds now and then, reading through it.
    if (round % 7 == 0) held = broad_phase.Pin();
    round % 10 == 9 ? broad_phase.Optimize() : broad_phase.Update();
    class Collect final : public BroadPhaseCollector {
     public:
      void AddHit(BodyID, float) override { ++count; }
      int count = 0;
    } collector;
    broad_phase.CollideAABB(held, AABB(Vec3::Constant(-300), Vec3::Constant(300)), {}, collector);
    pairs.clear();
    broad_phase.FindPairs(active, flags, layer_setup, pairs);
    if (round % 7 == 3) held.Release();
    ++round;
  }
}

void BroadPhaseUnderConcurrentChange(int workers, int iterations) {
  auto layer_setup = std::make_shared<DefaultLayerSetup>();
  QuadTreeBroadPhase broad_phase(kPerWorker * static_cast<std::uint32_t>(workers), layer_setup);
  Violations violations;
  std::atomic<int> workers_left{workers};
  std::vector<std::vector<Owned>> final_sets(static_cast<std::size_t>(workers));
  auto worker = [&](int w) {
    BroadPhaseWorker bodies(broad_phase, violations, w);
    // A worker whose add failed stops, but what it holds is still checked, and it is counted out either way,
    // or the rebuilder would spin forever.
    bodies.Run(iterations);
    final_sets[static_cast<std::size_t>(w)] = bodies.present();
    workers_left.fetch_sub(1);
  };
  std::thread rebuilder([&] { RebuildWhileWorkersRun(broad_phase, *layer_setup, workers, workers_left); });
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
// One worker's static and kinematic bodies in a stepping world, and the checks it makes after its own calls.
class WorldWorker {
 public:
  WorldWorker(PhysicsSystem& world, Violations& violations, std::atomic<int>& in_world, int worker)
      : world_(world),
        violations_(violations),
        in_world_(in_world),
        random_(static_cast<unsigned>(7 + worker)) {}

  // Runs `iterations` random calls; stops early when a create or add fails.
  void Run(int iterations) {
    for (int iteration = 0; iteration < iterations; ++iteration) {
      const int kind = static_cast<int>(random_() % 6);
      if (kind == 0 && present_.size() < 150) {
        if (!AddBatch()) return;
      } else if (kind == 1 && !present_.empty()) {
        RemoveOne();
      } else if (kind <= 3 && !present_.empty()) {
        TeleportOne();
      } else {
        const auto hits =
            world_.query().CastRayAll(Vec3(coordinate_(random_), 30, coordinate_(random_)), Vec3(0, -60, 0));
        if (!hits.ok() || hits->empty()) violations_.Report("a ray down onto the floor hit nothing");
      }
    }
  }

  const std::vector<BodyID>& present() const { return present_; }

 private:
  // Eight bodies, half static and half kinematic, prepared here and finalized in one go.
  bool AddBatch() {
    BodyInterface& bodies = world_.bodies();
    std::vector<BodyID> batch_ids;
    for (int n = 0; n < 8; ++n) {
      BodyCreationSettings settings =
          n % 2 ? Static(Box(0.5f, 0.5f, 0.5f), Vec3::Zero()) : Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3::Zero());
      if (n % 2 == 0) settings.motion_type = MotionType::kKinematic;
      settings.position = Vec3(coordinate_(random_), 5.0f + float(n), coordinate_(random_));
      auto id = bodies.CreateBody(settings);
      if (!id.ok()) {
        violations_.Report("create failed: " + id.error().message);
        return false;
      }
      batch_ids.push_back(*id);
    }
    Result<BodyAddBatch> batch = bodies.AddBodiesPrepare(batch_ids);
    if (!batch.ok() || !bodies.AddBodiesFinalize(*batch).ok()) {
      violations_.Report("batch add failed");
      return false;
    }
    present_.insert(present_.end(), batch_ids.begin(), batch_ids.end());
    in_world_.fetch_add(static_cast<int>(batch_ids.size()));
    return true;
  }

  void RemoveOne() {
    const std::size_t pick = random_() % present_.size();
    const BodyID id = present_[pick];
    const AABB bounds = *world_.bodies().GetWorldBounds(id);
    if (!world_.bodies().RemoveAndDestroyBody(id).ok()) violations_.Report("remove failed");
    present_.erase(present_.begin() + static_cast<std::ptrdiff_t>(pick));
    in_world_.fetch_sub(1);
    const auto found = world_.query().CollideAABB(bounds);
    if (!found.ok() || Contains(*found, id)) violations_.Report("a removed body was returned after removal");
  }

  void TeleportOne() {
    const BodyID id = present_[random_() % present_.size()];
    const Vec3 target(coordinate_(random_), 4.0f, coordinate_(random_));
    if (!world_.bodies().SetPosition(id, target).ok()) violations_.Report("teleport failed");
    const auto found = world_.query().CollideAABB(*world_.bodies().GetWorldBounds(id));
    if (!found.ok() || !Contains(*found, id))
      violations_.Report("a teleported body was missed at its new bounds");
    const auto hits = world_.query().CastRayAll(target + Vec3(0, 20, 0), Vec3(0, -40, 0));
    if (!hits.ok() ||
        std::none_of(hits->begin(), hits->end(), [&](const RayCastHit& h) { return h.body == id; }))
      violations_.Report("a ray through a teleported body missed it");
  }

  PhysicsSystem& world_;
  Violations& violations_;
  std::atomic<int>& in_world_;
  std::mt19937 random_;
  std::uniform_real_distribution<float> coordinate_{-100.0f, 100.0f};
  std::vector<BodyID> present_;
};

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
  std::vector<std::vector<BodyID>> final_sets(static_cast<std::size_t>(workers));
  auto worker = [&](int w) {
    WorldWorker bodies(*world, violations, in_world, w);
    bodies.Run(iterations);
    final_sets[static_cast<std::size_t>(w)] = bodies.present();
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
}

TEST(PhysicsSystemThreads, StreamedBatchesTeleportsRemovalsAndQueriesWhileStepping) {
  WorldUnderConcurrentChange(3, 1000);
}

TEST(PhysicsSystemThreadsStress, StreamedBatchesTeleportsRemovalsAndQueriesWhileSteppingLong) {
  WorldUnderConcurrentChange(8, 6000);
}

}  // namespace
}  // namespace strata::test
