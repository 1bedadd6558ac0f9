// The box-box collider against the general polyhedron collider it stands in for (random pairs, fixed seed:
// the same hit, normal, point count and points),
// and against closed forms: a box resting on a floor, crossed edges, a gap.
#include <random>

#include "TestWorld.h"
#include "physics/narrowphase/BoxBoxCollider.h"
#include "physics/narrowphase/PolyhedronCollider.h"

namespace strata::test {
namespace {

struct PosedPair {
  BoxShape a, b;
  Pose pose_a, pose_b;
};

Quat RandomRotation(std::mt19937& random) {
  std::normal_distribution<float> normal;
  return Quat(normal(random), normal(random), normal(random), normal(random)).normalized();
}

PosedPair RandomPair(std::mt19937& random) {
  std::uniform_real_distribution<float> extent(0.05f, 3.0f), unit(-1.0f, 1.0f);
  const Vec3 half_a(extent(random), extent(random), extent(random));
  const Vec3 half_b(extent(random), extent(random), extent(random));
  // Centres about as far apart as the boxes are big, so that about half the pairs touch.
  const float reach = 0.8f * (half_a.norm() + half_b.norm());
  const Vec3 offset = reach * Vec3(unit(random), unit(random), unit(random));
  return {BoxShape(half_a, 0.0f), BoxShape(half_b, 0.0f), Pose{Vec3(10, -3, 7), RandomRotation(random)},
          Pose{Vec3(10, -3, 7) + offset, RandomRotation(random)}};
}

bool ThroughPolyhedra(const PosedPair& pair, float max_separation, ContactManifold& manifold) {
  Polyhedron a, b;
  EXPECT_TRUE(MakePolyhedron(pair.a, pair.pose_a, a));
  EXPECT_TRUE(MakePolyhedron(pair.b, pair.pose_b, b));
  return CollidePolyhedra(a, b, max_separation, manifold);
}

TEST(BoxBoxCollider, AgreesWithThePolyhedronColliderOnRandomPairs) {
  std::mt19937 random(20261124);
  constexpr float kMaxSeparation = 0.05f;
  int touching = 0, differing = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const PosedPair pair = RandomPair(random);
    ContactManifold boxes, general;
    const bool hit = CollideBoxes(pair.a, pair.pose_a, pair.b, pair.pose_b, kMaxSeparation, boxes);
    ASSERT_EQ(hit, ThroughPolyhedra(pair, kMaxSeparation, general)) << "trial " << trial;
    if (!hit) continue;
    ++touching;
    ASSERT_GT(boxes.normal.dot(general.normal), 0.9999f) << "trial " << trial;
    ASSERT_EQ(boxes.count, general.count) << "trial " << trial;
    EXPECT_NEAR(boxes.MinSeparation(), general.MinSeparation(), 1e-4f) << "trial " << trial;
    // The same points, in whatever order. Reducing a clipped polygon of more than four points to four picks
    // the largest triangle: where two candidates tie to rounding, either is right, so a few pairs may differ.
    bool same_points = true;
    for (int i = 0; i < boxes.count; ++i) {
      float nearest = kLargeFloat;
      for (int j = 0; j < general.count; ++j)
        nearest = std::min(nearest, (boxes.points[i].position_a - general.points[j].position_a).norm() +
                                        (boxes.points[i].position_b - general.points[j].position_b).norm());
      same_points &= nearest < 2e-3f;
    }
    differing += same_points ? 0 : 1;
  }
  EXPECT_LE(differing, touching / 200) << differing << " of " << touching << " pairs";
  // Both outcomes were exercised in quantity.
  EXPECT_GT(touching, 1000);
  EXPECT_LT(touching, 3000);
}

TEST(BoxBoxCollider, BoxRestingOnAFloorTouchesAtItsFourBottomCornersInEitherOrder) {
  // The faces are parallel (to rounding, when the box is tipped by a hair), so either could be the reference:
  // the floor's is, whichever body comes first, and the box's bottom face needs no clipping.
  const BoxShape floor(Vec3(50, 1, 50), 0.0f), box(Vec3(0.5f, 0.25f, 0.5f), 0.0f);
  const Pose floor_pose{Vec3(0, -1, 0), Quat::Identity()};
  for (const float tip : {0.0f, 2e-5f}) {
    const Quat turn(Eigen::AngleAxisf(0.3f, Vec3::UnitY()) * Eigen::AngleAxisf(tip, Vec3::UnitX()));
    const Pose box_pose{Vec3(3, 0.24f, -2), turn};
    for (const bool floor_first : {true, false}) {
      ContactManifold manifold;
      ASSERT_TRUE(floor_first ? CollideBoxes(floor, floor_pose, box, box_pose, 0.02f, manifold)
                              : CollideBoxes(box, box_pose, floor, floor_pose, 0.02f, manifold));
      const Vec3 up = floor_first ? Vec3::UnitY() : Vec3(-Vec3::UnitY());  // the normal points from A to B
      EXPECT_TRUE(manifold.normal.isApprox(up, 1e-6f)) << tip << " " << floor_first;
      ASSERT_EQ(manifold.count, 4) << tip << " " << floor_first;
      for (int i = 0; i < 4; ++i) {
        const ContactPoint& point = manifold.points[i];
        const Vec3& on_floor = floor_first ? point.position_a : point.position_b;
        const Vec3& on_box = floor_first ? point.position_b : point.position_a;
        EXPECT_NEAR(point.separation, -0.01f, 2e-5f) << tip << " " << floor_first;
        EXPECT_NEAR(on_floor.y(), 0.0f, 1e-5f) << tip << " " << floor_first;
        // Each point is a bottom corner of the box: 0.5 * sqrt(2) from its centre in the floor's plane.
        const Vec3 from_centre = on_box - box_pose.position;
        EXPECT_NEAR(Vec3(from_centre.x(), 0, from_centre.z()).norm(), 0.5f * std::sqrt(2.0f), 1e-5f)
            << tip << " " << floor_first;
        EXPECT_NEAR(from_centre.y(), -0.25f, 2e-5f) << tip << " " << floor_first;
      }
    }
  }
}

TEST(BoxBoxCollider, EqualBoxesStackedCornerToCornerTouchAtTheirFourCorners) {
  // A tower's boxes: each one's bottom face meets the top face of the one below along all four edges, within
  // rounding (turned a hair, shifted a hair). The manifold is the four corners, not near-copies of some.
  const BoxShape cube(Vec3::Constant(0.5f), 0.0f);
  for (const float shift : {0.0f, 1e-7f, -3e-7f, 2e-6f})
    for (const float turn : {0.0f, 1e-6f, -4e-6f}) {
      const Pose lower{Vec3(3, 0.5f, -7), Quat::Identity()};
      const Pose upper{Vec3(3 + shift, 1.499f, -7 - shift), Quat(Eigen::AngleAxisf(turn, Vec3::UnitY()))};
      ContactManifold manifold;
      ASSERT_TRUE(CollideBoxes(cube, lower, cube, upper, 0.02f, manifold));
      ASSERT_EQ(manifold.count, 4) << shift << " " << turn;
      for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(manifold.points[i].separation, -0.001f, 1e-5f);
        for (int j = 0; j < i; ++j)
          EXPECT_GT((manifold.points[i].position_b - manifold.points[j].position_b).norm(), 0.99f)
              << shift << " " << turn;
      }
    }
}

TEST(BoxBoxCollider, CrossedEdgesTouchAtOnePointBetweenThem) {
  // Two unit cubes each turned 45 degrees, one about z and one about x, stacked so that their ridge edges
  // cross: the upper one's lowest edge runs along z, the lower one's highest along x.
  const BoxShape cube(Vec3::Constant(0.5f), 0.0f);
  const float ridge = 0.5f * std::sqrt(2.0f);
  const Pose lower{Vec3::Zero(), Quat(Eigen::AngleAxisf(kPi / 4, Vec3::UnitX()))};
  const Pose upper{Vec3(0, 2 * ridge - 0.01f, 0), Quat(Eigen::AngleAxisf(kPi / 4, Vec3::UnitZ()))};
  ContactManifold manifold;
  ASSERT_TRUE(CollideBoxes(cube, lower, cube, upper, 0.02f, manifold));
  ASSERT_EQ(manifold.count, 1);
  EXPECT_TRUE(manifold.normal.isApprox(Vec3::UnitY(), 1e-4f));
  EXPECT_NEAR(manifold.points[0].separation, -0.01f, 1e-5f);
  EXPECT_LT(manifold.points[0].position_a.cwiseAbs().x() + manifold.points[0].position_a.cwiseAbs().z(),
            1e-5f);
}

TEST(BoxBoxCollider, AGapWiderThanTheMarginIsNoContactAndANarrowerOneIsSpeculative) {
  const BoxShape cube(Vec3::Constant(0.5f), 0.0f);
  const Pose a{Vec3::Zero(), Quat::Identity()};
  ContactManifold manifold;
  EXPECT_FALSE(CollideBoxes(cube, a, cube, Pose{Vec3(1.03f, 0.2f, 0), Quat::Identity()}, 0.02f, manifold));
  ASSERT_TRUE(CollideBoxes(cube, a, cube, Pose{Vec3(1.01f, 0.2f, 0), Quat::Identity()}, 0.02f, manifold));
  EXPECT_TRUE(manifold.normal.isApprox(Vec3::UnitX(), 1e-6f));
  EXPECT_EQ(manifold.count, 4);
  EXPECT_NEAR(manifold.MinSeparation(), 0.01f, 1e-5f);
}

}  // namespace
}  // namespace strata::test
