// Both broad phases (the quad tree and the brute-force oracle) against a direct computation: random
// sequences of batch add, single add, remove, move and rebuild, with every query kind checked; bad input;
// batches; pinned generations.
#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "TestWorld.h"
#include "physics/broadphase/BruteForceBroadPhase.h"
#include "physics/broadphase/QuadTreeBroadPhase.h"

namespace strata::test {
namespace {

constexpr std::uint32_t kCapacity = 400;

std::unique_ptr<BroadPhase> MakeBroadPhase(bool quad_tree) {
  auto layers = std::make_shared<DefaultLayerSetup>();
  if (quad_tree) return std::make_unique<QuadTreeBroadPhase>(kCapacity, layers);
  return std::make_unique<BruteForceBroadPhase>(kCapacity, layers);
}

// What should be in the broad phase: body index -> (generation, bounds, layer).
struct Expected {
  std::uint32_t generation;
  AABB bounds;
  ObjectLayer layer;
};
using Model = std::map<std::uint32_t, Expected>;

std::set<std::uint32_t> Indices(const std::vector<BodyID>& ids) {
  std::set<std::uint32_t> set;
  for (const BodyID id : ids) set.insert(id.index);
  return set;
}

// Checks every query kind against the model.
void ExpectQueriesMatch(const BroadPhase& broad_phase, const Model& model, std::mt19937& random) {
  ASSERT_EQ(broad_phase.body_count(), model.size());
  std::uniform_real_distribution<float> position(-60.0f, 60.0f);
  DefaultLayerSetup layers;

  std::vector<BodyID> active;
  std::vector<std::uint8_t> flags(kCapacity, 0);
  for (const auto& [index, entry] : model)
    if (entry.layer == layers::kMoving) active.push_back({index, entry.generation}), flags[index] = 1;
  std::vector<BodyPair> pairs;
  broad_phase.FindPairs(active, flags, layers, pairs);
  std::set<std::pair<std::uint32_t, std::uint32_t>> found_pairs, expected_pairs;
  for (const BodyPair& pair : pairs) found_pairs.insert({pair.a.index, pair.b.index});
  for (const auto& [a, entry_a] : model) {
    if (!flags[a]) continue;
    for (const auto& [b, entry_b] : model) {
      if (a == b || (flags[b] && b < a) || !entry_a.bounds.Overlaps(entry_b.bounds)) continue;
      if (layers.ShouldCollide(entry_a.layer, entry_b.layer)) expected_pairs.insert({a, b});
    }
  }
  EXPECT_EQ(found_pairs, expected_pairs);
  EXPECT_EQ(found_pairs.size(), pairs.size()) << "a pair was reported twice";

  const Vec3 corner(position(random), position(random) * 0.2f, position(random));
  const AABB box(corner, corner + Vec3(12.8f, 20.0f, 12.8f));
  for (const QueryFilter filter : {QueryFilter{}, QueryFilter::OnlyLayer(layers::kMoving)}) {
    std::vector<BodyID> hits;
    broad_phase.CollideAABB(box, filter, hits);
    std::set<std::uint32_t> expected;
    for (const auto& [index, entry] : model)
      if (entry.bounds.Overlaps(box) && filter.AcceptsLayer(entry.layer)) expected.insert(index);
    EXPECT_EQ(Indices(hits), expected);
    EXPECT_EQ(hits.size(), expected.size());
  }

  const float radius = 6.0f;
  std::vector<BodyID> sphere_hits;
  broad_phase.CollideSphere(corner, radius, {}, sphere_hits);
  std::set<std::uint32_t> expected_sphere;
  for (const auto& [index, entry] : model)
    if (SquaredDistanceToBox(entry.bounds, corner) <= radius * radius) expected_sphere.insert(index);
  EXPECT_EQ(Indices(sphere_hits), expected_sphere);

  // Rays of 10 m and 100 m, one of them axis-parallel, and a swept box.
  const Vec3 origin(position(random), 8.0f, position(random));
  const Vec3 short_ray = Vec3(position(random), -10.0f, position(random)).normalized() * 10.0f;
  const Vec3 long_ray = Vec3(position(random), -3.0f, position(random)).normalized() * 100.0f;
  for (const Vec3& direction : {short_ray, long_ray, Vec3(0.0f, 0.0f, 100.0f)}) {
    std::vector<BroadPhaseRayHit> ray_hits;
    broad_phase.CastRay(origin, direction, {}, ray_hits);
    std::map<std::uint32_t, float> found, expected;
    for (const BroadPhaseRayHit& hit : ray_hits) found[hit.id.index] = hit.fraction;
    for (const auto& [index, entry] : model)
      if (const float t = entry.bounds.RayEntry(origin, SafeInverse(direction), 1.0f); t >= 0.0f)
        expected[index] = t;
    EXPECT_EQ(found, expected);
  }
  const AABB swept = AABB::FromCenterHalfExtents(origin, Vec3(1.0f, 2.0f, 0.5f));
  const Vec3 displacement(position(random), -5.0f, position(random));
  std::vector<BroadPhaseRayHit> sweep_hits;
  broad_phase.CastAABB(swept, displacement, {}, sweep_hits);
  std::set<std::uint32_t> expected_sweep;
  for (const auto& [index, entry] : model)
    if (entry.bounds.Expanded(swept.HalfExtents()).RayEntry(origin, SafeInverse(displacement), 1.0f) >= 0.0f)
      expected_sweep.insert(index);
  std::set<std::uint32_t> found_sweep;
  for (const BroadPhaseRayHit& hit : sweep_hits) found_sweep.insert(hit.id.index);
  EXPECT_EQ(found_sweep, expected_sweep);
}

class BroadPhaseOracle : public ::testing::TestWithParam<std::tuple<bool, unsigned>> {};

TEST_P(BroadPhaseOracle, RandomOperationsMatchDirectComputation) {
  const auto [quad_tree, seed] = GetParam();
  std::unique_ptr<BroadPhase> broad_phase = MakeBroadPhase(quad_tree);
  Model model;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> position(-50.0f, 50.0f), size(0.1f, 4.0f);
  auto random_box = [&] {
    const Vec3 center(position(random), position(random) * 0.2f, position(random));
    return AABB::FromCenterHalfExtents(center, Vec3(size(random), size(random), size(random)));
  };
  std::vector<std::uint32_t> generation(kCapacity, 1);
  auto absent_indices = [&](std::size_t count) {
    std::vector<std::uint32_t> picked;
    for (int tries = 0; tries < 200 && picked.size() < count; ++tries) {
      const std::uint32_t index = random() % kCapacity;
      if (!model.contains(index) && std::find(picked.begin(), picked.end(), index) == picked.end())
        picked.push_back(index);
    }
    return picked;
  };
  for (int operation = 0; operation < 1500; ++operation) {
    const int kind = static_cast<int>(random() % 10);
    if (kind <= 1) {  // a batch, finalized or (sometimes) aborted
      const std::vector<std::uint32_t> picked = absent_indices(1 + random() % 40);
      if (picked.empty()) continue;
      std::vector<BodyID> ids;
      std::vector<AABB> bounds;
      std::vector<ObjectLayer> layers;
      for (const std::uint32_t index : picked) {
        ids.push_back({index, ++generation[index]});
        bounds.push_back(random_box());
        layers.push_back(random() % 3 ? layers::kMoving : layers::kNonMoving);
      }
      Result<AddBatch> batch = broad_phase->AddBodiesPrepare(ids, bounds, layers);
      ASSERT_TRUE(batch.ok()) << batch.error().message;
      if (random() % 5 == 0) {
        broad_phase->AddBodiesAbort(*batch);
        continue;
      }
      ASSERT_TRUE(broad_phase->AddBodiesFinalize(*batch).ok());
      for (std::size_t i = 0; i < ids.size(); ++i)
        model[ids[i].index] = {ids[i].generation, bounds[i], layers[i]};
    } else if (kind == 2) {  // single add
      const std::vector<std::uint32_t> picked = absent_indices(1);
      if (picked.empty()) continue;
      const BodyID id{picked[0], ++generation[picked[0]]};
      const AABB box = random_box();
      ASSERT_TRUE(broad_phase->AddBody(id, box, layers::kMoving).ok());
      model[id.index] = {id.generation, box, layers::kMoving};
    } else if (kind <= 4 && !model.empty()) {  // remove one, or a few at once
      std::vector<BodyID> ids;
      for (std::size_t n = 1 + random() % 3; n > 0 && !model.empty(); --n) {
        auto it = std::next(model.begin(), static_cast<std::ptrdiff_t>(random() % model.size()));
        if (std::find(ids.begin(), ids.end(), BodyID{it->first, it->second.generation}) != ids.end())
          continue;
        ids.push_back({it->first, it->second.generation});
      }
      ASSERT_TRUE(broad_phase->RemoveBodies(ids).ok());
      for (const BodyID id : ids) model.erase(id.index);
    } else if (kind <= 8 && !model.empty()) {  // move, sometimes far, sometimes a little
      auto it = std::next(model.begin(), static_cast<std::ptrdiff_t>(random() % model.size()));
      const AABB box = random() % 2 ? random_box() : it->second.bounds.Expanded(0.3f);
      ASSERT_TRUE(broad_phase->UpdateBody({it->first, it->second.generation}, box).ok());
      it->second.bounds = box;
    } else {
      random() % 8 ? broad_phase->Update() : broad_phase->Optimize();
    }
    if (operation % 25 == 0) ExpectQueriesMatch(*broad_phase, model, random);
    if (HasFatalFailure() || HasFailure()) return;
  }
  broad_phase->Optimize();
  ExpectQueriesMatch(*broad_phase, model, random);
}

INSTANTIATE_TEST_SUITE_P(BothBroadPhases, BroadPhaseOracle,
                         ::testing::Combine(::testing::Bool(), ::testing::Values(11u, 12u, 13u)),
                         [](const auto& test_info) {
                           return std::string(std::get<0>(test_info.param) ? "QuadTree" : "BruteForce") +
                                  "_seed" + std::to_string(std::get<1>(test_info.param));
                         });

// A snapshot of everything a query can see, to check that rejected calls change nothing.
std::set<std::uint32_t> Everything(const BroadPhase& broad_phase) {
  std::vector<BodyID> hits;
  broad_phase.CollideAABB(AABB(Vec3::Constant(-1e6f), Vec3::Constant(1e6f)), {}, hits);
  return Indices(hits);
}

class BroadPhaseBadInput : public ::testing::TestWithParam<bool> {};

TEST_P(BroadPhaseBadInput, RejectedCallsLeaveTheTreeUnchanged) {
  std::unique_ptr<BroadPhase> broad_phase = MakeBroadPhase(GetParam());
  const BodyID a{1, 1}, b{2, 1}, c{3, 1};
  const AABB unit(Vec3::Zero(), Vec3::Ones());
  ASSERT_TRUE(broad_phase->AddBody(a, unit, layers::kMoving).ok());
  ASSERT_TRUE(broad_phase->AddBody(b, unit, layers::kNonMoving).ok());
  broad_phase->Update();
  const auto before = Everything(*broad_phase);
  const BroadPhaseStats stats_before = broad_phase->stats();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const AABB inverted(Vec3::Ones(), Vec3::Zero());
  const AABB not_a_number(Vec3(nan, 0, 0), Vec3::Ones());

  EXPECT_EQ(broad_phase->AddBody(c, inverted, layers::kMoving).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(broad_phase->AddBody(c, not_a_number, layers::kMoving).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(broad_phase->AddBody(c, unit, 7).error().code, ErrorCode::kInvalidArgument);  // no such layer
  EXPECT_EQ(broad_phase->AddBody(a, unit, layers::kMoving).error().code,
            ErrorCode::kInvalidState);  // present
  EXPECT_EQ(broad_phase->UpdateBody(a, not_a_number).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(broad_phase->UpdateBody(a, inverted).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(broad_phase->UpdateBody(c, unit).error().code, ErrorCode::kInvalidState);  // never added
  EXPECT_FALSE(broad_phase->UpdateBody({1, 2}, unit).ok());                            // stale generation
  EXPECT_FALSE(broad_phase->RemoveBody(BodyID{}).ok());
  // A batch naming a body twice, or a present body, claims nothing.
  const std::vector<BodyID> twice{c, c};
  const std::vector<AABB> two_bounds{unit, unit};
  const std::vector<ObjectLayer> two_layers{layers::kMoving, layers::kMoving};
  EXPECT_EQ(broad_phase->AddBodiesPrepare(twice, two_bounds, two_layers).error().code,
            ErrorCode::kInvalidArgument);
  const std::vector<BodyID> with_present{c, a};
  EXPECT_EQ(broad_phase->AddBodiesPrepare(with_present, two_bounds, two_layers).error().code,
            ErrorCode::kInvalidState);
  // Removing twice: the second fails, as does a batch that lists one body twice or an absent one.
  ASSERT_TRUE(broad_phase->RemoveBody(a).ok());
  EXPECT_EQ(broad_phase->RemoveBody(a).error().code, ErrorCode::kInvalidState);
  const std::vector<BodyID> remove_twice{b, b};
  EXPECT_FALSE(broad_phase->RemoveBodies(remove_twice).ok());
  const std::vector<BodyID> remove_with_absent{b, a};
  EXPECT_FALSE(broad_phase->RemoveBodies(remove_with_absent).ok());
  EXPECT_TRUE(broad_phase->Contains(b));
  EXPECT_EQ(Everything(*broad_phase), std::set<std::uint32_t>{2});
  ASSERT_TRUE(broad_phase->AddBody(a, unit, layers::kMoving).ok());
  EXPECT_EQ(Everything(*broad_phase), before);
  EXPECT_EQ(broad_phase->body_count(), 2u);
  // c was never claimed by the failed calls: it can be added now.
  ASSERT_TRUE(broad_phase->AddBody(c, unit, layers::kMoving).ok());
  EXPECT_EQ(broad_phase->stats().rebuilds_skipped, stats_before.rebuilds_skipped);
}

TEST_P(BroadPhaseBadInput, BatchFinalizesOnceAndAbortReleasesItsBodies) {
  std::unique_ptr<BroadPhase> broad_phase = MakeBroadPhase(GetParam());
  std::vector<BodyID> ids;
  std::vector<AABB> bounds;
  std::vector<ObjectLayer> layers;
  for (std::uint32_t i = 0; i < 50; ++i) {
    ids.push_back({i, 1});
    bounds.push_back(AABB::FromCenterHalfExtents(Vec3(static_cast<float>(i), 0, 0), Vec3::Constant(0.4f)));
    layers.push_back(layers::kMoving);
  }
  const std::size_t nodes_before = broad_phase->stats().nodes_in_use;
  {
    Result<AddBatch> batch = broad_phase->AddBodiesPrepare(ids, bounds, layers);
    ASSERT_TRUE(batch.ok());
    // Prepared but not finalized: invisible, not counted, and claimed against a second add.
    EXPECT_TRUE(Everything(*broad_phase).empty());
    EXPECT_EQ(broad_phase->body_count(), 0u);
    EXPECT_FALSE(broad_phase->AddBody(ids[7], bounds[7], layers::kMoving).ok());
    EXPECT_FALSE(broad_phase->UpdateBody(ids[7], bounds[7]).ok());
    broad_phase->AddBodiesAbort(*batch);
    EXPECT_FALSE(batch->prepared());
    EXPECT_EQ(broad_phase->AddBodiesFinalize(*batch).error().code, ErrorCode::kInvalidState);
  }
  EXPECT_EQ(broad_phase->stats().nodes_in_use, nodes_before);
  {
    Result<AddBatch> dropped = broad_phase->AddBodiesPrepare(ids, bounds, layers);
    ASSERT_TRUE(dropped.ok());
  }  // destroyed while prepared: aborts itself
  Result<AddBatch> batch = broad_phase->AddBodiesPrepare(ids, bounds, layers);
  ASSERT_TRUE(batch.ok());
  ASSERT_TRUE(broad_phase->AddBodiesFinalize(*batch).ok());
  EXPECT_EQ(Everything(*broad_phase).size(), ids.size());
  const auto after_first = Everything(*broad_phase);
  EXPECT_EQ(broad_phase->AddBodiesFinalize(*batch).error().code, ErrorCode::kInvalidState);
  EXPECT_EQ(Everything(*broad_phase), after_first);
  EXPECT_EQ(broad_phase->body_count(), ids.size());
  // Another broad phase's batch is refused.
  std::unique_ptr<BroadPhase> other = MakeBroadPhase(GetParam());
  const BodyID stranger{100, 1};
  const AABB unit(Vec3::Zero(), Vec3::Ones());
  const ObjectLayer moving = layers::kMoving;
  Result<AddBatch> foreign = other->AddBodiesPrepare({&stranger, 1}, {&unit, 1}, {&moving, 1});
  ASSERT_TRUE(foreign.ok());
  EXPECT_EQ(broad_phase->AddBodiesFinalize(*foreign).error().code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(foreign->prepared());
}

INSTANTIATE_TEST_SUITE_P(BothBroadPhases, BroadPhaseBadInput, ::testing::Bool(), [](const auto& test_info) {
  return std::string(test_info.param ? "QuadTree" : "BruteForce");
});

TEST(QuadTreeBroadPhase, ManySingleAddsDegradeThenRebuildAndStayCorrect) {
  // Exactly as many bodies as the broad phase has room for: the rebuild must still find its nodes.
  QuadTreeBroadPhase broad_phase(300, std::make_shared<DefaultLayerSetup>());
  Model model;
  std::mt19937 random(5);
  std::uniform_real_distribution<float> position(-50.0f, 50.0f);
  // 300 single adds stack new roots; queries must still see everything, before and after a rebuild.
  for (std::uint32_t i = 0; i < 300; ++i) {
    const AABB box =
        AABB::FromCenterHalfExtents(Vec3(position(random), 0, position(random)), Vec3::Constant(0.5f));
    ASSERT_TRUE(broad_phase.AddBody({i, 1}, box, layers::kMoving).ok());
    model[i] = {1, box, layers::kMoving};
  }
  ExpectQueriesMatch(broad_phase, model, random);
  EXPECT_GT(broad_phase.stats().max_depth, 50u);  // a chain of roots, three bodies each
  broad_phase.Update();
  ExpectQueriesMatch(broad_phase, model, random);
  EXPECT_LE(broad_phase.stats().max_depth, 6u);      // log4(300) ~ 4.1, plus uneven splits
  EXPECT_EQ(broad_phase.stats().retired_nodes, 0u);  // nobody pinned the old generation
}

TEST(QuadTreeBroadPhase, StaticTreeIsNotRebuiltWhenOnlyDynamicBodiesMove) {
  QuadTreeBroadPhase broad_phase(kCapacity, std::make_shared<DefaultLayerSetup>());
  for (std::uint32_t i = 0; i < 100; ++i)
    ASSERT_TRUE(broad_phase
                    .AddBody({i, 1}, AABB::FromCenterHalfExtents(Vec3(float(i), 0, 0), Vec3::Constant(0.5f)),
                             i < 90 ? layers::kNonMoving : layers::kMoving)
                    .ok());
  broad_phase.Optimize();
  const std::uint64_t generation = broad_phase.stats().generation;
  broad_phase.Update();
  EXPECT_EQ(broad_phase.stats().generation, generation) << "nothing changed, so no new generation";
  const BroadPhasePin pin = broad_phase.Pin();
  ASSERT_TRUE(
      broad_phase.UpdateBody({95, 1}, AABB::FromCenterHalfExtents(Vec3(95, 1, 0), Vec3::Constant(0.5f)))
          .ok());
  broad_phase.Update();
  EXPECT_EQ(broad_phase.stats().generation, generation + 1);
  // Only the dynamic tree's changed path was dropped: a handful of nodes, not the static tree's 90 bodies.
  EXPECT_GT(broad_phase.stats().retired_nodes, 0u);
  EXPECT_LE(broad_phase.stats().retired_nodes, 4u);
}

// A row of 40 moving boxes 2 m wide, 3 m apart along x (body i at x = 3 i), in an optimized tree.
void AddRowOfUnitBoxes(QuadTreeBroadPhase& broad_phase) {
  for (std::uint32_t i = 0; i < 40; ++i)
    ASSERT_TRUE(broad_phase
                    .AddBody({i, 1}, AABB::FromCenterHalfExtents(Vec3(float(i) * 3, 0, 0), Vec3::Constant(1)),
                             layers::kMoving)
                    .ok());
  broad_phase.Optimize();
}

// A body whose new bounds lie inside its slot (a game object swaying within where it was) writes nothing
// shared and asks for no rebuild; bounds that leave the slot widen it up to the root and do; queries find the
// body at every place it was put.
TEST(QuadTreeBroadPhase, MovesWithinABodysSlotNeedNoRebuildAndMovesOutOfItDo) {
  QuadTreeBroadPhase broad_phase(kCapacity, std::make_shared<DefaultLayerSetup>());
  AddRowOfUnitBoxes(broad_phase);
  auto finds = [&](const AABB& box) {
    std::vector<BodyID> hits;
    broad_phase.CollideAABB(box, {}, hits);
    return std::find(hits.begin(), hits.end(), BodyID{7, 1}) != hits.end();
  };
  const std::uint64_t generation = broad_phase.stats().generation;
  // Body 7 fills its slot exactly (x 20..22): a smaller box inside it is within.
  const AABB inside = AABB::FromCenterHalfExtents(Vec3(21.2f, 0.3f, 0), Vec3::Constant(0.5f));
  ASSERT_TRUE(broad_phase.UpdateBody({7, 1}, inside).ok());
  broad_phase.Update();
  EXPECT_EQ(broad_phase.stats().generation, generation) << "a move within the slot rebuilt the tree";
  EXPECT_TRUE(finds(inside));
  const AABB outside = AABB::FromCenterHalfExtents(Vec3(21, 40, 0), Vec3::Constant(0.5f));
  ASSERT_TRUE(broad_phase.UpdateBody({7, 1}, outside).ok());
  EXPECT_TRUE(finds(outside)) << "widened to the root before the rebuild";
  broad_phase.Update();
  EXPECT_EQ(broad_phase.stats().generation, generation + 1);
  EXPECT_TRUE(finds(outside));
  EXPECT_FALSE(finds(AABB::FromCenterHalfExtents(Vec3(21, 0, 0), Vec3::Constant(0.2f))))
      << "the rebuild tightens the slot to where the body is";
}

// A body gliding at a steady pace: each rebuild sizes its slot for a few more moves like the last, so the
// tree is rebuilt on a fraction of the moves, and queries still see the body exactly where it is (its slot
// may reach ahead; the body's own bounds decide). A jump gets no room ahead.
TEST(QuadTreeBroadPhase, SteadyMotionRebuildsOnAFractionOfTheMovesAndQueriesStayExact) {
  QuadTreeBroadPhase broad_phase(kCapacity, std::make_shared<DefaultLayerSetup>());
  AddRowOfUnitBoxes(broad_phase);
  auto hits = [&](const AABB& box) {
    std::vector<BodyID> found;
    broad_phase.CollideAABB(box, {}, found);
    std::sort(found.begin(), found.end(), [](BodyID a, BodyID b) { return a.index < b.index; });
    return found;
  };
  const std::uint64_t first_generation = broad_phase.stats().generation;
  constexpr int kMoves = 60;
  const Vec3 start(21, 0, 0), step(0.05f, 0.02f, 0);  // body 7, from where it was added
  for (int move = 1; move <= kMoves; ++move) {
    const Vec3 centre = start + float(move) * step;
    const AABB bounds = AABB::FromCenterHalfExtents(centre, Vec3::Constant(1));
    ASSERT_TRUE(broad_phase.UpdateBody({7, 1}, bounds).ok());
    broad_phase.Update();
    // A small box at the body's centre finds it; one just past its face (inside the room its slot keeps
    // ahead) does not.
    auto has_body = [](const std::vector<BodyID>& found) {
      return std::any_of(found.begin(), found.end(), [](BodyID id) { return id == BodyID{7, 1}; });
    };
    ASSERT_TRUE(has_body(hits(AABB::FromCenterHalfExtents(centre, Vec3::Constant(0.05f)))))
        << "move " << move;
    const Vec3 ahead = centre + Vec3(1.0f + 2.0f * step.x(), 0, 0);
    EXPECT_FALSE(has_body(hits(AABB::FromCenterHalfExtents(ahead, Vec3::Constant(0.01f)))))
        << "move " << move;
  }
  const std::uint64_t rebuilds = broad_phase.stats().generation - first_generation;
  EXPECT_GE(rebuilds, 1u);
  EXPECT_LE(rebuilds, std::uint64_t{kMoves / 2}) << "a steadily moving body rebuilt the tree on most moves";
  // A jump of 30 m: after the rebuild the slot is the body's bounds, with no room ahead.
  const Vec3 landing = start + Vec3(0, 30, 0);
  ASSERT_TRUE(broad_phase.UpdateBody({7, 1}, AABB::FromCenterHalfExtents(landing, Vec3::Constant(1))).ok());
  broad_phase.Update();
  EXPECT_EQ(hits(AABB::FromCenterHalfExtents(landing, Vec3::Constant(0.05f))), (std::vector<BodyID>{{7, 1}}));
  const std::uint64_t after_jump = broad_phase.stats().generation;
  ASSERT_TRUE(
      broad_phase
          .UpdateBody({7, 1}, AABB::FromCenterHalfExtents(landing + Vec3(0.01f, 0, 0), Vec3::Constant(1)))
          .ok());
  broad_phase.Update();
  EXPECT_EQ(broad_phase.stats().generation, after_jump + 1)
      << "a jump left room ahead, so the next small move stayed inside the slot";
}

// Holding a pin across 100 steps while the world changes: queries through the pin read only live nodes
// (freed nodes are poisoned, so the ASan build would stop on a late read), old generations pile up, and
// their memory comes back once the pin is released.
TEST(QuadTreeBroadPhase, PinHeldForAHundredStepsKeepsNodesAliveThenGivesThemBack) {
  auto world = MakeWorld();
  BodyInterface& bodies = world->bodies();
  Add(*world, Static(Box(100, 1, 100), Vec3(0, -1, 0)));
  std::vector<BodyID> dynamic;
  for (int i = 0; i < 60; ++i)
    dynamic.push_back(
        Add(*world, Dynamic(Box(0.4f, 0.4f, 0.4f), Vec3(float(i % 10) * 2 - 10, 1 + float(i / 10) * 2, 0))));
  ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
  const BroadPhase& broad_phase = world->broad_phase();
  const std::size_t nodes_unpinned = broad_phase.stats().nodes_in_use;

  class CountingCollector final : public BroadPhaseCollector {
   public:
    void AddHit(BodyID, float) override { ++hits; }
    int hits = 0;
  };
  BroadPhasePin pin = broad_phase.Pin();
  const std::uint64_t pinned_generation = pin.generation();
  std::mt19937 random(3);
  std::size_t most_retired = 0;
  for (int step = 0; step < 100; ++step) {
    // Add, remove and move bodies, then step (which rebuilds and swaps generations).
    if (step % 3 == 0)
      dynamic.push_back(Add(*world, Dynamic(Sphere(0.3f), Vec3(float(random() % 20) - 10, 5, 3))));
    if (step % 4 == 0 && dynamic.size() > 10) {
      ASSERT_TRUE(bodies.RemoveAndDestroyBody(dynamic.front()).ok());
      dynamic.erase(dynamic.begin());
    }
    ASSERT_TRUE(
        bodies.SetPosition(dynamic[random() % dynamic.size()], Vec3(float(random() % 20) - 10, 8, -3)).ok());
    ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
    CountingCollector collector;
    broad_phase.CollideAABB(pin, AABB(Vec3::Constant(-200), Vec3::Constant(200)), {}, collector);
    EXPECT_GT(collector.hits, 0);
    most_retired = std::max(most_retired, broad_phase.stats().retired_nodes);
    EXPECT_EQ(broad_phase.stats().pinned_old_generations, 1u);
  }
  EXPECT_GT(broad_phase.stats().generation, pinned_generation + 50);
  EXPECT_GT(most_retired, 100u) << "old generations' nodes should have been kept for the pin";
  EXPECT_GT(broad_phase.stats().retired_bytes, 0u);
  pin.Release();
  ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
  EXPECT_EQ(broad_phase.stats().retired_nodes, 0u);
  EXPECT_EQ(broad_phase.stats().pinned_old_generations, 0u);
  // What is left is the live trees, about what the world used before the pin.
  EXPECT_LE(broad_phase.stats().nodes_in_use, nodes_unpinned + 20);
}

}  // namespace
}  // namespace strata::test
