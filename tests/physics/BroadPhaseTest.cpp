// The brute-force broad phase (the oracle the quad tree will be checked against): random sequences of
// add, remove and move, with pair and query results compared to a direct computation.
#include <map>
#include <random>

#include "TestWorld.h"
#include "physics/broadphase/BruteForceBroadPhase.h"

namespace strata::test {
namespace {

TEST(BroadPhase, RandomOperationsMatchDirectComputation) {
  constexpr std::uint32_t kCapacity = 300;
  BruteForceBroadPhase broad_phase(kCapacity);
  std::map<std::uint32_t, std::pair<AABB, ObjectLayer>> present;
  std::mt19937 random(11);
  std::uniform_real_distribution<float> position(-50.0f, 50.0f), size(0.1f, 4.0f);
  auto random_box = [&] {
    const Vec3 center(position(random), position(random) * 0.2f, position(random));
    return AABB::FromCenterHalfExtents(center, Vec3(size(random), size(random), size(random)));
  };
  DefaultLayerSetup layers;
  for (int operation = 0; operation < 3000; ++operation) {
    const std::uint32_t index = random() % kCapacity;
    const BodyID id{index, 1};
    const auto it = present.find(index);
    const int kind = random() % 3;
    if (it == present.end()) {
      const AABB box = random_box();
      const ObjectLayer layer = random() % 2 ? layers::kMoving : layers::kNonMoving;
      broad_phase.AddBody(id, box, layer);
      present[index] = {box, layer};
    } else if (kind == 0) {
      broad_phase.RemoveBody(id);
      present.erase(it);
    } else {
      const AABB box = random_box();
      broad_phase.UpdateBody(id, box);
      it->second.first = box;
    }
    if (operation % 100 != 0) continue;
    ASSERT_EQ(broad_phase.body_count(), present.size());
    // Pairs for the moving bodies.
    std::vector<BodyID> active;
    std::vector<std::uint8_t> flags(kCapacity, 0);
    for (const auto& [i, entry] : present)
      if (entry.second == layers::kMoving) active.push_back({i, 1}), flags[i] = 1;
    std::vector<BodyPair> pairs;
    broad_phase.FindPairs(active, flags, layers, pairs);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found, expected;
    for (const BodyPair& pair : pairs) found.insert({pair.a.index, pair.b.index});
    for (const auto& [a, entry_a] : present) {
      if (!flags[a]) continue;
      for (const auto& [b, entry_b] : present) {
        if (a == b || (flags[b] && b < a) || !entry_a.first.Overlaps(entry_b.first)) continue;
        if (!layers.ShouldCollide(entry_a.second, entry_b.second)) continue;
        expected.insert({a, b});
      }
    }
    EXPECT_EQ(found, expected);
    EXPECT_EQ(found.size(), pairs.size());  // no duplicates
    // Box query.
    const AABB query = random_box().Expanded(5.0f);
    std::vector<BodyID> hits;
    broad_phase.CollideAABB(query, {}, hits);
    std::set<std::uint32_t> hit_set, expected_hits;
    for (const BodyID hit : hits) hit_set.insert(hit.index);
    for (const auto& [i, entry] : present)
      if (entry.first.Overlaps(query)) expected_hits.insert(i);
    EXPECT_EQ(hit_set, expected_hits);
    // Ray query.
    const Vec3 origin(position(random), 5.0f, position(random)),
        direction(position(random), -10.0f, position(random));
    std::vector<BroadPhaseRayHit> ray_hits;
    broad_phase.CastRay(origin, direction, 1.0f, {}, ray_hits);
    std::set<std::uint32_t> ray_set, expected_ray;
    for (const BroadPhaseRayHit& hit : ray_hits) ray_set.insert(hit.id.index);
    for (const auto& [i, entry] : present)
      if (entry.first.RayEntry(origin, SafeInverse(direction), 1.0f) >= 0.0f) expected_ray.insert(i);
    EXPECT_EQ(ray_set, expected_ray);
  }
}

}  // namespace
}  // namespace strata::test
