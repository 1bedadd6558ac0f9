// World queries: ray casts (closest and all), AABB and shape overlap, layer filters; every result is
// checked against an exhaustive test of every body, so the broad phase can never hide a body.
#include <random>

#include "TestWorld.h"
#include "physics/narrowphase/Gjk.h"

namespace strata::test {
namespace {

class QueryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    world_ = MakeWorld();
    ids_.push_back(Add(*world_, Static(Box(20, 1, 20), Vec3(0, -1, 0))));
    std::mt19937 random(42);
    std::uniform_real_distribution<float> spread(-15.0f, 15.0f), height(0.5f, 6.0f), size(0.2f, 1.0f);
    for (int i = 0; i < 120; ++i) {
      ShapeRef shape;
      switch (i % 3) {
        case 0:
          shape = Box(size(random), size(random), size(random));
          break;
        case 1:
          shape = Sphere(size(random));
          break;
        default:
          shape = Capsule(size(random), size(random));
          break;
      }
      const Quat rotation(
          Eigen::AngleAxisf(spread(random), Vec3(spread(random), 1, spread(random)).normalized()));
      BodyCreationSettings settings =
          Dynamic(shape, Vec3(spread(random), height(random), spread(random)), rotation);
      if (i % 4 == 0) settings.motion_type = MotionType::kKinematic;
      ids_.push_back(Add(*world_, settings));
    }
  }

  // Exhaustive reference: every body's exact shape.
  std::optional<RayCastHit> ReferenceRay(const Vec3& origin, const Vec3& direction,
                                         const QueryFilter& filter) {
    std::optional<RayCastHit> best;
    for (const BodyID id : ids_) {
      BodyLockRead lock(world_->body_manager(), id);
      if (!filter.AcceptsLayer(lock.body().object_layer())) continue;
      const Pose& pose = lock.body().pose();
      ShapeRayHit hit;
      if (lock.body().shape()->CastRay(pose.ToLocal(origin), pose.DirectionToLocal(direction), 1.0f, hit) &&
          (!best || hit.fraction < best->fraction))
        best = RayCastHit{id, hit.fraction, origin + hit.fraction * direction,
                          pose.DirectionToWorld(hit.normal), 0};
    }
    return best;
  }

  std::unique_ptr<PhysicsSystem> world_;
  std::vector<BodyID> ids_;
};

TEST_F(QueryTest, ClosestRayMatchesExhaustiveSearch) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> spread(-18.0f, 18.0f);
  int hits = 0;
  for (int ray = 0; ray < 300; ++ray) {
    const Vec3 origin(spread(random), 10.0f, spread(random));
    const Vec3 direction = Vec3(spread(random), -10.0f, spread(random)) - Vec3(0, 10, 0) * 0.0f;
    const auto hit = *world_->query().CastRay(origin, direction);
    const auto expected = ReferenceRay(origin, direction, {});
    ASSERT_EQ(hit.has_value(), expected.has_value());
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(hit->fraction, expected->fraction, 1e-5f);
  }
  EXPECT_GT(hits, 150);
}

TEST_F(QueryTest, AllHitsAreSortedAndComplete) {
  int multi_hit_rays = 0;
  for (float z = -15.0f; z <= 15.0f; z += 0.5f) {
    const Vec3 origin(-30, 1.0f, z), direction(60, 0.5f, 0);
    const auto hits = *world_->query().CastRayAll(origin, direction);
    std::set<BodyID> expected;
    for (const BodyID id : ids_) {
      BodyLockRead lock(world_->body_manager(), id);
      const Pose& pose = lock.body().pose();
      ShapeRayHit hit;
      if (lock.body().shape()->CastRay(pose.ToLocal(origin), pose.DirectionToLocal(direction), 1.0f, hit))
        expected.insert(id);
    }
    std::set<BodyID> found;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      found.insert(hits[i].body);
      if (i > 0) {
        EXPECT_LE(hits[i - 1].fraction, hits[i].fraction);
      }
    }
    EXPECT_EQ(found, expected);
    EXPECT_EQ(found.size(), hits.size());  // one hit per body
    multi_hit_rays += hits.size() > 1;
  }
  EXPECT_GT(multi_hit_rays, 5);
}

TEST_F(QueryTest, AabbOverlapMatchesExhaustiveSearch) {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> spread(-15.0f, 15.0f);
  for (int query = 0; query < 100; ++query) {
    const AABB box = AABB::FromCenterHalfExtents(Vec3(spread(random), 2.0f, spread(random)), Vec3(3, 2, 2));
    const auto found = *world_->query().CollideAABB(box);
    std::vector<BodyID> expected;
    for (const BodyID id : ids_)
      if (world_->bodies().GetWorldBounds(id)->Overlaps(box)) expected.push_back(id);
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(found, expected);
  }
}

TEST_F(QueryTest, ShapeOverlapFindsExactlyTheTouchedBodies) {
  std::mt19937 random(9);
  std::uniform_real_distribution<float> spread(-15.0f, 15.0f);
  const ShapeRef probe = Sphere(1.5f);
  for (int query = 0; query < 60; ++query) {
    const Pose pose{Vec3(spread(random), 2.0f, spread(random)), Quat::Identity()};
    const auto overlaps = *world_->query().CollideShape(*probe, pose);
    std::set<BodyID> found;
    for (const ShapeOverlap& overlap : overlaps) {
      found.insert(overlap.body);
      EXPECT_GT(overlap.penetration, 0.0f);
    }
    // Reference: the exact GJK distance between the probe and every body (no broad phase involved).
    for (const BodyID id : ids_) {
      BodyLockRead lock(world_->body_manager(), id);
      if (!lock.body().shape()->IsConvex()) continue;
      const ConvexShape& convex = static_cast<const ConvexShape&>(*lock.body().shape());
      const GjkResult gjk =
          GjkClosestPoints(PosedConvex(convex, lock.body().pose(), false),
                           PosedConvex(static_cast<const ConvexShape&>(*probe), pose, false), 100);
      if (gjk.overlapping) {
        EXPECT_TRUE(found.count(id)) << "missed body " << id.index;
      } else if (gjk.distance > 1e-4f) {
        EXPECT_FALSE(found.count(id)) << "reported separated body " << id.index;
      }
    }
  }
}

TEST_F(QueryTest, LayerFiltersSelectBodies) {
  const auto only_static = *world_->query().CastRay(Vec3(0.3f, 50, 0.2f), Vec3(0, -100, 0),
                                                    QueryFilter::OnlyLayer(layers::kNonMoving));
  ASSERT_TRUE(only_static.has_value());
  EXPECT_EQ(only_static->body, ids_[0]);
  EXPECT_NEAR(only_static->position.y(), 0.0f, 1e-4f);
  QueryFilter skip_floor;
  skip_floor.ignore_body_index = ids_[0].index;
  const auto boxes = *world_->query().CollideAABB(AABB(Vec3(-50, -5, -50), Vec3(50, 50, 50)), skip_floor);
  EXPECT_EQ(boxes.size(), ids_.size() - 1);
}

TEST_F(QueryTest, BadQueriesAreRejected) {
  EXPECT_FALSE(world_->query().CastRay(Vec3(NAN, 0, 0), Vec3(1, 0, 0)).ok());
  EXPECT_FALSE(world_->query().CastRay(Vec3(0, 0, 0), Vec3(0, 0, 0)).ok());
  EXPECT_FALSE(world_->query().CollideAABB(AABB(Vec3(1, 1, 1), Vec3(0, 0, 0))).ok());
  EXPECT_FALSE(world_->query().CollideShape(*Sphere(1), Pose{Vec3(INFINITY, 0, 0), Quat::Identity()}).ok());
}

TEST_F(QueryTest, QueriesSeeBodiesAfterSteps) {
  StepFor(*world_, 30);
  for (const BodyID id : ids_) {
    const AABB bounds = *world_->bodies().GetWorldBounds(id);
    const auto found = *world_->query().CollideAABB(bounds);
    EXPECT_TRUE(std::find(found.begin(), found.end(), id) != found.end());
  }
}

}  // namespace
}  // namespace strata::test
