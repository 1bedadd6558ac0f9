// Navmesh validation on small hand-made levels: coverage of a flat floor, clearance around an obstacle,
// slopes and steps against the agent's limits, paths across tile borders, determinism of tile bytes.
#include <gtest/gtest.h>

#include <cmath>

#include "NavMeshTestWorld.h"
#include "navmesh/Validation.h"
#include "physics/broadphase/QuadTreeBroadPhase.h"

namespace strata::test {
namespace {

using navmesh::NavMeshSettings;
using navmesh::TileCoord;

constexpr float kTile = 12.8f;

TEST(NavMeshBuild, FlatFloorCoversFloorMinusAgentRadius) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  const auto service = BuildArea(*world, TileArea(2));
  EXPECT_EQ(service->navmesh().tile_count(), 4);
  const NavMeshSettings settings;
  const float side = 2.0f * kTile - 2.0f * settings.agent_radius;
  const double expected = static_cast<double>(side) * side;
  const double area = service->navmesh().WalkableArea();
  EXPECT_NEAR(area, expected, 0.03 * expected) << "walkable " << area << " m^2, expected " << expected;
  EXPECT_EQ(navmesh::CountIslands(service->navmesh()), 1);
}

TEST(NavMeshBuild, SensorsAreNoObstacles) {
  // A 4 m trigger volume standing on the floor: agents walk through it as if it were not there.
  const auto area_with = [](bool sensor) {
    auto world = MakeWorld();
    AddFloor(*world, 1);
    BodyCreationSettings box = Static(Box(2, 2, 2), Vec3(6.4f, 2.0f, 6.4f));
    box.is_sensor = sensor;
    Add(*world, box);
    return BuildArea(*world, TileArea(1))->navmesh().WalkableArea();
  };
  const double through_sensor = area_with(true), around_box = area_with(false);
  auto bare = MakeWorld();
  AddFloor(*bare, 1);
  const double floor = BuildArea(*bare, TileArea(1))->navmesh().WalkableArea();
  EXPECT_EQ(through_sensor, floor);
  EXPECT_LT(around_box, floor - 10.0);  // the same box, solid, takes its footprint and more
}

TEST(NavMeshBuild, BoxObstacleKeepsAgentRadiusClearAndPathGoesAround) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  // Straddles the corner of all four tiles.
  const AABB obstacle(Vec3(kTile - 1.5f, 0.0f, kTile - 1.5f), Vec3(kTile + 1.5f, 2.5f, kTile + 1.5f));
  AddSlab(*world, obstacle.min.x(), obstacle.max.x(), obstacle.min.z(), obstacle.max.z(), obstacle.max.y(),
          2.5f);
  const auto service = BuildArea(*world, TileArea(2));
  const NavMeshSettings settings;
  const float clearance = navmesh::ClearanceToBox(service->navmesh(), obstacle, settings.agent_max_climb);
  // Polygon edges follow the voxel grid, so allow one cell of simplification error.
  EXPECT_GE(clearance, settings.agent_radius - settings.cell_size) << "clearance " << clearance;

  const auto query = MakeQuery(service->navmesh());
  const Vec3 from(kTile - 6.0f, 0.0f, kTile), to(kTile + 6.0f, 0.0f, kTile);
  const auto path = query->FindPath(from, to);
  ASSERT_TRUE(path.ok());
  EXPECT_TRUE(path->found);
  EXPECT_TRUE(path->reached_end);
  EXPECT_FALSE(navmesh::PathCrossesBox(*path, obstacle));
  EXPECT_GT(path->length, (to - from).norm() + 0.5f);
  EXPECT_GE(navmesh::TilesOnPath(service->navmesh(), *path).size(), 2u);
}

/// A plank 4 m wide rising at `degrees` from (x, 0, z_min) along +z, 8 m long.
BodyID AddRamp(PhysicsSystem& world, float x, float degrees) {
  const float radians = degrees * kPi / 180.0f;
  const float half_length = 4.0f;
  const Quat tilt(Eigen::AngleAxisf(-radians, Vec3::UnitX()));
  const Vec3 center(x, half_length * std::sin(radians), 3.0f + half_length * std::cos(radians));
  return Add(world, Static(Box(2.0f, 0.1f, half_length), center, tilt));
}

float RampSurfaceHeight(float degrees) {
  return 4.0f * std::sin(degrees * kPi / 180.0f) + 0.1f / std::cos(degrees * kPi / 180.0f);
}

TEST(NavMeshBuild, ThirtyDegreeRampIsWalkableFiftyIsNot) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  AddRamp(*world, 5.0f, 30.0f);
  AddRamp(*world, 18.0f, 50.0f);
  const auto service = BuildArea(*world, TileArea(2));
  auto query = MakeQuery(service->navmesh());
  query->set_search_extents(Vec3(0.3f, 0.4f, 0.3f));
  const float mid_z30 = 3.0f + 4.0f * std::cos(30.0f * kPi / 180.0f);
  const auto on30 = query->FindNearestPoly(Vec3(5.0f, RampSurfaceHeight(30.0f), mid_z30));
  ASSERT_TRUE(on30.ok()) << "no navmesh on the 30 degree ramp";
  EXPECT_NEAR(on30->point.y(), RampSurfaceHeight(30.0f), 0.4f);
  const float mid_z50 = 3.0f + 4.0f * std::cos(50.0f * kPi / 180.0f);
  EXPECT_FALSE(query->FindNearestPoly(Vec3(18.0f, RampSurfaceHeight(50.0f), mid_z50)).ok())
      << "navmesh on the 50 degree ramp";
}

TEST(NavMeshBuild, StepsUpToMaxClimbConnectHigherOnesDoNot) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  AddSlab(*world, 3.0f, 9.0f, 4.0f, 10.0f, 0.5f, 0.5f);    // low step: 0.5 m <= 0.9 m
  AddSlab(*world, 16.0f, 22.0f, 4.0f, 10.0f, 1.2f, 1.2f);  // high step: 1.2 m > 0.9 m
  const auto service = BuildArea(*world, TileArea(2));
  const auto query = MakeQuery(service->navmesh());
  const Vec3 start(12.0f, 0.0f, 20.0f);
  const auto low = query->FindPath(start, Vec3(6.0f, 0.5f, 7.0f));
  ASSERT_TRUE(low.ok());
  EXPECT_TRUE(low->reached_end);
  const auto high = query->FindPath(start, Vec3(19.0f, 1.2f, 7.0f));
  ASSERT_TRUE(high.ok());
  EXPECT_FALSE(high->reached_end);
  // The top of the high step is navmesh, just an island of its own.
  EXPECT_TRUE(query->FindNearestPoly(Vec3(19.0f, 1.2f, 7.0f)).ok());
  EXPECT_EQ(navmesh::CountIslands(service->navmesh()), 2);
}

TEST(NavMeshBuild, PathsCrossStitchedTileBorders) {
  auto world = MakeWorld();
  AddFloor(*world, 3);
  const auto service = BuildArea(*world, TileArea(3));
  const auto query = MakeQuery(service->navmesh());
  const auto path = query->FindPath(Vec3(2.0f, 0.0f, 2.0f), Vec3(36.0f, 0.0f, 30.0f));
  ASSERT_TRUE(path.ok());
  EXPECT_TRUE(path->reached_end);
  EXPECT_GE(navmesh::TilesOnPath(service->navmesh(), *path).size(), 3u);
  // On an open floor the string-pulled path is the straight line.
  EXPECT_NEAR(path->length, (Vec3(36.0f, 0.0f, 30.0f) - Vec3(2.0f, 0.0f, 2.0f)).norm(), 0.2f);
  const auto ray = query->Raycast(Vec3(2.0f, 0.0f, 2.0f), Vec3(36.0f, 0.0f, 2.0f));
  ASSERT_TRUE(ray.ok());
  EXPECT_FALSE(ray->hit_wall);
  const auto off_edge = query->Raycast(Vec3(2.0f, 0.0f, 2.0f), Vec3(60.0f, 0.0f, 2.0f));
  ASSERT_TRUE(off_edge.ok());
  EXPECT_TRUE(off_edge->hit_wall);
  EXPECT_NEAR(off_edge->fraction * 58.0f, 3.0f * kTile - 0.6f - 2.0f, 0.5f);
}

TEST(NavMeshBuild, SameWorldGivesByteIdenticalTiles) {
  const NavMeshSettings settings;
  std::vector<std::vector<unsigned char>> runs;
  for (int run = 0; run < 2; ++run) {
    auto world = MakeWorld();
    AddFloor(*world, 2);
    AddRamp(*world, 5.0f, 30.0f);
    AddSlab(*world, 14.0f, 20.0f, 14.0f, 20.0f, 0.6f, 0.6f);
    const auto geometry = navmesh::GatherTileGeometry(*world, navmesh::TileGatherBox(settings, {0, 0}), {});
    auto built = navmesh::BuildTile(settings, {0, 0}, geometry);
    ASSERT_TRUE(built.ok());
    ASSERT_FALSE(built->data.empty());
    runs.emplace_back(built->data.bytes().begin(), built->data.bytes().end());
  }
  EXPECT_EQ(runs[0], runs[1]);
}

TEST(NavMeshBuild, WorkerCountDoesNotChangeTheNavmesh) {
  auto world = MakeWorld();
  AddFloor(*world, 3);
  AddRamp(*world, 5.0f, 30.0f);
  AddSlab(*world, 14.0f, 20.0f, 14.0f, 20.0f, 0.6f, 0.6f);
  const auto one = BuildArea(*world, TileArea(3), FastServiceConfig(1));
  const auto three = BuildArea(*world, TileArea(3), FastServiceConfig(3));
  EXPECT_EQ(one->navmesh().Tiles(), three->navmesh().Tiles());
  EXPECT_EQ(one->navmesh().polygon_count(), three->navmesh().polygon_count());
  EXPECT_EQ(one->navmesh().WalkableArea(), three->navmesh().WalkableArea());
}

TEST(NavMeshBuild, GatherSkipsDebrisAndFilteredLayers) {
  auto world = MakeWorld();
  AddFloor(*world, 1);
  Add(*world, Dynamic(Box(0.2f, 0.2f, 0.2f), Vec3(3, 0.2f, 3)));  // debris
  const BodyID crate = Add(*world, Dynamic(Box(1.0f, 1.0f, 1.0f), Vec3(8, 1, 8)));
  const NavMeshSettings settings;
  const AABB box = navmesh::TileGatherBox(settings, {0, 0});
  const auto geometry = navmesh::GatherTileGeometry(*world, box, {});
  ASSERT_EQ(geometry.bodies.size(), 2u);  // floor and the 2 m crate
  EXPECT_EQ(geometry.bodies[1].id, crate);
  EXPECT_EQ(geometry.triangle_count(), 24u);  // two boxes, 12 triangles each
  navmesh::NavMeshBodyFilter static_only;
  static_only.object_layers = 1ull << layers::kNonMoving;
  EXPECT_EQ(navmesh::GatherTileGeometry(*world, box, static_only).bodies.size(), 1u);
}

/// A plug-in broad phase that, like one written before AddOverlap existed, reports overlaps through AddHit
/// only (no bounds): the quad tree with its overlap reports stripped of their bounds.
class BoundslessBroadPhase final : public BroadPhase {
 public:
  explicit BoundslessBroadPhase(std::shared_ptr<BroadPhase> inner) : inner_(std::move(inner)) {}
  Result<AddBatch> AddBodiesPrepare(std::span<const BodyID> ids, std::span<const AABB> bounds,
                                    std::span<const ObjectLayer> layers) override {
    return inner_->AddBodiesPrepare(ids, bounds, layers);
  }
  Status AddBodiesFinalize(AddBatch& batch) override { return inner_->AddBodiesFinalize(batch); }
  void AddBodiesAbort(AddBatch& batch) override { inner_->AddBodiesAbort(batch); }
  Status RemoveBodies(std::span<const BodyID> ids) override { return inner_->RemoveBodies(ids); }
  Status UpdateBody(BodyID id, const AABB& bounds) override { return inner_->UpdateBody(id, bounds); }
  bool Contains(BodyID id) const override { return inner_->Contains(id); }
  std::size_t body_count() const override { return inner_->body_count(); }
  void Update() override { inner_->Update(); }
  void Optimize() override { inner_->Optimize(); }
  BroadPhaseStats stats() const override { return inner_->stats(); }
  BroadPhasePin Pin() const override { return inner_->Pin(); }  // the inner one owns and releases it
  void FindPairs(std::span<const BodyID> active, std::span<const std::uint8_t> active_flags,
                 const LayerSetup& layers, std::vector<BodyPair>& out) const override {
    inner_->FindPairs(active, active_flags, layers, out);
  }
  void CollideAABB(const BroadPhasePin& pin, const AABB& box, const QueryFilter& filter,
                   BroadPhaseCollector& collector) const override {
    struct HitsOnly final : BroadPhaseCollector {
      explicit HitsOnly(BroadPhaseCollector& forward_to) : target(forward_to) {}
      void AddHit(BodyID id, float fraction) override { target.AddHit(id, fraction); }
      void AddOverlap(BodyID id, const AABB&) override { target.AddHit(id, 0.0f); }
      BroadPhaseCollector& target;
    } hits_only(collector);
    inner_->CollideAABB(pin, box, filter, hits_only);
  }
  void CollideSphere(const BroadPhasePin& pin, const Vec3& center, float radius, const QueryFilter& filter,
                     BroadPhaseCollector& collector) const override {
    inner_->CollideSphere(pin, center, radius, filter, collector);
  }
  void CastRay(const BroadPhasePin& pin, const Vec3& origin, const Vec3& direction, const QueryFilter& filter,
               BroadPhaseCollector& collector) const override {
    inner_->CastRay(pin, origin, direction, filter, collector);
  }
  void CastAABB(const BroadPhasePin& pin, const AABB& box, const Vec3& displacement,
                const QueryFilter& filter, BroadPhaseCollector& collector) const override {
    inner_->CastAABB(pin, box, displacement, filter, collector);
  }

 protected:
  void ReleasePin(std::uint32_t) const override {}  // never called: every pin is the inner broad phase's

 private:
  std::shared_ptr<BroadPhase> inner_;
};

TEST(NavMeshBuild, ABroadPhaseWithoutBoundsLeavesMovingBodiesTheirTeleportedBounds) {
  PhysicsSystemConfig config;
  config.max_bodies = 64;
  config.job_system = std::make_shared<SerialJobSystem>();
  const auto layers = std::make_shared<DefaultLayerSetup>();
  config.layers = layers;
  config.broad_phase =
      std::make_shared<BoundslessBroadPhase>(std::make_shared<QuadTreeBroadPhase>(config.max_bodies, layers));
  auto created = PhysicsSystem::Create(config);
  ASSERT_TRUE(created.ok());
  PhysicsSystem& world = **created;
  AddFloor(world, 1);
  const BodyID crate = Add(world, Dynamic(Box(1.0f, 1.0f, 1.0f), Vec3(6, 1, 6)));
  const auto geometry = navmesh::GatherTileGeometry(world, navmesh::TileGatherBox({}, {0, 0}), {});
  ASSERT_EQ(geometry.bodies.size(), 2u);
  EXPECT_EQ(geometry.bodies[1].id, crate);
  // The crate's own 2 m box, not an inside-out box spanning the world.
  EXPECT_TRUE(geometry.bodies[1].bounds.min.isApprox(Vec3(5, 0, 5)));
  EXPECT_TRUE(geometry.bodies[1].bounds.max.isApprox(Vec3(7, 2, 7)));
  EXPECT_LT(geometry.bounds.Size().maxCoeff(), 20.0f);
}

}  // namespace
}  // namespace strata::test
