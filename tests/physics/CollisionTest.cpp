// Narrow phase: GJK distances, EPA depths, manifolds from face clipping, meshes without internal-edge
// catches.
#include "TestWorld.h"
#include "physics/narrowphase/CollideShapes.h"
#include "physics/narrowphase/Epa.h"
#include "physics/narrowphase/Gjk.h"

namespace strata::test {
namespace {

const ConvexShape& Convex(const ShapeRef& shape) {
  return static_cast<const ConvexShape&>(*shape);
}

TEST(Collision, GjkDistanceBetweenBoxes) {
  const ShapeRef box = Box(1, 1, 1);
  const Pose a{Vec3(0, 0, 0), Quat::Identity()};
  const Pose b{Vec3(3.5f, 0.3f, -0.2f), Quat::Identity()};
  const GjkResult result =
      GjkClosestPoints(PosedConvex(Convex(box), a, false), PosedConvex(Convex(box), b, false), 10);
  ASSERT_FALSE(result.overlapping);
  EXPECT_NEAR(result.distance, 1.5f, 1e-4f);
  EXPECT_NEAR(result.point_a.x(), 1.0f, 1e-4f);
  EXPECT_NEAR(result.point_b.x(), 2.5f, 1e-4f);
}

TEST(Collision, TheGapAlongAnAxisIsTheShapesShadowsApartAndTheTestLeavesOneWhenApart) {
  // A rounded box (half 1, radius 0.05) turned 45 degrees about z, and a capsule standing 3 m to its right:
  // along x the box reaches its rounded corner, sqrt(2) (1 - r) + r; the capsule reaches back its radius.
  const ShapeRef box = Box(1, 1, 1), capsule = Capsule(0.5f, 0.25f);
  const Mat3 turned = Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 at_a(5, -2, 1), at_b = at_a + Vec3(3, 0, 0);
  const float corner = std::sqrt(2.0f) * (1.0f - 0.05f) + 0.05f;
  EXPECT_NEAR(GapAlong(Convex(box), at_a, turned, Convex(capsule), at_b, Mat3::Identity(), Vec3::UnitX()),
              3.0f - corner - 0.25f, 1e-5f);
  // Along y their shadows overlap by the box's reach plus the capsule's half length and radius.
  EXPECT_NEAR(GapAlong(Convex(box), at_a, turned, Convex(capsule), at_b, Mat3::Identity(), Vec3::UnitY()),
              -(corner + 0.75f), 1e-5f);
  // The contact test finds them apart and leaves an axis they are apart along beyond the reach (GJK stops
  // once it knows that, so not necessarily by their whole distance).
  CollisionScratch scratch;
  std::vector<ContactManifold> found;
  const Pose pose_a{at_a, Quat(Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitZ()))},
      pose_b{at_b, Quat::Identity()};
  CollideShapes(*box, pose_a, *capsule, pose_b, ContactReach{0.1f}, ContactManifold{}, found, scratch);
  EXPECT_TRUE(found.empty());
  ASSERT_FALSE(scratch.separating_axis.isZero());
  const Vec3 axis = scratch.separating_axis.normalized();
  const float gap = GapAlong(Convex(box), at_a, turned, Convex(capsule), at_b, Mat3::Identity(), axis);
  EXPECT_GT(gap, 0.1f);
  EXPECT_LE(gap, 3.0f - corner - 0.25f + 1e-5f);
  // The other way round the axis turns round with the pair.
  CollideShapes(*capsule, pose_b, *box, pose_a, ContactReach{0.1f}, ContactManifold{}, found, scratch);
  EXPECT_LT(scratch.separating_axis.normalized().dot(axis), -0.999f);
  // Touching: no axis is left.
  const Pose touching{at_a + Vec3(corner + 0.25f, 0, 0), Quat::Identity()};
  CollideShapes(*box, pose_a, *capsule, touching, ContactReach{0.1f}, ContactManifold{}, found, scratch);
  EXPECT_FALSE(found.empty());
  EXPECT_TRUE(scratch.separating_axis.isZero());
}

TEST(Collision, GjkHandlesLargeAgainstSmall) {
  // A 100 m floor against a 1 m box 1 mm above it: float-only simplex math loses this.
  const ShapeRef floor = Box(50, 1, 50), box = Box(0.5f, 0.5f, 0.5f);
  const Pose floor_pose{Vec3(0, -1, 0), Quat::Identity()};
  const Pose box_pose{Vec3(0.0002f, 0.501f, -0.0004f), Quat(Eigen::AngleAxisf(0.0003f, Vec3::UnitX()))};
  ContactManifold manifold;
  ASSERT_TRUE(CollideConvexConvex(Convex(box), box_pose, Convex(floor), floor_pose, 0.02f, manifold));
  EXPECT_GT(-manifold.normal.y(), 0.999f);
  EXPECT_EQ(manifold.count, 4);
  for (int i = 0; i < manifold.count; ++i) EXPECT_NEAR(manifold.points[i].separation, 0.001f, 2e-4f);
}

TEST(Collision, EpaDepthOfOverlappingBoxes) {
  const ShapeRef box = Box(1, 1, 1);
  const Pose a{Vec3(0, 0, 0), Quat::Identity()};
  const Pose b{Vec3(0.2f, 1.7f, 0.1f), Quat::Identity()};
  const PosedConvex exact_a(Convex(box), a, false), exact_b(Convex(box), b, false);
  const GjkResult gjk = GjkClosestPoints(exact_a, exact_b, 0.0f);
  ASSERT_TRUE(gjk.overlapping);
  PenetrationResult penetration;
  ASSERT_TRUE(EpaPenetration(exact_a, exact_b, gjk, penetration));
  EXPECT_NEAR(penetration.depth, 0.3f, 1e-3f);
  EXPECT_TRUE(penetration.normal.isApprox(Vec3(0, 1, 0), 1e-3f));
}

TEST(Collision, DeepBoxOverlapGivesFourPointManifold) {
  const ShapeRef box = Box(1, 1, 1);
  ContactManifold manifold;
  ASSERT_TRUE(CollideConvexConvex(Convex(box), Pose{Vec3(0, 0, 0), Quat::Identity()}, Convex(box),
                                  Pose{Vec3(0.1f, 1.6f, 0.0f), Quat::Identity()}, 0.02f, manifold));
  EXPECT_EQ(manifold.count, 4);
  EXPECT_TRUE(manifold.normal.isApprox(Vec3(0, 1, 0), 1e-3f));
  for (int i = 0; i < manifold.count; ++i) EXPECT_NEAR(manifold.points[i].separation, -0.4f, 1e-3f);
}

TEST(Collision, RotatedBoxCornerGivesOnePoint) {
  const ShapeRef box = SharpBox(1, 1, 1);
  const Quat corner_down = Quat::FromTwoVectors(Vec3(1, 1, 1).normalized(), Vec3(0, -1, 0));
  const float corner = std::sqrt(3.0f);
  ContactManifold manifold;
  ASSERT_TRUE(CollideConvexConvex(Convex(box), Pose{Vec3(0, corner - 0.01f, 0), corner_down},
                                  Convex(Box(5, 1, 5)), Pose{Vec3(0, -1, 0), Quat::Identity()}, 0.02f,
                                  manifold));
  EXPECT_EQ(manifold.count, 1);
  EXPECT_NEAR(manifold.points[0].separation, -0.01f, 1e-3f);
  EXPECT_TRUE(manifold.normal.isApprox(Vec3(0, -1, 0), 1e-3f));
}

TEST(Collision, SphereFastPathsMatchGeometry) {
  ContactManifold manifold;
  ASSERT_TRUE(CollideConvexConvex(Convex(Sphere(1)), Pose{Vec3(0, 0, 0), Quat::Identity()},
                                  Convex(Sphere(0.5f)), Pose{Vec3(1.4f, 0, 0), Quat::Identity()}, 0.0f,
                                  manifold));
  EXPECT_NEAR(manifold.points[0].separation, -0.1f, 1e-5f);
  ASSERT_TRUE(CollideConvexConvex(Convex(Sphere(0.5f)), Pose{Vec3(0, 1.4f, 0), Quat::Identity()},
                                  Convex(Box(1, 1, 1)), Pose{Vec3(0, 0, 0), Quat::Identity()}, 0.0f,
                                  manifold));
  EXPECT_NEAR(manifold.points[0].separation, -0.1f, 1e-5f);
  EXPECT_TRUE(manifold.normal.isApprox(Vec3(0, -1, 0), 1e-5f));
  EXPECT_FALSE(CollideConvexConvex(Convex(Sphere(0.5f)), Pose{Vec3(0, 3, 0), Quat::Identity()},
                                   Convex(Box(1, 1, 1)), Pose{Vec3(0, 0, 0), Quat::Identity()}, 0.1f,
                                   manifold));
}

TEST(Collision, CapsuleLyingOnBoxTouchesAlongItsLength) {
  const Quat lying(Eigen::AngleAxisf(kPi / 2, Vec3::UnitZ()));
  ContactManifold manifold;
  ASSERT_TRUE(CollideConvexConvex(Convex(Capsule(1, 0.5f)), Pose{Vec3(0, 0.49f, 0), lying},
                                  Convex(Box(5, 0.5f, 5)), Pose{Vec3(0, -0.5f, 0), Quat::Identity()}, 0.02f,
                                  manifold));
  EXPECT_EQ(manifold.count, 2);
  for (int i = 0; i < manifold.count; ++i) EXPECT_NEAR(manifold.points[i].separation, -0.01f, 1e-3f);
}

std::shared_ptr<const TriangleMeshShape> FlatGrid(int cells, float size) {
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  for (int z = 0; z <= cells; ++z)
    for (int x = 0; x <= cells; ++x)
      vertices.emplace_back(x * size - cells * size / 2, 0.0f, z * size - cells * size / 2);
  for (int z = 0; z < cells; ++z)
    for (int x = 0; x < cells; ++x) {
      const std::uint32_t i0 = z * (cells + 1) + x, i1 = i0 + 1, i2 = i0 + cells + 1, i3 = i2 + 1;
      triangles.push_back({i0, i2, i1});
      triangles.push_back({i1, i2, i3});
    }
  return std::static_pointer_cast<const TriangleMeshShape>(*TriangleMeshShape::Create(vertices, triangles));
}

TEST(Collision, CapsuleTouchesASphereOnItsTopWhicheverComesFirst) {
  // The sphere's core is a point: the capsule's nearest core point is the top of its segment, not an end
  // picked by default (which missed this contact with the capsule as A).
  const ShapeRef capsule = Capsule(0.3f, 0.3f), ball = Sphere(0.5f);
  const Pose standing{Vec3(0.05f, 0.0f, -0.03f), Quat::Identity()};
  const Pose above{Vec3(0.0f, 1.05f, 0.0f), Quat::Identity()};
  const float expected = (above.position - Vec3(0.05f, 0.3f, -0.03f)).norm() - 0.8f;  // -0.0485
  ContactManifold capsule_first, ball_first;
  ASSERT_TRUE(CollideConvexConvex(Convex(capsule), standing, Convex(ball), above, 0.02f, capsule_first));
  ASSERT_TRUE(CollideConvexConvex(Convex(ball), above, Convex(capsule), standing, 0.02f, ball_first));
  EXPECT_NEAR(capsule_first.MinSeparation(), expected, 1e-4f);
  EXPECT_NEAR(ball_first.MinSeparation(), expected, 1e-4f);
  EXPECT_GT(capsule_first.normal.y(), 0.99f);
  EXPECT_LT(ball_first.normal.y(), -0.99f);
}

TEST(Collision, ABallLandsOnALyingCapsuleWhicheverWasMadeFirst) {
  // The ball comes down on the middle of the capsule's core, not an end of it: the contact a point core
  // needs from the nearest point of a segment (the capsule as A missed it).
  for (const bool capsule_first : {true, false}) {
    auto world = MakeWorld();
    Add(*world, Static(Box(5, 0.5f, 5), Vec3(0, -0.5f, 0)));
    const BodyCreationSettings capsule =
        Dynamic(Capsule(0.6f, 0.3f), Vec3(0, 0.3f, 0), Quat(Eigen::AngleAxisf(kPi / 2, Vec3::UnitZ())));
    const BodyCreationSettings ball = Dynamic(Sphere(0.5f), Vec3(0.05f, 2.0f, 0.0f));
    const BodyID first = Add(*world, capsule_first ? capsule : ball);
    const BodyID second = Add(*world, capsule_first ? ball : capsule);
    const BodyID dropped = capsule_first ? second : first;
    StepFor(*world, 40);  // two thirds of a second: it lands on the capsule (top 0.6) at about 0.43 s
    // On the capsule (centre near 1.1), not through it onto the floor (0.5).
    EXPECT_GT(Position(*world, dropped).y(), 0.9f)
        << (capsule_first ? "capsule made first" : "ball made first");
  }
}

TEST(Collision, BoxOnMeshEdgeUsesFaceNormal) {
  const auto grid = FlatGrid(4, 1.0f);
  // A box whose bottom spans an internal diagonal and a grid line.
  std::vector<ContactManifold> manifolds;
  CollideConvexMesh(Convex(Box(0.3f, 0.3f, 0.3f)), Pose{Vec3(0.0f, 0.29f, 0.0f), Quat::Identity()}, *grid,
                    Pose{}, 0.02f, ContactManifold{}, manifolds);
  ASSERT_FALSE(manifolds.empty());
  for (const ContactManifold& manifold : manifolds) {
    EXPECT_GT(-manifold.normal.y(), 0.999f);
    for (int i = 0; i < manifold.count; ++i) EXPECT_NEAR(manifold.points[i].separation, -0.01f, 2e-3f);
  }
}

TEST(Collision, ARoundedBoxOnAFlatMeshGetsTheFaceNormalWhereItsCoreOverhangsAnInternalCorner) {
  // A pose BoxSlidingOverMeshDoesNotCatchOnInternalEdges reaches at 6 m/s, turned by a hundredth of a degree.
  // The rounded core overhangs an internal corner of the first triangle it meets, and GJK's normal from that
  // corner tilts by 1.8 degrees: opening the manifold, it pushed the sliding box sideways and up.
  const auto grid = FlatGrid(40, 1.0f);
  const Pose sliding{Vec3(-8.89895821f, 0.249753028f, 0.301060379f),
                     Quat(1.0f, -0.000126787796f, -1.41026703e-06f, 3.65597152e-05f).normalized()};
  std::vector<ContactManifold> found;
  CollideConvexMesh(Convex(Box(0.25f, 0.25f, 0.25f)), sliding, *grid, Pose{}, 0.02f, ContactManifold{},
                    found);
  ASSERT_FALSE(found.empty());
  for (const ContactManifold& manifold : found) EXPECT_GT(-manifold.normal.y(), 0.999999f);
}

TEST(Collision, BoxSlidingOverMeshDoesNotCatchOnInternalEdges) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  BodyCreationSettings ground;
  ground.shape = FlatGrid(40, 1.0f);
  ground.motion_type = MotionType::kStatic;
  ground.object_layer = layers::kNonMoving;
  ground.friction = 0.0f;
  Add(*world, ground);
  BodyCreationSettings box = Dynamic(Box(0.25f, 0.25f, 0.25f), Vec3(-15, 0.25f, 0.3f));
  box.friction = 0.0f;
  box.linear_damping = 0.0f;
  box.angular_damping = 0.0f;
  box.linear_velocity = Vec3(6, 0, 0);
  const BodyID id = Add(*world, box);
  float max_vertical = 0.0f, min_forward = 100.0f;
  for (int step = 0; step < 180; ++step) {
    ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
    max_vertical = std::max(max_vertical, std::abs(Velocity(*world, id).y()));
    min_forward = std::min(min_forward, Velocity(*world, id).x());
  }
  EXPECT_LT(max_vertical, 0.1f);  // no hops over triangle edges
  EXPECT_GT(min_forward, 5.9f);   // no speed lost to catching
  EXPECT_NEAR(Position(*world, id).y(), 0.25f, 0.01f);
}

TEST(Collision, EveryShapeRestsOnAMesh) {
  PhysicsSettings settings;
  auto world = MakeWorld(settings);
  BodyCreationSettings ground;
  ground.shape = FlatGrid(20, 2.0f);
  ground.motion_type = MotionType::kStatic;
  ground.object_layer = layers::kNonMoving;
  Add(*world, ground);
  const std::vector<Vec3> hull_points = {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1),
                                         Vec3(0, 0, -1)};
  const std::vector<std::pair<ShapeRef, float>> shapes = {{Box(0.5f, 0.75f, 1.0f), 0.75f},
                                                          {Sphere(0.5f), 0.5f},
                                                          {Capsule(0.75f, 0.5f), 1.25f},
                                                          {*ConvexHullShape::Create(hull_points), 0.0f}};
  std::vector<BodyID> ids;
  for (std::size_t i = 0; i < shapes.size(); ++i)
    ids.push_back(Add(*world, Dynamic(shapes[i].first, Vec3(4.0f * i - 6.0f, 3.0f, 1.0f))));
  StepFor(*world, 240);
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const AABB bounds = *world->bodies().GetWorldBounds(ids[i]);
    EXPECT_NEAR(bounds.min.y(), 0.0f, 0.02f) << "shape " << i;
    EXPECT_LT(Velocity(*world, ids[i]).norm(), 0.05f) << "shape " << i;
  }
}

}  // namespace
}  // namespace strata::test
