// HeightFieldShape: it is the triangles of the same mesh (corners, normals, internal edges, box queries, ray
// hits), bodies rest and roll on it as on that mesh, holes let things through, and bad grids are refused.
#include <algorithm>
#include <random>

#include "TestWorld.h"

namespace strata::test {
namespace {

constexpr std::uint32_t kColumns = 13, kRows = 9;
constexpr float kCell = 1.5f;

const HeightFieldShape& AsField(const ShapeRef& shape) {
  return static_cast<const HeightFieldShape&>(*shape);
}
const TriangleMeshShape& AsMesh(const ShapeRef& shape) {
  return static_cast<const TriangleMeshShape&>(*shape);
}

TEST(HeightField, IsTheTrianglesOfTheSameMesh) {
  const ShapeRef field_shape = HeightField(kColumns, kRows, kCell, RollingHeights(kColumns, kRows, kCell));
  const HeightFieldShape& field = AsField(field_shape);
  const ShapeRef mesh_shape = MeshOf(field);
  const TriangleMeshShape& mesh = AsMesh(mesh_shape);
  ASSERT_EQ(field.triangle_count(), mesh.triangle_count());
  EXPECT_EQ(field.triangle_count(), 2u * (kColumns - 1) * (kRows - 1));
  int internal = 0;
  for (std::uint32_t t = 0; t < field.triangle_count(); ++t) {
    for (int corner = 0; corner < 3; ++corner)
      EXPECT_EQ(field.Vertex(t, corner), mesh.Vertex(t, corner)) << t;
    EXPECT_EQ(field.Normal(t), mesh.Normal(t)) << t;
    EXPECT_EQ(field.ActiveEdges(t), mesh.ActiveEdges(t)) << t;
    internal += field.ActiveEdges(t) != 0b111;
  }
  EXPECT_GT(internal, 0);  // the bumps leave flat and concave edges inside, which must not be real
  EXPECT_TRUE(field.LocalBounds().min.isApprox(mesh.LocalBounds().min));
  EXPECT_TRUE(field.LocalBounds().max.isApprox(mesh.LocalBounds().max));

  std::mt19937 random(7);
  std::uniform_real_distribution<float> across(-3.0f, 21.0f), up(-1.0f, 3.0f), size(0.0f, 4.0f);
  for (int k = 0; k < 200; ++k) {
    const Vec3 corner(across(random), up(random), across(random));
    const AABB box{corner, corner + Vec3(size(random), size(random), size(random))};
    std::vector<std::uint32_t> from_field, from_mesh;
    field.QueryBox(box, from_field);
    mesh.QueryBox(box, from_mesh);
    std::sort(from_field.begin(), from_field.end());
    std::sort(from_mesh.begin(), from_mesh.end());
    EXPECT_EQ(from_field, from_mesh) << "box " << k;
  }
  // Rays from above, slanted, nearly flat (across many cells), from below and from outside the grid.
  int hits = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 origin(across(random), 4.0f * up(random), across(random));
    const Vec3 direction =
        Vec3(across(random) - origin.x(), up(random) - origin.y(), across(random) - origin.z());
    ShapeRayHit on_field, on_mesh;
    const bool field_hit = field.CastRay(origin, direction, 1.0f, on_field);
    ASSERT_EQ(field_hit, mesh.CastRay(origin, direction, 1.0f, on_mesh)) << "ray " << k;
    if (!field_hit) continue;
    ++hits;
    EXPECT_EQ(on_field.sub_shape, on_mesh.sub_shape) << "ray " << k;
    EXPECT_EQ(on_field.fraction, on_mesh.fraction) << "ray " << k;
    EXPECT_EQ(on_field.normal, on_mesh.normal) << "ray " << k;
  }
  EXPECT_GT(hits, 50);
}

TEST(HeightField, BodiesRestAndRollAsOnTheSameMesh) {
  const ShapeRef field = HeightField(kColumns, kRows, kCell, RollingHeights(kColumns, kRows, kCell));
  const ShapeRef mesh = MeshOf(AsField(field));
  std::vector<Vec3> ends[2];
  for (const ShapeRef& ground : {field, mesh}) {
    auto world = MakeWorld();
    BodyCreationSettings terrain = Static(ground, Vec3(-9, 0, -6));
    terrain.friction = 0.6f;
    Add(*world, terrain);
    // A ball rolls down the slope; another lands on a grid corner, where six triangles touch it at once
    // (their contacts merge in triangle order, not in the order a query found them); a box on a gentle part
    // stays; a capsule lands across a bump.
    std::vector<BodyID> bodies;
    bodies.push_back(Add(*world, Dynamic(Sphere(0.4f), Vec3(-6.4f, 2.5f, 0.35f))));
    bodies.push_back(Add(*world, Dynamic(Sphere(0.4f), Vec3(-6.0f, 2.5f, -3.0f))));
    BodyCreationSettings box = Dynamic(Box(0.4f, 0.4f, 0.4f), Vec3(-8.2f, 2.0f, -4.1f));
    box.friction = 0.9f;
    bodies.push_back(Add(*world, box));
    bodies.push_back(Add(*world, Dynamic(Capsule(0.5f, 0.25f), Vec3(0.4f, 2.5f, 2.3f),
                                         Quat(Eigen::AngleAxisf(kPi / 2, Vec3::UnitX())))));
    StepFor(*world, 120);
    for (const BodyID id : bodies) ends[ground == field ? 0 : 1].push_back(Position(*world, id));
  }
  ASSERT_EQ(ends[0].size(), ends[1].size());
  // The same triangles in the same order: the same contacts, bit for bit.
  for (std::size_t b = 0; b < ends[0].size(); ++b) {
    EXPECT_EQ(ends[0][b], ends[1][b]) << "body " << b;
    EXPECT_GT(ends[0][b].y(), -2.0f) << "body " << b << " fell through";  // the lowest ground is about -1
  }
  EXPECT_GT(ends[0][0].x(), -5.9f);  // the ball rolled down the slope (+x)
}

TEST(HeightField, HolesLetThingsThrough) {
  constexpr std::uint32_t kSide = 9;
  std::vector<float> heights(kSide * kSide, 0.0f);
  heights[4 * kSide + 4] = HeightFieldShape::kHole;  // the four cells around sample (4, 4): x, z in 3..5 m
  const ShapeRef shape = HeightField(kSide, kSide, 1.0f, heights);
  const HeightFieldShape& field = AsField(shape);
  EXPECT_TRUE(field.IsHole(3, 3) && field.IsHole(4, 4) && !field.IsHole(2, 3));
  ShapeRayHit hit;
  EXPECT_FALSE(field.CastRay(Vec3(4.2f, 1, 3.7f), Vec3(0, -2, 0), 1.0f, hit));
  ASSERT_TRUE(field.CastRay(Vec3(1.5f, 1, 1.5f), Vec3(0, -2, 0), 1.0f, hit));
  EXPECT_NEAR(hit.fraction, 0.5f, 1e-6f);
  std::vector<std::uint32_t> triangles;
  field.QueryBox(AABB(Vec3(3.2f, -1, 3.2f), Vec3(4.8f, 1, 4.8f)), triangles);
  EXPECT_TRUE(triangles.empty());

  auto world = MakeWorld();
  Add(*world, Static(shape, Vec3::Zero()));
  const BodyID over_hole = Add(*world, Dynamic(Box(0.3f, 0.3f, 0.3f), Vec3(4.0f, 1.0f, 4.0f)));
  const BodyID beside = Add(*world, Dynamic(Box(0.3f, 0.3f, 0.3f), Vec3(1.5f, 1.0f, 6.5f)));
  StepFor(*world, 90);
  EXPECT_LT(Position(*world, over_hole).y(), -2.0f);
  EXPECT_NEAR(Position(*world, beside).y(), 0.3f, 0.02f);
}

TEST(HeightField, BadGridsAreRefusedWithTheReason) {
  const std::vector<float> four(4, 0.0f);
  auto expect_error = [](const Result<ShapeRef>& made, ErrorCode code, const std::string& words) {
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().code, code);
    EXPECT_NE(made.error().message.find(words), std::string::npos) << made.error().message;
  };
  expect_error(HeightFieldShape::Create(1, 4, 1.0f, four), ErrorCode::kInvalidArgument, "1 x 4");
  expect_error(HeightFieldShape::Create(2, 3, 1.0f, four), ErrorCode::kInvalidArgument, "got 4 heights");
  for (const float cell :
       {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()})
    expect_error(HeightFieldShape::Create(2, 2, cell, four), ErrorCode::kInvalidArgument, "cell size");
  std::vector<float> spiked = four;
  spiked[3] = std::numeric_limits<float>::infinity();
  expect_error(HeightFieldShape::Create(2, 2, 1.0f, spiked), ErrorCode::kInvalidArgument, "column 1, row 1");
  std::vector<float> towering = four;
  towering[2] = 2e7f;
  expect_error(HeightFieldShape::Create(2, 2, 1.0f, towering), ErrorCode::kInvalidArgument,
               "column 0, row 1");
  expect_error(HeightFieldShape::Create(2, 2, 3e7f, four), ErrorCode::kInvalidArgument, "spans");
  const std::vector<float> holes(9, HeightFieldShape::kHole);
  expect_error(HeightFieldShape::Create(3, 3, 1.0f, holes), ErrorCode::kDegenerateShape, "hole");
  // Refused before anything the size of the grid is read or allocated.
  expect_error(HeightFieldShape::Create(100000, 100000, 1.0f, four), ErrorCode::kInvalidArgument,
               "100000 x 100000");
  // It is level geometry: no dynamic body may use it.
  BodyCreationSettings dynamic = Dynamic(HeightField(2, 2, 1.0f, four), Vec3::Zero());
  auto world = MakeWorld();
  EXPECT_FALSE(world->bodies().CreateAndAddBody(dynamic).ok());
}

}  // namespace
}  // namespace strata::test
