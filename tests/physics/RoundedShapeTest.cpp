// Rounded boxes and hulls (convex radius): their size and errors, contacts measured against closed-form
// distances, resting heights, rays on the rounded corners, and runs that match bit for bit on any thread
// count.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/core/ThreadPoolJobSystem.h"
#include "physics/narrowphase/CollideShapes.h"
#include "tests/physics/TestWorld.h"

namespace strata::test {
namespace {

const ConvexShape& Convex(const ShapeRef& shape) {
  return static_cast<const ConvexShape&>(*shape);
}

// Square pyramid, apex up: Jolt's PerformanceTest hull.
ShapeRef Pyramid(std::optional<float> convex_radius = std::nullopt) {
  const std::vector<Vec3> points = {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1),
                                    Vec3(0, 0, -1)};
  return convex_radius ? *ConvexHullShape::Create(points, *convex_radius) : *ConvexHullShape::Create(points);
}

// The contact of `a` at `pose_a` with `b` at `pose_b`, looking `reach` apart.
ContactManifold Contact(const ShapeRef& a, const Pose& pose_a, const ShapeRef& b, const Pose& pose_b,
                        float reach = 1.0f) {
  ContactManifold manifold;
  EXPECT_TRUE(CollideConvexConvex(Convex(a), pose_a, Convex(b), pose_b, reach, manifold));
  return manifold;
}

// A sphere's distance to a rounded box: to the core box, less both radii.
float SphereToRoundedBox(const Vec3& centre, const Vec3& core_half, float convex_radius,
                         float sphere_radius) {
  const Vec3 nearest = centre.cwiseMax(-core_half).cwiseMin(core_half);
  return (centre - nearest).norm() - convex_radius - sphere_radius;
}

TEST(RoundedShape, TheDefaultRadiusIsJoltsShrunkForSmallShapesAndBadRadiiAreRefused) {
  EXPECT_FLOAT_EQ(Convex(Box(1, 2, 3)).convex_radius(), kDefaultConvexRadius);
  EXPECT_FLOAT_EQ(Convex(Box(0.1f, 2, 3)).convex_radius(), 0.025f);  // a quarter of the thinnest side
  EXPECT_FLOAT_EQ(Convex(SharpBox(1, 1, 1)).convex_radius(), 0.0f);
  EXPECT_FALSE(Convex(SharpBox(1, 1, 1)).CoreIsExact());
  EXPECT_FLOAT_EQ(Convex(*BoxShape::Create(Vec3(1, 1, 1), 0.3f)).convex_radius(), 0.3f);
  EXPECT_FLOAT_EQ(Convex(Pyramid()).convex_radius(), kDefaultConvexRadius);
  EXPECT_FLOAT_EQ(Convex(Pyramid(0.0f)).convex_radius(), 0.0f);
  // A rounded box keeps its extents: the rounding is inside them.
  EXPECT_EQ(Box(1, 2, 3)->LocalBounds().max, Vec3(1, 2, 3));
  for (const float bad : {-0.01f, 1.5f, std::nanf(""), INFINITY}) {
    const Result<ShapeRef> box = BoxShape::Create(Vec3(1, 2, 3), bad);
    ASSERT_FALSE(box.ok()) << bad;
    EXPECT_NE(box.error().message.find("convex radius"), std::string::npos) << box.error().message;
  }
  // Rounded by its whole thinnest half extent, a box's core is flat: still a shape rays and contacts meet.
  const ShapeRef slab = *BoxShape::Create(Vec3(1, 0.2f, 1), 0.2f);
  ShapeRayHit hit;
  ASSERT_TRUE(slab->CastRay(Vec3(0.3f, 2, 0.1f), Vec3(0, -4, 0), 1.0f, hit));
  EXPECT_NEAR(2.0f - 4.0f * hit.fraction, 0.2f, 1e-5f);
  ContactManifold on_slab;
  ASSERT_TRUE(CollideConvexConvex(Convex(slab), Pose{}, Convex(Sphere(0.5f)),
                                  Pose{Vec3(0.9f, 0.65f, 0.9f), Quat::Identity()}, 0.1f, on_slab));
  EXPECT_NEAR(on_slab.MinSeparation(),
              SphereToRoundedBox(Vec3(0.9f, 0.65f, 0.9f), Vec3(0.8f, 0, 0.8f), 0.2f, 0.5f), 2e-4f);
  // The pyramid's interior is 0.2 m deep below its centroid: half of that at most.
  const std::vector<Vec3> points = {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1),
                                    Vec3(0, 0, -1)};
  EXPECT_TRUE(ConvexHullShape::Create(points, 0.1f).ok());
  EXPECT_FALSE(ConvexHullShape::Create(points, 0.11f).ok());
  EXPECT_FALSE(ConvexHullShape::Create(points, -1.0f).ok());
}

TEST(RoundedShape, ContactsWithASphereMatchTheDistanceToTheCoreAtFacesEdgesAndCorners) {
  const Vec3 half(1.0f, 0.5f, 0.75f);
  const float radius = 0.1f;
  const ShapeRef box = *BoxShape::Create(half, radius), sphere = Sphere(0.3f);
  const Vec3 core = half.array() - radius;
  const Pose box_pose{Vec3(40, -3, 12), Quat(Eigen::AngleAxisf(0.4f, Vec3(1, 2, 3).normalized()))};
  // Before a face, an edge and a corner, apart and overlapping.
  const std::vector<Vec3> local_centres = {
      Vec3(0.2f, 0.9f, 0.1f),  Vec3(0.3f, 0.75f, 0.1f),  Vec3(1.2f, 0.7f, 0.2f),   Vec3(1.15f, 0.68f, 0.1f),
      Vec3(1.2f, 0.7f, 0.95f), Vec3(1.05f, 0.6f, 0.85f), Vec3(-1.3f, -0.8f, 1.0f), Vec3(0.0f, -0.55f, -0.9f)};
  for (const Vec3& local : local_centres) {
    const Vec3 centre = box_pose.ToWorld(local);
    const ContactManifold manifold = Contact(box, box_pose, sphere, Pose{centre, Quat::Identity()});
    ASSERT_EQ(manifold.count, 1);
    const float expected = SphereToRoundedBox(local, core, radius, 0.3f);
    EXPECT_NEAR(manifold.points[0].separation, expected, 2e-4f) << local.transpose();
    // The normal runs from the core's nearest point to the centre.
    const Vec3 nearest = local.cwiseMax(-core).cwiseMin(core);
    const Vec3 normal = box_pose.DirectionToWorld((local - nearest).normalized());
    EXPECT_GT(manifold.normal.dot(normal), 0.9999f) << local.transpose();
  }
}

TEST(RoundedShape, TwoRoundedBoxesMeetEdgeOnEdgeAtTheCoresDistanceLessBothRadii) {
  // Two unit cubes, one turned 45 degrees about z and the other 45 degrees about x, edges crossed above
  // each other: the cores' edges are sqrt(2) (1 - r) from each centre.
  const float radius = 0.05f;
  const ShapeRef cube = *BoxShape::Create(Vec3::Constant(1.0f), radius);
  const Pose lower{Vec3(3, 1, -2), Quat(Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitZ()))};
  for (const float gap : {0.02f, 0.0f, -0.03f}) {
    const float reach = std::sqrt(2.0f) * (1.0f - radius) + radius;
    const Pose upper{lower.position + Vec3(0, 2 * reach + gap, 0),
                     Quat(Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitX()))};
    const ContactManifold manifold = Contact(cube, lower, cube, upper);
    ASSERT_GE(manifold.count, 1);
    EXPECT_NEAR(manifold.MinSeparation(), gap, 2e-4f);
    EXPECT_GT(manifold.normal.y(), 0.9999f);
  }
}

TEST(RoundedShape, ARoundedBoxOnItsEdgeTouchesAtTheRoundingNotTheSharpEdge) {
  const float radius = 0.05f;
  const ShapeRef cube = *BoxShape::Create(Vec3::Constant(0.5f), radius);
  const ShapeRef floor = SharpBox(5, 1, 5);
  const float rounded_reach = std::sqrt(2.0f) * (0.5f - radius) + radius;  // below the centre
  const Pose on_edge{Vec3(0, rounded_reach - 0.002f, 0), Quat(Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitZ()))};
  const ContactManifold manifold =
      Contact(floor, Pose{Vec3(0, -1, 0), Quat::Identity()}, cube, on_edge, 0.02f);
  ASSERT_GE(manifold.count, 1);
  EXPECT_GT(manifold.normal.y(), 0.9999f);
  // 2 mm in, not the 2 cm more the sharp edge would be.
  for (int i = 0; i < manifold.count; ++i) EXPECT_NEAR(manifold.points[i].separation, -0.002f, 2e-4f);
  // The sharp box is in by (sqrt(2) - 1) r more there.
  const ContactManifold sharp =
      Contact(floor, Pose{Vec3(0, -1, 0), Quat::Identity()}, SharpBox(0.5f, 0.5f, 0.5f), on_edge, 0.02f);
  EXPECT_NEAR(sharp.MinSeparation(), -0.002f - (std::sqrt(2.0f) - 1.0f) * radius, 5e-4f);
}

TEST(RoundedShape, ARoundedHullsApexIsItsCorePointPlusTheRadius) {
  // The pyramid's four slanted faces, moved in by r, meet below its apex; its flat bottom stays put.
  const ShapeRef rounded = Pyramid(0.05f), sharp = Pyramid(0.0f), ball = Sphere(0.25f);
  // The faces are (1, 1, 1)-like planes x + y + z = 1: moved in by r they meet on the axis at y = 1 - sqrt(3)
  // r.
  const float core_apex = 1.0f - std::sqrt(3.0f) * 0.05f;
  const Pose hull_pose{Vec3(-7, 2, 5), Quat::Identity()};
  const Pose above{hull_pose.position + Vec3(0, 1.4f, 0), Quat::Identity()};
  const ContactManifold round = Contact(rounded, hull_pose, ball, above);
  EXPECT_NEAR(round.points[0].separation, 1.4f - core_apex - 0.05f - 0.25f, 2e-4f);
  EXPECT_NEAR(Contact(sharp, hull_pose, ball, above).points[0].separation, 1.4f - 1.0f - 0.25f, 2e-4f);
  // Its flat bottom stays where the points put it.
  const Pose below{hull_pose.position + Vec3(0.1f, -0.3f, 0.05f), Quat::Identity()};
  EXPECT_NEAR(Contact(rounded, hull_pose, ball, below).points[0].separation, 0.3f - 0.25f, 2e-4f);
}

TEST(RoundedShape, RaysHitTheRoundedCornerAndPassWhereOnlyTheSharpCornerWouldBe) {
  const float radius = 0.1f;
  const ShapeRef box = *BoxShape::Create(Vec3::Constant(1.0f), radius);
  const Vec3 diagonal = Vec3(1, 1, 1).normalized();
  ShapeRayHit hit;
  // Straight at the corner along the diagonal: it meets the corner sphere around the core's corner.
  ASSERT_TRUE(box->CastRay(Vec3::Constant(3.0f), -diagonal * 10.0f, 1.0f, hit));
  const Vec3 expected = Vec3::Constant(1.0f - radius) + radius * diagonal;
  EXPECT_NEAR(hit.fraction * 10.0f, (Vec3::Constant(3.0f) - expected).norm(), 1e-4f);
  EXPECT_GT(hit.normal.dot(diagonal), 0.9999f);
  // Past the rounded edge along x, 5 mm inside the sharp box's two faces: only the sharp box is hit.
  const Vec3 grazing(-3, 1.0f - 0.005f, 1.0f - 0.005f);
  EXPECT_FALSE(box->CastRay(grazing, Vec3(6, 0, 0), 1.0f, hit));
  EXPECT_TRUE(SharpBox(1, 1, 1)->CastRay(grazing, Vec3(6, 0, 0), 1.0f, hit));
  // A face is where it always was, with its own normal.
  ASSERT_TRUE(box->CastRay(Vec3(0.3f, 5, -0.2f), Vec3(0, -10, 0), 1.0f, hit));
  EXPECT_FLOAT_EQ(hit.fraction, 0.4f);
  EXPECT_EQ(hit.normal, Vec3::UnitY());
  // From inside: at once.
  ASSERT_TRUE(box->CastRay(Vec3::Zero(), Vec3(0, 0, 5), 1.0f, hit));
  EXPECT_EQ(hit.fraction, 0.0f);
  // The rounded hull's apex, from above.
  ASSERT_TRUE(Pyramid(0.05f)->CastRay(Vec3(0, 3, 0), Vec3(0, -3, 0), 1.0f, hit));
  EXPECT_NEAR(3.0f - 3.0f * hit.fraction, 1.0f - std::sqrt(3.0f) * 0.05f + 0.05f, 1e-4f);
  EXPECT_GT(hit.normal.y(), 0.9999f);
}

TEST(RoundedShape, TurnedBoundsFitTheRoundedShape) {
  const ShapeRef box = *BoxShape::Create(Vec3(1, 0.5f, 0.25f), 0.2f);
  const Pose turned{Vec3(100, 0, -50), Quat(Eigen::AngleAxisf(0.7f, Vec3(1, 1, 0).normalized()))};
  const AABB bounds = box->WorldBounds(turned);
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 along = Vec3::Unit(axis);
    const float reach = turned.ToWorld(Convex(box).Support(turned.DirectionToLocal(along)))[axis];
    EXPECT_NEAR(bounds.max[axis], reach, 1e-4f);
    EXPECT_GT(SharpBox(1, 0.5f, 0.25f)->WorldBounds(turned).max[axis], bounds.max[axis] + 0.01f);
  }
}

TEST(RoundedShape, RoundedHullsOfRandomCloudsStayInsideTheirPointsHullAndKeepTheirFaces) {
  std::mt19937 random(42);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int cloud = 0; cloud < 20; ++cloud) {
    std::vector<Vec3> points;
    const int count = 6 + 20 * (cloud % 5);
    const Vec3 stretch(1.0f + unit(random) * 0.5f, 1.0f + unit(random) * 0.8f, 0.5f + unit(random) * 0.3f);
    for (int i = 0; i < count; ++i)
      points.push_back(stretch.cwiseProduct(Vec3(unit(random), unit(random), unit(random)).normalized()));
    const Result<ShapeRef> made = ConvexHullShape::Create(points);
    ASSERT_TRUE(made.ok()) << made.error().message;
    const auto& hull = static_cast<const ConvexHullShape&>(**made);
    ASSERT_TRUE(hull.CoreIsExact());
    const float radius = hull.convex_radius();
    // Every support of the rounded shape lies on or inside every face plane of the points' hull.
    for (int d = 0; d < 200; ++d) {
      const Vec3 direction(unit(random), unit(random), unit(random));
      const Vec3 reach = hull.Support(direction);
      for (const HullFace& face : hull.faces()) EXPECT_LE(face.normal.dot(reach) - face.offset, 1e-4f);
    }
    // And it is no smaller than the hull scaled until every face is the radius in, then rounded: along a
    // face's normal it reaches the plane less the radius's share of the face's distance from the centroid.
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& v : hull.vertices()) centroid += v;
    centroid /= static_cast<float>(hull.vertices().size());
    float depth = kLargeFloat;
    for (const HullFace& face : hull.faces())
      depth = std::min(depth, face.offset - face.normal.dot(centroid));
    for (const HullFace& face : hull.faces()) {
      const float from_centroid = face.offset - face.normal.dot(centroid);
      EXPECT_GE(face.normal.dot(hull.Support(face.normal)),
                face.offset - radius / depth * from_centroid - 1e-4f);
    }
    EXPECT_GT(radius, 0.0f);
  }
}

// 16 m x 16 m of ground in 2 m cells, rising and falling half a metre.
void WavyGround(std::vector<Vec3>& vertices, std::vector<TriangleMeshShape::Indices>& triangles) {
  for (int z = 0; z <= 8; ++z)
    for (int x = 0; x <= 8; ++x)
      vertices.emplace_back(2.0f * x - 8.0f, 0.5f * std::sin(1.3f * x) * std::cos(0.9f * z), 2.0f * z - 8.0f);
  for (std::uint32_t z = 0; z < 8; ++z)
    for (std::uint32_t x = 0; x < 8; ++x) {
      const std::uint32_t i = z * 9 + x;
      triangles.push_back({i, i + 9, i + 1});
      triangles.push_back({i + 1, i + 9, i + 10});
    }
}

// Rounded boxes and pyramids dropped on a wavy mesh: where every body is after `steps`, bit for bit.
std::vector<float> DropOnMesh(std::shared_ptr<JobSystem> jobs, int steps) {
  PhysicsSystemConfig config;
  config.max_bodies = 64;
  config.job_system = std::move(jobs);
  auto world = std::move(*PhysicsSystem::Create(config, PhysicsSettings{}));
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  WavyGround(vertices, triangles);
  Add(*world, Static(*TriangleMeshShape::Create(vertices, triangles), Vec3::Zero()));
  std::vector<BodyID> ids;
  for (int i = 0; i < 24; ++i) {
    const ShapeRef shape = i % 2 == 0 ? Box(0.4f, 0.3f, 0.5f) : Pyramid();
    const Vec3 at(-5.0f + 2.2f * (i % 5), 2.0f + 1.1f * (i / 5), -4.0f + 1.7f * (i % 4));
    ids.push_back(
        Add(*world, Dynamic(shape, at, Quat(Eigen::AngleAxisf(0.3f * i, Vec3(1, 2, 3).normalized())))));
  }
  StepFor(*world, steps);
  return Positions(*world, ids);
}

TEST(RoundedShape, PilesOnAMeshSettleAboveItAndMatchBitForBitOnEveryThreadCount) {
  const std::vector<float> serial = DropOnMesh(std::make_shared<SerialJobSystem>(), 180);
  EXPECT_EQ(DropOnMesh(std::make_shared<ThreadPoolJobSystem>(2), 180), serial);
  EXPECT_EQ(DropOnMesh(std::make_shared<ThreadPoolJobSystem>(4), 180), serial);
  for (std::size_t i = 1; i < serial.size(); i += 3) EXPECT_GT(serial[i], -0.6f);  // none fell through
}

// Over a tilted, finely split plane the rounded shape's nearest point is its core's lowest point less the
// radius, whether it stands over a triangle's inside (taken from the plane) or beside an edge (GJK decides).
TEST(RoundedShape, OnAMeshEveryPoseTouchesAtTheCoresLowestPointLessTheRadius) {
  const Quat tilt(Eigen::AngleAxisf(0.35f, Vec3(1, 0, 2).normalized()));
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  for (int z = 0; z <= 12; ++z)
    for (int x = 0; x <= 12; ++x) vertices.push_back(tilt * Vec3(0.5f * x - 3.0f, 0.0f, 0.5f * z - 3.0f));
  for (std::uint32_t z = 0; z < 12; ++z)
    for (std::uint32_t x = 0; x < 12; ++x) {
      const std::uint32_t i = z * 13 + x;
      triangles.push_back({i, i + 13, i + 1});
      triangles.push_back({i + 1, i + 13, i + 14});
    }
  const ShapeRef mesh = *TriangleMeshShape::Create(vertices, triangles);
  const Vec3 up = tilt * Vec3::UnitY();
  std::mt19937 random(42);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), gap(0.0005f, 0.04f);
  for (int i = 0; i < 400; ++i) {
    const ShapeRef shape = i % 2 == 0 ? Box(0.4f, 0.3f, 0.5f) : Pyramid();
    const ConvexShape& convex = Convex(shape);
    const Quat rotation =
        Quat(Eigen::AngleAxisf(3.0f * unit(random), Vec3(unit(random), unit(random), 1.0f).normalized()));
    // Stand the core's lowest point `expected` plus the radius above the plane, somewhere over its middle.
    const Vec3 lowest = rotation * convex.CoreSupport(rotation.conjugate() * -up);
    const float expected = gap(random);
    // A quarter of the feet on a corner of the grid and a quarter on an edge, where GJK decides.
    Vec3 foot(1.5f * unit(random), 0.0f, 1.5f * unit(random));
    if (i % 4 == 0) foot = Vec3(0.5f * std::round(2.0f * foot.x()), 0.0f, 0.5f * std::round(2.0f * foot.z()));
    if (i % 4 == 1) foot.x() = 0.5f * std::round(2.0f * foot.x());
    foot = tilt * foot;
    const Pose pose{foot + (expected + convex.core_radius()) * up - lowest, rotation};
    std::vector<ContactManifold> found;
    CollideConvexMesh(convex, pose, static_cast<const TriangleMeshShape&>(*mesh), Pose{}, 0.05f,
                      ContactManifold{}, found);
    ASSERT_FALSE(found.empty()) << "pose " << i;
    float deepest = kLargeFloat;
    for (const ContactManifold& manifold : found) {
      // GJK's stopping rule leaves a face-on pair's normal within a few degrees of the face's.
      EXPECT_GT(-manifold.normal.dot(up), 0.999f) << "pose " << i;
      for (int p = 0; p < manifold.count; ++p) deepest = std::min(deepest, manifold.points[p].separation);
    }
    EXPECT_NEAR(deepest, expected, 2e-5f) << "pose " << i;
  }
}

// Over a wavy mesh, the nearest contact is GJK's distance from the core to the nearest triangle less the
// radius, for every pose: standing over a triangle's inside is read right, and so is standing beside it.
TEST(RoundedShape, OverAWavyMeshTheDeepestContactIsTheNearestTrianglesDistance) {
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  WavyGround(vertices, triangles);
  const ShapeRef mesh = *TriangleMeshShape::Create(vertices, triangles);
  const auto& triangle_mesh = static_cast<const TriangleMeshShape&>(*mesh);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int near = 0;
  for (int i = 0; i < 800; ++i) {
    const ShapeRef shape = i % 2 == 0 ? Box(0.4f, 0.3f, 0.5f) : Pyramid();
    const ConvexShape& convex = Convex(shape);
    const Quat rotation(
        Eigen::AngleAxisf(3.0f * unit(random), Vec3(unit(random), unit(random), 1.0f).normalized()));
    const Vec3 at(5.0f * unit(random), 0.0f, 5.0f * unit(random));
    ShapeRayHit hit;
    ASSERT_TRUE(triangle_mesh.CastRay(at + Vec3(0, 5, 0), Vec3(0, -10, 0), 1.0f, hit));
    const float lowest = (rotation * convex.Support(rotation.conjugate() * -Vec3::UnitY())).y();
    const Pose pose{Vec3(at.x(), 5.0f - 10.0f * hit.fraction - lowest + 0.02f + 0.03f * unit(random), at.z()),
                    rotation};
    // The reference: GJK from the core to every triangle, less the radius.
    const PosedConvex core(convex, pose, true);
    float expected = kLargeFloat;
    bool cores_overlap = false;
    for (std::uint32_t t = 0; t < triangle_mesh.triangle_count(); ++t) {
      const TriangleSupport triangle(triangle_mesh.Vertex(t, 0), triangle_mesh.Vertex(t, 1),
                                     triangle_mesh.Vertex(t, 2));
      const GjkResult result = GjkClosestPoints(core, triangle, 1.0f);
      cores_overlap |= result.overlapping;
      expected = std::min(expected, result.distance - convex.core_radius());
    }
    if (cores_overlap || expected > 0.04f || expected < 0.001f) continue;  // a gap the mesh reports
    ++near;
    std::vector<ContactManifold> found;
    CollideConvexMesh(convex, pose, triangle_mesh, Pose{}, 0.05f, ContactManifold{}, found);
    float deepest = kLargeFloat;
    for (const ContactManifold& manifold : found)
      for (int p = 0; p < manifold.count; ++p) deepest = std::min(deepest, manifold.points[p].separation);
    EXPECT_NEAR(deepest, expected, 1e-4f) << "pose " << i;
  }
  EXPECT_GT(near, 200);
}

TEST(RoundedShape, ARoundedBoxRestsOnAMeshAndOnABoxAtItsHalfHeight) {
  for (const bool on_mesh : {true, false}) {
    PhysicsSettings settings;
    settings.allow_sleeping = false;
    auto world = MakeWorld(settings);
    if (on_mesh) {
      const std::vector<Vec3> vertices = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
      const std::vector<TriangleMeshShape::Indices> triangles = {{0, 2, 1}, {0, 3, 2}};
      Add(*world, Static(*TriangleMeshShape::Create(vertices, triangles), Vec3::Zero()));
    } else {
      Add(*world, Static(Box(5, 1, 5), Vec3(0, -1, 0)));
    }
    const BodyID box = Add(*world, Dynamic(Box(0.6f, 0.35f, 0.45f), Vec3(0.3f, 0.5f, -0.2f),
                                           Quat(Eigen::AngleAxisf(0.5f, Vec3::UnitY()))));
    StepFor(*world, 180);
    // Within the contact slop of touching, flat: the rounding does not lower a face.
    EXPECT_NEAR(Position(*world, box).y(), 0.35f, 2e-3f) << (on_mesh ? "mesh" : "box");
    const Vec3 up = *world->bodies().GetRotation(box) * Vec3::UnitY();
    EXPECT_GT(up.y(), 0.9999f);
  }
}

}  // namespace
}  // namespace strata::test
