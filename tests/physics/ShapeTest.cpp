// Shapes: mass properties, ray casts, hull building, mesh validation and BVH queries.
#include <random>

#include "TestWorld.h"

namespace strata::test {
namespace {

TEST(Shapes, BoxMassProperties) {
  const MassProperties box = Box(1, 2, 3)->ComputeMassProperties(10.0f);
  EXPECT_NEAR(box.mass, 10.0f * 48.0f, 1e-3f);
  EXPECT_NEAR(box.inertia(0, 0), box.mass / 12.0f * (16 + 36), 1e-2f);
  EXPECT_NEAR(box.inertia(1, 1), box.mass / 12.0f * (4 + 36), 1e-2f);
  EXPECT_NEAR(box.inertia(2, 2), box.mass / 12.0f * (4 + 16), 1e-2f);
}

TEST(Shapes, SphereAndCapsuleMassProperties) {
  const MassProperties sphere = Sphere(2)->ComputeMassProperties(1.0f);
  EXPECT_NEAR(sphere.mass, 4.0f / 3.0f * kPi * 8.0f, 1e-3f);
  EXPECT_NEAR(sphere.inertia(1, 1), 0.4f * sphere.mass * 4.0f, 1e-3f);
  // A capsule with no cylinder is a sphere.
  const MassProperties round = Capsule(0.0f, 2.0f)->ComputeMassProperties(1.0f);
  EXPECT_NEAR(round.mass, sphere.mass, 1e-3f);
  EXPECT_NEAR(round.inertia(0, 0), sphere.inertia(0, 0), 1e-2f);
  const MassProperties capsule = Capsule(1.0f, 0.5f)->ComputeMassProperties(1.0f);
  EXPECT_NEAR(capsule.mass, kPi * 0.25f * 2.0f + 4.0f / 3.0f * kPi * 0.125f, 1e-4f);
  EXPECT_LT(capsule.inertia(1, 1), capsule.inertia(0, 0));  // slender along Y
}

TEST(Shapes, HullOfCubeMatchesBox) {
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i)
    points.emplace_back(i & 1 ? 1.0f : -1.0f, i & 2 ? 2.0f : -2.0f, i & 4 ? 0.5f : -0.5f);
  points.emplace_back(0.1f, 0.2f, 0.0f);  // interior point must not become a vertex
  auto hull = ConvexHullShape::Create(points);
  ASSERT_TRUE(hull.ok()) << hull.error().message;
  const auto& convex = static_cast<const ConvexHullShape&>(**hull);
  EXPECT_EQ(convex.vertices().size(), 8u);
  EXPECT_EQ(convex.faces().size(), 6u);  // coplanar triangles merged into quads
  const MassProperties expected = Box(1, 2, 0.5f)->ComputeMassProperties(3.0f);
  const MassProperties actual = convex.ComputeMassProperties(3.0f);
  EXPECT_NEAR(actual.mass, expected.mass, 1e-3f * expected.mass);
  EXPECT_LT((actual.center_of_mass).norm(), 1e-4f);
  EXPECT_TRUE(actual.inertia.isApprox(expected.inertia, 1e-3f));
}

TEST(Shapes, HullOfOffsetTetrahedronHasItsCentroid) {
  const std::vector<Vec3> points = {Vec3(10, 0, 0), Vec3(11, 0, 0), Vec3(10, 1, 0), Vec3(10, 0, 1)};
  auto hull = ConvexHullShape::Create(points);
  ASSERT_TRUE(hull.ok());
  const MassProperties properties = (*hull)->ComputeMassProperties(6.0f);
  EXPECT_NEAR(properties.mass, 1.0f, 1e-4f);  // volume 1/6
  EXPECT_TRUE(properties.center_of_mass.isApprox(Vec3(10.25f, 0.25f, 0.25f), 1e-4f));
}

TEST(Shapes, DegenerateHullsAreRejected) {
  const std::vector<Vec3> coplanar = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1),
                                      Vec3(0.5f, 0, 0.5f)};
  const std::vector<Vec3> collinear = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  const std::vector<Vec3> coincident(5, Vec3(1, 1, 1));
  const std::vector<Vec3> too_few = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::vector<Vec3> with_nan = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, NAN)};
  for (const auto* points : {&coplanar, &collinear, &coincident, &too_few}) {
    auto hull = ConvexHullShape::Create(*points);
    ASSERT_FALSE(hull.ok());
    EXPECT_EQ(hull.error().code, ErrorCode::kDegenerateShape);
  }
  auto hull = ConvexHullShape::Create(with_nan);
  ASSERT_FALSE(hull.ok());
  EXPECT_EQ(hull.error().code, ErrorCode::kInvalidArgument);
}

TEST(Shapes, BadPrimitiveSizesAreRejected) {
  EXPECT_FALSE(SphereShape::Create(0.0f).ok());
  EXPECT_FALSE(SphereShape::Create(NAN).ok());
  EXPECT_FALSE(BoxShape::Create(Vec3(1, -1, 1)).ok());
  EXPECT_FALSE(CapsuleShape::Create(-1.0f, 1.0f).ok());
  EXPECT_FALSE(CapsuleShape::Create(1.0f, 0.0f).ok());
}

TEST(Shapes, RayCastsHitTheSurface) {
  ShapeRayHit hit;
  ASSERT_TRUE(Sphere(1)->CastRay(Vec3(-5, 0, 0), Vec3(10, 0, 0), 1.0f, hit));
  EXPECT_NEAR(hit.fraction, 0.4f, 1e-5f);
  EXPECT_TRUE(hit.normal.isApprox(Vec3(-1, 0, 0), 1e-5f));
  ASSERT_TRUE(Box(1, 2, 3)->CastRay(Vec3(0, 10, 0), Vec3(0, -20, 0), 1.0f, hit));
  EXPECT_NEAR(hit.fraction, 0.4f, 1e-5f);
  EXPECT_TRUE(hit.normal.isApprox(Vec3(0, 1, 0), 1e-5f));
  ASSERT_TRUE(Capsule(1, 0.5f)->CastRay(Vec3(0, 10, 0), Vec3(0, -10, 0), 1.0f, hit));
  EXPECT_NEAR(hit.fraction, 1.0f - 0.15f, 1e-5f);
  ASSERT_TRUE(Capsule(1, 0.5f)->CastRay(Vec3(5, 0.5f, 0), Vec3(-10, 0, 0), 1.0f, hit));
  EXPECT_NEAR(hit.fraction, 0.45f, 1e-5f);
  EXPECT_FALSE(Sphere(1)->CastRay(Vec3(-5, 2, 0), Vec3(10, 0, 0), 1.0f, hit));
  EXPECT_FALSE(Sphere(1)->CastRay(Vec3(-5, 0, 0), Vec3(10, 0, 0), 0.3f, hit));  // too short
  const std::vector<Vec3> tetra = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  ASSERT_TRUE((*ConvexHullShape::Create(tetra))->CastRay(Vec3(0.2f, 5, 0.2f), Vec3(0, -10, 0), 1.0f, hit));
  EXPECT_NEAR(hit.fraction, (5.0f - 0.6f) / 10.0f, 1e-5f);
}

ShapeRef Grid(int cells, float size, std::vector<Vec3>* vertices_out = nullptr) {
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  for (int z = 0; z <= cells; ++z)
    for (int x = 0; x <= cells; ++x)
      vertices.emplace_back(x * size, 0.05f * std::sin(x * 0.3f + z * 0.2f), z * size);
  for (int z = 0; z < cells; ++z) {
    for (int x = 0; x < cells; ++x) {
      const std::uint32_t i0 = z * (cells + 1) + x, i1 = i0 + 1, i2 = i0 + cells + 1, i3 = i2 + 1;
      triangles.push_back({i0, i2, i1});
      triangles.push_back({i1, i2, i3});
    }
  }
  if (vertices_out) *vertices_out = vertices;
  return *TriangleMeshShape::Create(vertices, triangles);
}

TEST(Shapes, MeshValidation) {
  const std::vector<Vec3> vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)};
  EXPECT_EQ(TriangleMeshShape::Create({}, {}).error().code, ErrorCode::kDegenerateShape);
  const std::vector<TriangleMeshShape::Indices> out_of_range = {{0, 1, 7}};
  EXPECT_EQ(TriangleMeshShape::Create(vertices, out_of_range).error().code, ErrorCode::kInvalidArgument);
  const std::vector<TriangleMeshShape::Indices> degenerate = {{0, 1, 1}};
  EXPECT_EQ(TriangleMeshShape::Create(vertices, degenerate).error().code, ErrorCode::kDegenerateShape);
  const std::vector<Vec3> with_nan = {Vec3(0, 0, 0), Vec3(1, NAN, 0), Vec3(0, 0, 1)};
  const std::vector<TriangleMeshShape::Indices> one = {{0, 1, 2}};
  EXPECT_EQ(TriangleMeshShape::Create(with_nan, one).error().code, ErrorCode::kInvalidArgument);
  const std::vector<TriangleMeshShape::Indices> mixed = {{0, 1, 1}, {0, 2, 1}};
  auto mesh = TriangleMeshShape::Create(vertices, mixed);
  ASSERT_TRUE(mesh.ok());
  EXPECT_EQ(static_cast<const TriangleMeshShape&>(**mesh).triangle_count(), 1u);  // degenerate one dropped
}

TEST(Shapes, MillionTriangleMeshQueriesMatchBruteForce) {
  const ShapeRef shape = Grid(708, 1.0f);  // 1,002,528 triangles
  const auto& mesh = static_cast<const TriangleMeshShape&>(*shape);
  ASSERT_GT(mesh.triangle_count(), 1000000u);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(0.0f, 708.0f);
  for (int query = 0; query < 20; ++query) {
    const Vec3 center(coordinate(random), 0.0f, coordinate(random));
    const AABB box = AABB::FromCenterHalfExtents(center, Vec3(2.0f, 1.0f, 3.0f));
    std::vector<std::uint32_t> found;
    mesh.QueryBox(box, found);
    std::sort(found.begin(), found.end());
    std::vector<std::uint32_t> expected;
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
      AABB bounds;
      for (int c = 0; c < 3; ++c) bounds.Encapsulate(mesh.Vertex(t, c));
      if (bounds.Overlaps(box)) expected.push_back(t);
    }
    EXPECT_EQ(found, expected);
    ShapeRayHit hit;
    ASSERT_TRUE(mesh.CastRay(center + Vec3(0, 10, 0), Vec3(0, -20, 0), 1.0f, hit));
    EXPECT_NEAR(hit.fraction, 0.5f, 0.01f);
    EXPECT_GT(hit.normal.y(), 0.99f);
  }
}

TEST(Shapes, MeshInternalEdgesAreInactiveAndBorderEdgesActive) {
  const ShapeRef shape = Grid(4, 1.0f);
  const auto& mesh = static_cast<const TriangleMeshShape&>(*shape);
  // Triangle 0 sits in the corner cell: its edge along the grid border is active, its diagonal is not.
  const std::uint8_t edges = mesh.ActiveEdges(0);
  EXPECT_NE(edges, 0);
  EXPECT_NE(edges, 0b111);
  int interior_active = 0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    bool on_border = false;
    for (int c = 0; c < 3; ++c) {
      const Vec3& v = mesh.Vertex(t, c);
      on_border |= v.x() == 0 || v.x() == 4 || v.z() == 0 || v.z() == 4;
    }
    if (!on_border) interior_active += mesh.ActiveEdges(t) != 0;
  }
  EXPECT_EQ(interior_active, 0);  // a nearly flat grid has no real edges inside
}

TEST(Shapes, TrianglesInsideABox) {
  std::vector<Triangle> triangles;
  Box(1, 1, 1)->GetTrianglesInBox(AABB(Vec3(-10, -10, -10), Vec3(10, 10, 10)),
                                  Pose{Vec3(5, 0, 0), Quat::Identity()}, triangles);
  ASSERT_EQ(triangles.size(), 12u);
  for (const Triangle& t : triangles)
    for (const Vec3& v : t.vertices) EXPECT_NEAR(std::abs(v.x() - 5.0f), 1.0f, 1.01f);
  triangles.clear();
  Box(1, 1, 1)->GetTrianglesInBox(AABB(Vec3(20, 20, 20), Vec3(30, 30, 30)), Pose{}, triangles);
  EXPECT_TRUE(triangles.empty());
  const ShapeRef grid = Grid(10, 1.0f);
  triangles.clear();
  grid->GetTrianglesInBox(AABB(Vec3(2.2f, -1, 2.2f), Vec3(3.8f, 1, 3.8f)), Pose{}, triangles);
  EXPECT_EQ(triangles.size(), 2u * 4u);  // cells (2..3) x (2..3), two triangles each
  triangles.clear();
  Sphere(1)->GetTrianglesInBox(AABB(Vec3(-2, -2, -2), Vec3(2, 2, 2)), Pose{}, triangles);
  EXPECT_GT(triangles.size(), 50u);
}

}  // namespace
}  // namespace strata::test
