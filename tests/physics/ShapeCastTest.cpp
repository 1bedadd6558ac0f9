// Shape casts against analytic answers and a brute-force sweep, point and closest-point queries, and the
// filters every query shares (sensors left out, bad input refused).
#include <random>

#include "TestWorld.h"
#include "physics/narrowphase/CollideShapes.h"
#include "physics/narrowphase/Gjk.h"
#include "physics/narrowphase/ShapeSweep.h"

namespace strata::test {
namespace {

constexpr float kTolerance = 1e-4f;

ShapeRef Hull() {
  const std::vector<Vec3> points = {{0.5f, 0, 0},         {-0.4f, 0.1f, 0.3f}, {0, 0.6f, -0.2f},
                                    {0.1f, -0.5f, -0.4f}, {0.2f, 0.2f, 0.5f},  {-0.3f, -0.3f, -0.3f},
                                    {-0.2f, 0.4f, 0.3f}};
  return *ConvexHullShape::Create(points);
}

ShapeRef FloorMesh(float half, float height) {
  const std::vector<Vec3> vertices = {
      {-half, height, -half}, {half, height, -half}, {half, height, half}, {-half, height, half}};
  const std::vector<TriangleMeshShape::Indices> triangles = {{0, 2, 1}, {0, 3, 2}};
  return *TriangleMeshShape::Create(vertices, triangles);
}

// A flat height field at `height` over [0, 20] x [0, 20], or the slope y = slope * x.
ShapeRef Terrain(float height, float slope) {
  std::vector<float> heights;
  for (int r = 0; r < 21; ++r)
    for (int c = 0; c < 21; ++c) heights.push_back(height + slope * static_cast<float>(c));
  return HeightField(21, 21, 1.0f, heights);
}

std::optional<SweepContact> Sweep(const ShapeRef& shape, const Pose& start, const Vec3& displacement,
                                  const ShapeRef& target, const Pose& target_pose,
                                  const ShapeCastSettings& settings = {}) {
  CollisionScratch scratch;
  return SweepConvexShape(static_cast<const ConvexShape&>(*shape), start, displacement, *target, target_pose,
                          settings, scratch);
}

// The fraction a contact `gap` metres short of touching reports: within the tolerance of `exact`.
void ExpectFraction(const std::optional<SweepContact>& hit, float exact, float length) {
  ASSERT_TRUE(hit.has_value());
  EXPECT_LE(hit->fraction, exact + 1e-5f);
  EXPECT_GE(hit->fraction, exact - 1.5f * kTolerance / length);
}

TEST(ShapeCast, SphereAtABoxFaceAndEdge) {
  const ShapeRef box = SharpBox(1, 1, 1), sphere = Sphere(0.5f);
  const auto face = Sweep(sphere, Pose{{-5, 0, 0}, Quat::Identity()}, {10, 0, 0}, box, Pose{});
  ExpectFraction(face, 0.35f, 10.0f);
  EXPECT_NEAR(face->normal.x(), -1.0f, 1e-4f);
  EXPECT_NEAR(face->point.x(), -1.0f, 1e-3f);
  EXPECT_EQ(face->penetration, 0.0f);
  // Passing 0.2 m over the top: the sphere meets the top edge, where |centre - edge| = 0.5.
  const auto edge = Sweep(sphere, Pose{{-5, 1.2f, 0}, Quat::Identity()}, {10, 0, 0}, box, Pose{});
  const float reach = std::sqrt(0.25f - 0.04f);
  ExpectFraction(edge, (5.0f - 1.0f - reach) / 10.0f, 10.0f);
  EXPECT_NEAR(edge->normal.x(), -reach / 0.5f, 1e-3f);
  EXPECT_NEAR(edge->normal.y(), 0.2f / 0.5f, 1e-3f);
  EXPECT_NEAR(edge->point.y(), 1.0f, 1e-3f);
  // 0.6 m over the top it passes.
  EXPECT_FALSE(Sweep(sphere, Pose{{-5, 1.6f, 0}, Quat::Identity()}, {10, 0, 0}, box, Pose{}).has_value());
  // Short of the box.
  EXPECT_FALSE(Sweep(sphere, Pose{{-5, 0, 0}, Quat::Identity()}, {3, 0, 0}, box, Pose{}).has_value());
}

// An upright capsule 0.4 mm above a box's top face and 8.4 mm out past its edge: the narrow phase's rounded
// box tilts the contact normal there and reads an overlap, yet the shapes never touch sliding over the face,
// and moving down they meet where the capsule's cap reaches the edge.
TEST(ShapeCast, CapsuleJustClearOfABoxEdgeIsNoStartContact) {
  const ShapeRef capsule = Capsule(0.6f, 0.3f), box = SharpBox(2, 1, 0.7f);
  const Pose box_pose{{1.0f, -1.9004f, 0.7084f}, Quat::Identity()};
  const Pose start{Vec3::Zero(), Quat::Identity()};
  EXPECT_FALSE(Sweep(capsule, start, {0, 0, 1}, box, box_pose).has_value());
  const float drop = 0.3004f - std::sqrt(0.09f - 0.0084f * 0.0084f);
  const auto down = Sweep(capsule, start, {0, -0.01f, 0}, box, box_pose);
  ExpectFraction(down, drop / 0.01f, 0.01f);
  EXPECT_EQ(down->penetration, 0.0f);
  // Far from the origin the same.
  const Vec3 far(928.5f, 4.5f, 77.5f);
  EXPECT_FALSE(Sweep(capsule, Pose{far, Quat::Identity()}, {0, 0, 1}, box,
                     Pose{far + box_pose.position, Quat::Identity()})
                   .has_value());
}

TEST(ShapeCast, BoxAtABoxStraightAndTurned) {
  const ShapeRef target = SharpBox(1, 1, 1), box = SharpBox(0.5f, 0.5f, 0.5f);
  ExpectFraction(Sweep(box, Pose{{-5, 0, 0}, Quat::Identity()}, {10, 0, 0}, target, Pose{}), 0.35f, 10.0f);
  // Turned 45 degrees about y it reaches sqrt(2) / 2 ahead of its centre, corner first onto the face.
  const Quat turned(Eigen::AngleAxisf(kPi / 4, Vec3::UnitY()));
  const auto corner = Sweep(box, Pose{{-5, 0.2f, 0.1f}, turned}, {10, 0, 0}, target, Pose{});
  ExpectFraction(corner, (5.0f - 1.0f - 0.5f * std::sqrt(2.0f)) / 10.0f, 10.0f);
  EXPECT_NEAR(corner->normal.x(), -1.0f, 1e-3f);
  // The target turned instead: its edge comes out to sqrt(2).
  const auto edge =
      Sweep(box, Pose{{-5, 0, 0}, Quat::Identity()}, {10, 0, 0}, target, Pose{{0, 0, 0}, turned});
  ExpectFraction(edge, (5.0f - std::sqrt(2.0f) - 0.5f) / 10.0f, 10.0f);
}

TEST(ShapeCast, CapsuleAtAMeshAndAtAHeightField) {
  const ShapeRef capsule = Capsule(0.5f, 0.3f);
  const ShapeRef floor = FloorMesh(10, 0);
  // Upright, its lowest point 0.8 m below its centre.
  const auto upright = Sweep(capsule, Pose{{1, 3, 2}, Quat::Identity()}, {0, -5, 0}, floor, Pose{});
  ExpectFraction(upright, 2.2f / 5.0f, 5.0f);
  EXPECT_NEAR(upright->normal.y(), 1.0f, 1e-4f);
  EXPECT_NEAR(upright->point.y(), 0.0f, 1e-3f);
  // Lying down, 0.3 m.
  const Quat lying(Eigen::AngleAxisf(kPi / 2, Vec3::UnitZ()));
  ExpectFraction(Sweep(capsule, Pose{{1, 3, 2}, lying}, {0, -5, 0}, floor, Pose{}), 2.7f / 5.0f, 5.0f);
  // From below, the mesh's back: it passes, unless back faces count.
  EXPECT_FALSE(Sweep(capsule, Pose{{1, -3, 2}, Quat::Identity()}, {0, 5, 0}, floor, Pose{}).has_value());
  ShapeCastSettings back;
  back.back_faces = true;
  ExpectFraction(Sweep(capsule, Pose{{1, -3, 2}, Quat::Identity()}, {0, 5, 0}, floor, Pose{}, back),
                 2.2f / 5.0f, 5.0f);
  // The same on a height field at 1 m, placed 100 m out.
  const ShapeRef flat = Terrain(1, 0);
  const Pose far{{100, 0, -50}, Quat::Identity()};
  ExpectFraction(Sweep(capsule, Pose{{105, 4, -45}, Quat::Identity()}, {0, -5, 0}, flat, far), 2.2f / 5.0f,
                 5.0f);
  // On the slope y = x / 2 the capsule's lower cap meets the plane when its core's end is r above it.
  const ShapeRef slope = Terrain(0, 0.5f);
  const auto sloped = Sweep(capsule, Pose{{6, 8, 5}, Quat::Identity()}, {0, -8, 0}, slope, Pose{});
  const float resting_centre = 0.5f * 6 + 0.3f * std::sqrt(1.25f) + 0.5f;
  ExpectFraction(sloped, (8 - resting_centre) / 8.0f, 8.0f);
  EXPECT_NEAR(sloped->normal.x(), -0.5f / std::sqrt(1.25f), 1e-3f);
  EXPECT_NEAR(sloped->normal.y(), 1.0f / std::sqrt(1.25f), 1e-3f);
}

TEST(ShapeCast, StartOverlapsReportTheirPenetration) {
  const ShapeRef box = Box(1, 1, 1), sphere = Sphere(0.5f);
  const Pose inside{{-1.2f, 0, 0}, Quat::Identity()};
  const auto overlap = Sweep(sphere, inside, {-3, 0, 0}, box, Pose{});
  ASSERT_TRUE(overlap.has_value());
  EXPECT_EQ(overlap->fraction, 0.0f);
  EXPECT_NEAR(overlap->penetration, 0.3f, 1e-4f);
  EXPECT_NEAR(overlap->normal.x(), -1.0f, 1e-4f);
  // Moving out of it is free when the settings say so; moving in is not.
  ShapeCastSettings moving_out;
  moving_out.ignore_overlaps_moving_out = true;
  EXPECT_FALSE(Sweep(sphere, inside, {-3, 0, 0}, box, Pose{}, moving_out).has_value());
  const auto deeper = Sweep(sphere, inside, {3, 0, 0}, box, Pose{}, moving_out);
  ASSERT_TRUE(deeper.has_value());
  EXPECT_EQ(deeper->fraction, 0.0f);
  // A capsule sunk 0.1 m into a mesh floor.
  const auto sunk =
      Sweep(Capsule(0.5f, 0.3f), Pose{{0, 0.7f, 0}, Quat::Identity()}, {1, 0, 0}, FloorMesh(10, 0), Pose{});
  ASSERT_TRUE(sunk.has_value());
  EXPECT_EQ(sunk->fraction, 0.0f);
  EXPECT_NEAR(sunk->penetration, 0.1f, 1e-3f);
  EXPECT_NEAR(sunk->normal.y(), 1.0f, 1e-3f);
}

// The deepest overlap of two shapes as the narrow phase's contacts see it (0 when apart or touching).
float Overlap(const ShapeRef& shape, const Pose& pose, const ShapeRef& target, const Pose& target_pose) {
  std::vector<ContactManifold> manifolds;
  CollideShapes(*shape, pose, *target, target_pose, 0.0f, ContactManifold{}, manifolds);
  float deepest = 0.0f;
  for (const ContactManifold& manifold : manifolds) deepest = std::max(deepest, -manifold.MinSeparation());
  return deepest;
}

// The distance between two shapes (GJK on spheres and capsules as core and radius, on the other shapes as
// they are), a shape made of triangles by its nearest triangle; 0 when they overlap.
float Distance(const ShapeRef& shape, const Pose& pose, const ShapeRef& target, const Pose& target_pose) {
  const MeasuredConvex a(static_cast<const ConvexShape&>(*shape), pose);
  const auto gap = [&](const ConvexSupport& b, float radius) {
    const GjkResult closest = GjkClosestPoints(a.support, b, 10.0f);
    return closest.overlapping ? 0.0f : std::max(0.0f, closest.distance - a.radius - radius);
  };
  if (target->IsConvex()) {
    const MeasuredConvex b(static_cast<const ConvexShape&>(*target), target_pose);
    return gap(b.support, b.radius);
  }
  std::vector<Triangle> triangles;
  target->GetTrianglesInBox(shape->WorldBounds(pose).Expanded(1.0f), target_pose, triangles);
  float nearest = 10.0f;
  for (const Triangle& t : triangles)
    nearest = std::min(nearest, gap(TriangleSupport(t.vertices[0], t.vertices[1], t.vertices[2]), 0.0f));
  return nearest;
}

TEST(ShapeCast, AgreesWithABruteForceSweepOnTenThousandRandomCasts) {
  std::mt19937 random(2024);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), centred(-1.0f, 1.0f);
  const auto random_rotation = [&] {
    return Quat(Eigen::AngleAxisf(6.2832f * unit(random),
                                  Vec3(centred(random), centred(random), centred(random)).normalized()));
  };
  const std::vector<ShapeRef> casts = {Sphere(0.4f), Box(0.3f, 0.5f, 0.2f), Capsule(0.4f, 0.25f), Hull()};
  const std::vector<ShapeRef> targets = {Sphere(0.8f), Box(1, 0.6f, 0.8f), Capsule(0.6f, 0.5f),
                                         Hull(),       FloorMesh(3, 0),    Terrain(0, 0.3f)};
  constexpr int kCasts = 10000, kSamples = 64;
  int hits = 0, overlaps = 0;
  for (int i = 0; i < kCasts; ++i) {
    const ShapeRef& shape = casts[static_cast<std::size_t>(i) % casts.size()];
    const std::size_t target_index = (static_cast<std::size_t>(i) / casts.size()) % targets.size();
    const ShapeRef& target = targets[target_index];
    const bool terrain = target_index >= 4;  // starts above it, so every cast meets its front
    const Pose target_pose{terrain ? Vec3(-3, 0, -3) : Vec3::Zero(),
                           terrain ? Quat::Identity() : random_rotation()};
    Vec3 start = 3.0f * Vec3(centred(random), centred(random), centred(random));
    if (terrain) start.y() = 1.5f + 2.0f * unit(random) + (target_index == 5 ? 0.3f * (start.x() + 3) : 0.0f);
    const Pose pose{start, random_rotation()};
    // Aimed near the target's middle (a third pass by it), 2 to 8 m long.
    const Vec3 aim =
        (terrain ? Vec3(start.x() + centred(random), 0, start.z() + centred(random)) : Vec3::Zero()) +
        Vec3(centred(random), centred(random), centred(random));
    const Vec3 displacement = (aim - start).normalized() * (2.0f + 6.0f * unit(random));
    const std::optional<SweepContact> hit = Sweep(shape, pose, displacement, target, target_pose);
    const auto at = [&](float t) { return Pose{start + t * displacement, pose.rotation}; };
    // Overlapping by more than the narrow phase's rounding, as its contacts and GJK both see it (each alone
    // misjudges some near touches by a few millimetres).
    const auto overlap_at = [&](float t) {
      return Distance(shape, at(t), target, target_pose) > 0.0f ? 0.0f
                                                                : Overlap(shape, at(t), target, target_pose);
    };
    constexpr float kMargin = 2e-3f;  // the narrow phase's own rounding near touching
    // Brute force: the first of kSamples evenly spaced positions where the shapes overlap.
    int first_overlap = -1;
    for (int k = 0; k <= kSamples && first_overlap < 0; ++k)
      if (overlap_at(static_cast<float>(k) / kSamples) > kMargin) first_overlap = k;
    if (!hit) {
      EXPECT_LT(first_overlap, 0) << "cast " << i << ": missed an overlap at t = " << first_overlap << "/64";
      continue;
    }
    ++hits;
    overlaps += hit->fraction == 0.0f && hit->penetration > 0.0f;
    // Touching where it says (or already overlapping), and overlapping nowhere before it.
    if (hit->penetration == 0.0f) {
      EXPECT_LT(Distance(shape, at(hit->fraction), target, target_pose), kTolerance + 1e-5f) << "cast " << i;
    } else {
      EXPECT_NEAR(overlap_at(0.0f), hit->penetration, kMargin) << "cast " << i;
    }
    for (int k = 0; static_cast<float>(k) / kSamples < hit->fraction - 1e-3f; ++k)
      EXPECT_LT(overlap_at(static_cast<float>(k) / kSamples), kMargin) << "cast " << i << " sample " << k;
    if (first_overlap >= 0) {
      EXPECT_LE(hit->fraction, static_cast<float>(first_overlap) / kSamples) << "cast " << i;
    }
  }
  // Enough of each outcome to mean something.
  EXPECT_GT(hits, kCasts / 4);
  EXPECT_LT(hits, kCasts - kCasts / 10);
  EXPECT_GT(overlaps, 100);
}

TEST(ShapeCast, WorldCastFindsTheNearestBodyAllHitsAndSkipsSensors) {
  auto world = MakeWorld();
  const BodyID floor = Add(*world, Static(FloorMesh(20, 0), Vec3::Zero()));
  const BodyID near_box = Add(*world, Static(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 3)));
  const BodyID far_box = Add(*world, Static(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 6)));
  BodyCreationSettings trigger = Static(Box(1, 1, 1), Vec3(0, 1, 1.5f));
  trigger.is_sensor = true;
  trigger.object_layer = layers::kMoving;
  const BodyID sensor = Add(*world, trigger);
  const ShapeRef sphere = Sphere(0.4f);
  const Pose start{{0, 0.5f, 0}, Quat::Identity()};
  const auto first = world->query().CastShape(*sphere, start, Vec3(0, 0, 10));
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(first->has_value());
  EXPECT_EQ((*first)->body, near_box);
  EXPECT_NEAR((*first)->fraction, (3.0f - 0.5f - 0.4f) / 10.0f, 1e-4f);
  // All: the two boxes; the floor 0.1 m below is never touched and the sensor is left out.
  const auto all = world->query().CastShapeAll(*sphere, start, Vec3(0, 0, 10));
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), 2u);
  EXPECT_EQ((*all)[0].body, near_box);
  EXPECT_EQ((*all)[1].body, far_box);
  // Asked for, the sensor comes first; cast down, the floor.
  QueryFilter with_sensors;
  with_sensors.sensors = true;
  EXPECT_EQ((**world->query().CastShape(*sphere, start, Vec3(0, 0, 10), {}, with_sensors)).body, sensor);
  EXPECT_EQ((**world->query().CastShape(*sphere, start, Vec3(0, -1, 0))).body, floor);
  // Bad input: a mesh to cast, a NaN, a bad tolerance; nothing changes.
  EXPECT_FALSE(world->query().CastShape(*FloorMesh(1, 0), start, Vec3(1, 0, 0)).ok());
  EXPECT_FALSE(world->query().CastShape(*sphere, start, Vec3(NAN, 0, 0)).ok());
  ShapeCastSettings bad;
  bad.tolerance = 0.0f;
  EXPECT_FALSE(world->query().CastShapeAll(*sphere, start, Vec3(1, 0, 0), bad).ok());
}

TEST(PointQueries, CollidePointFindsSolidsClosedMeshesAndBelowTerrain) {
  auto world = MakeWorld();
  const BodyID box = Add(*world, Static(Box(1, 1, 1), Vec3(0, 1, 0)));
  const BodyID ball = Add(*world, Dynamic(Sphere(0.5f), Vec3(5, 5, 0)));
  const BodyID terrain = Add(*world, Static(Terrain(0, 0.5f), Vec3(-30, 0, -10)));
  // A closed mesh: the box [10, 12]^3 as triangles.
  std::vector<Triangle> faces;
  Box(1, 1, 1)->GetTrianglesInBox(AABB(Vec3::Constant(-2), Vec3::Constant(2)), Pose{}, faces);
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  for (const Triangle& face : faces) {
    const auto first = static_cast<std::uint32_t>(vertices.size());
    for (const Vec3& v : face.vertices) vertices.push_back(v);
    triangles.push_back({first, first + 1, first + 2});
  }
  const BodyID closed =
      Add(*world, Static(*TriangleMeshShape::Create(vertices, triangles), Vec3(11, 11, 11)));
  const auto at = [&](const Vec3& point) { return *world->query().CollidePoint(point); };
  EXPECT_EQ(at({0.5f, 1.5f, -0.9f}), std::vector<BodyID>{box});
  EXPECT_EQ(at({5.2f, 5.2f, 0.2f}), std::vector<BodyID>{ball});
  EXPECT_TRUE(at({5.4f, 5.4f, 0.2f}).empty());
  EXPECT_EQ(at({11.3f, 10.2f, 11.9f}), std::vector<BodyID>{closed});
  EXPECT_TRUE(at({12.3f, 10.2f, 11.9f}).empty());
  // The slope y = (x + 30) / 2: below it is inside.
  EXPECT_EQ(at({-25.3f, 2.0f, -3.7f}), std::vector<BodyID>{terrain});
  EXPECT_TRUE(at({-25.3f, 2.9f, -3.7f}).empty());
  EXPECT_FALSE(world->query().CollidePoint(Vec3(INFINITY, 0, 0)).ok());
}

TEST(PointQueries, ClosestPointToShapesAndPoints) {
  auto world = MakeWorld();
  const BodyID box = Add(*world, Static(Box(1, 1, 1), Vec3(0, 1, 0)));
  const BodyID floor = Add(*world, Static(FloorMesh(20, -0.5f), Vec3::Zero()));
  const auto near_box = *world->query().ClosestPoint(Vec3(3, 1.5f, 0), 5.0f);
  ASSERT_TRUE(near_box.has_value());
  EXPECT_EQ(near_box->body, box);
  EXPECT_NEAR(near_box->distance, 2.0f, 1e-4f);
  EXPECT_NEAR(near_box->point_on_body.x(), 1.0f, 1e-4f);
  EXPECT_NEAR(near_box->normal.x(), 1.0f, 1e-4f);
  // A sphere above the floor's far end, away from the box: the floor, 1.5 m - 0.5 m below.
  const auto over_floor =
      *world->query().ClosestPoint(*Sphere(0.5f), Pose{{15, 1.5f, 15}, Quat::Identity()}, 3.0f);
  ASSERT_TRUE(over_floor.has_value());
  EXPECT_EQ(over_floor->body, floor);
  EXPECT_NEAR(over_floor->distance, 1.5f, 1e-3f);
  EXPECT_NEAR(over_floor->point_on_query.y(), 1.0f, 1e-3f);
  // Out of reach: nothing. Inside: distance 0.
  EXPECT_FALSE(world->query().ClosestPoint(Vec3(15, 5, 15), 1.0f)->has_value());
  EXPECT_EQ((**world->query().ClosestPoint(Vec3(0, 1, 0), 1.0f)).distance, 0.0f);
  EXPECT_FALSE(world->query().ClosestPoint(Vec3(0, 1, 0), -1.0f).ok());
}

}  // namespace
}  // namespace strata::test
