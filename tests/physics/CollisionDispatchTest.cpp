// The narrow phase's dispatch table: every pair of built-in shapes (the height field too) has a way to
// collide and every target a cast, either order of a pair gives the same contact turned round, a shape added
// by kind gets GJK, casts and the triangle shapes at once, a step's reach (ContactReach) makes contacts only
// along the way the shapes close, and a kinematic mesh (the owner of its pairs, so A) carries boxes.
#include <algorithm>
#include <array>
#include <string>

#include "TestWorld.h"
#include "physics/narrowphase/CollisionDispatch.h"

namespace strata::test {
namespace {

const ConvexShape& Convex(const ShapeRef& shape) {
  return static_cast<const ConvexShape&>(*shape);
}

ShapeRef Hull() {
  const std::vector<Vec3> corners = {
      {-0.4f, -0.4f, -0.4f}, {0.4f, -0.4f, -0.4f}, {0.0f, -0.4f, 0.5f}, {0.0f, 0.5f, 0.0f}};
  return *ConvexHullShape::Create(corners);
}

ShapeRef Ground(float half_size) {
  // Two triangles, front faces up.
  const std::vector<Vec3> vertices = {{-half_size, 0, -half_size},
                                      {half_size, 0, -half_size},
                                      {half_size, 0, half_size},
                                      {-half_size, 0, half_size}};
  const std::vector<TriangleMeshShape::Indices> triangles = {{0, 2, 1}, {0, 3, 2}};
  return *TriangleMeshShape::Create(vertices, triangles);
}

ShapeRef Terrain(float half_size) {
  // Flat, 2 m cells, its surface at y = 0 across [-half_size, half_size] once placed at (-half_size, 0,
  // -half_size).
  const auto samples = static_cast<std::uint32_t>(half_size) + 1;
  return *HeightFieldShape::Create(samples, samples, 2.0f, std::vector<float>(samples * samples, 0.0f));
}

// One shape of every built-in type, each centred so that it reaches about 0.5 m from its reference point (the
// terrain's reference point is its corner).
std::vector<ShapeRef> EveryShape() {
  return {Sphere(0.5f), Box(0.5f, 0.5f, 0.5f), Capsule(0.3f, 0.3f), Hull(), Ground(5.0f), Terrain(5.0f)};
}

// Where a shape is placed so that its top (or surface) is where the others expect it.
Vec3 Origin(const Shape& shape) {
  return shape.type() == ShapeType::kHeightField ? Vec3(-5.0f, 0.0f, -5.0f) : Vec3::Zero();
}

std::vector<ContactManifold> Contacts(const ShapeRef& a, const Pose& pose_a, const ShapeRef& b,
                                      const Pose& pose_b) {
  ContactManifold prototype;
  prototype.body_a = BodyID{1, 1};
  prototype.body_b = BodyID{2, 1};
  std::vector<ContactManifold> out;
  CollisionScratch scratch;
  CollisionDispatch::Default().Collide(*a, pose_a, *b, pose_b, ContactReach{0.02f}, prototype, out, scratch);
  return out;
}

TEST(CollisionDispatch, EveryBuiltInPairCollidesExceptTwoMeshesAndEveryTargetHasACast) {
  const CollisionDispatch& table = CollisionDispatch::Default();
  const std::array types = {ShapeType::kSphere,     ShapeType::kBox,          ShapeType::kCapsule,
                            ShapeType::kConvexHull, ShapeType::kTriangleMesh, ShapeType::kHeightField};
  auto made_of_triangles = [](ShapeType type) {
    return type == ShapeType::kTriangleMesh || type == ShapeType::kHeightField;
  };
  for (const ShapeType a : types)
    for (const ShapeType b : types)
      EXPECT_EQ(table.Collides(a, b), !made_of_triangles(a) || !made_of_triangles(b))
          << ToString(a) << " vs " << ToString(b);
  // A sphere swept down onto each type of target 2 m below it touches about 1.5 m down.
  const ShapeRef ball = Sphere(0.25f);
  std::vector<Triangle> scratch;
  for (const ShapeRef& target : EveryShape()) {
    const std::optional<ShapeCastHit> hit =
        table.Cast(Convex(ball), Pose{Vec3(0, 2, 0), Quat::Identity()}, Vec3(0, -3, 0), *target,
                   Pose{Origin(*target) + Vec3(0, -0.5f, 0), Quat::Identity()}, 1e-3f, scratch);
    ASSERT_TRUE(hit.has_value()) << ToString(target->type());
    EXPECT_GT(hit->normal.y(), 0.7f) << ToString(target->type());
    EXPECT_GT(hit->fraction, 0.3f) << ToString(target->type());
    EXPECT_LT(hit->fraction, 0.9f) << ToString(target->type());
  }
}

// Where `a` and `b` touch: B sunk a little into A's top, both a little turned; a mesh lies flat under the
// convex shape, whichever of the two it is.
void Place(const Shape& a, const Shape& b, Pose& pose_a, Pose& pose_b) {
  if (a.IsConvex() && b.IsConvex()) {
    pose_a = {Vec3(0.05f, 0.0f, -0.03f), Quat(Eigen::AngleAxisf(0.2f, Vec3::UnitY()))};
    pose_b = {Vec3(0.0f, 0.8f, 0.0f), Quat(Eigen::AngleAxisf(0.1f, Vec3::UnitZ()))};
    return;
  }
  const Shape& convex = a.IsConvex() ? a : b;
  const Shape& ground = a.IsConvex() ? b : a;
  const Pose flat{Origin(ground), Quat::Identity()};
  const Pose above{Vec3(0.1f, -convex.LocalBounds().min.y() - 0.01f, 0.2f), Quat::Identity()};
  pose_a = a.IsConvex() ? above : flat;
  pose_b = a.IsConvex() ? flat : above;
}

TEST(CollisionDispatch, EitherOrderOfAPairGivesTheSameContactTurnedRound) {
  const std::vector<ShapeRef> shapes = EveryShape();
  int pairs = 0;
  for (const ShapeRef& a : shapes)
    for (const ShapeRef& b : shapes) {
      if (!a->IsConvex() && !b->IsConvex()) continue;
      Pose place_a, place_b;
      Place(*a, *b, place_a, place_b);
      const std::vector<ContactManifold> forward = Contacts(a, place_a, b, place_b);
      const std::vector<ContactManifold> backward = Contacts(b, place_b, a, place_a);
      SCOPED_TRACE(std::string(ToString(a->type())) + " vs " + ToString(b->type()));
      ASSERT_FALSE(forward.empty());
      ASSERT_EQ(forward.size(), backward.size());
      for (std::size_t m = 0; m < forward.size(); ++m) {
        EXPECT_EQ(forward[m].body_a, (BodyID{1, 1}));
        EXPECT_EQ(backward[m].body_a, (BodyID{1, 1}));
        EXPECT_EQ(forward[m].sub_shape_a, backward[m].sub_shape_b);
        EXPECT_EQ(forward[m].sub_shape_b, backward[m].sub_shape_a);
        EXPECT_TRUE(forward[m].normal.isApprox(-backward[m].normal, 2e-3f));
        EXPECT_NEAR(forward[m].MinSeparation(), backward[m].MinSeparation(), 2e-3f);
        // Each point of one order is a point of the other with its sides swapped.
        for (int i = 0; i < forward[m].count; ++i) {
          const ContactPoint& p = forward[m].points[i];
          const bool found = std::any_of(backward[m].points, backward[m].points + backward[m].count,
                                         [&](const ContactPoint& q) {
                                           return (p.position_a - q.position_b).norm() < 2e-3f &&
                                                  (p.position_b - q.position_a).norm() < 2e-3f;
                                         });
          EXPECT_TRUE(found) << "point " << i;
        }
      }
      ++pairs;
    }
  EXPECT_EQ(pairs, 32);  // 6 x 6 less the four pairs of two triangle shapes
}

TEST(CollisionDispatch, AMeshAsAHasItsTriangleOnItsOwnSide) {
  const std::vector<ContactManifold> contacts =
      Contacts(Ground(5.0f), Pose{}, Box(0.5f, 0.5f, 0.5f), Pose{Vec3(1.0f, 0.49f, 2.0f), Quat::Identity()});
  ASSERT_FALSE(contacts.empty());
  for (const ContactManifold& manifold : contacts) {
    EXPECT_GT(manifold.normal.y(), 0.999f);  // from the ground (A) up to the box (B)
    EXPECT_LE(manifold.sub_shape_a, 1u);
    EXPECT_EQ(manifold.sub_shape_b, 0u);
    for (int i = 0; i < manifold.count; ++i) {
      EXPECT_NEAR(manifold.points[i].position_a.y(), 0.0f, 1e-4f);    // on the ground
      EXPECT_NEAR(manifold.points[i].position_b.y(), -0.01f, 1e-4f);  // on the box's bottom
    }
  }
}

// Counts its calls and reports one contact whose normal tells which way round it was called.
int g_calls = 0;
void MarkedContact(const Shape& a, const Pose& pose_a, const Shape& /*b*/, const Pose& pose_b,
                   const ContactReach& /*reach*/, const ContactManifold& prototype,
                   std::vector<ContactManifold>& out, CollisionScratch& /*scratch*/) {
  ++g_calls;
  ContactManifold manifold = prototype;
  manifold.normal = a.type() == ShapeType::kCapsule ? Vec3::UnitX() : Vec3::UnitZ();
  manifold.sub_shape_b = 7;
  manifold.count = 1;
  manifold.points[0] = {pose_a.position, pose_b.position, -0.1f};
  out.push_back(manifold);
}

TEST(CollisionDispatch, AShapeAddedByKindGetsEveryPairAndARegisteredPairServesBothOrders) {
  CollisionDispatch table;
  table.AddConvexShape(ShapeType::kBox);
  table.AddTriangleShape(ShapeType::kTriangleMesh, CollideConvexWithMesh, CastOntoTriangles,
                         SweepOntoTriangleShape<TriangleMeshShape>);
  EXPECT_FALSE(table.Collides(ShapeType::kCapsule, ShapeType::kBox));
  // The one line a new convex shape needs: GJK against the convex shapes before it, and the mesh's function.
  table.AddConvexShape(ShapeType::kCapsule);
  EXPECT_TRUE(table.Collides(ShapeType::kCapsule, ShapeType::kBox));
  EXPECT_TRUE(table.Collides(ShapeType::kBox, ShapeType::kCapsule));
  EXPECT_TRUE(table.Collides(ShapeType::kCapsule, ShapeType::kTriangleMesh));
  EXPECT_TRUE(table.Collides(ShapeType::kTriangleMesh, ShapeType::kCapsule));
  EXPECT_FALSE(table.Collides(ShapeType::kTriangleMesh, ShapeType::kTriangleMesh));
  const ShapeRef capsule = Capsule(0.5f, 0.25f), box = Box(0.5f, 0.5f, 0.5f), ground = Ground(5.0f);
  const Pose resting{Vec3(0, 0.26f, 0), Quat(Eigen::AngleAxisf(kPi / 2, Vec3::UnitZ()))};
  ContactManifold prototype;
  prototype.body_a = BodyID{1, 1};
  prototype.body_b = BodyID{2, 1};
  std::vector<ContactManifold> out;
  CollisionScratch scratch;
  table.Collide(*capsule, resting, *ground, Pose{}, ContactReach{0.02f}, prototype, out, scratch);
  ASSERT_FALSE(out.empty());
  EXPECT_LT(out.front().normal.y(), -0.999f);
  std::vector<Triangle> triangles;
  EXPECT_TRUE(table
                  .Cast(Convex(box), Pose{Vec3(0, 3, 0), Quat::Identity()}, Vec3(0, -4, 0), *capsule, resting,
                        1e-3f, triangles)
                  .has_value());

  // A faster form for (capsule, box) serves (box, capsule) too, called the registered way round and its
  // contact turned round; the pair order it was given is kept in the body ids and sub-shapes.
  table.RegisterCollide(ShapeType::kCapsule, ShapeType::kBox, MarkedContact);
  g_calls = 0;
  out.clear();
  const Pose at_capsule{Vec3(1, 0, 0), Quat::Identity()}, at_box{Vec3(0, 2, 0), Quat::Identity()};
  table.Collide(*capsule, at_capsule, *box, at_box, ContactReach{0.02f}, prototype, out, scratch);
  table.Collide(*box, at_box, *capsule, at_capsule, ContactReach{0.02f}, prototype, out, scratch);
  EXPECT_EQ(g_calls, 2);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].normal, Vec3::UnitX());
  EXPECT_EQ(out[0].sub_shape_b, 7u);
  EXPECT_EQ(out[0].points[0].position_a, at_capsule.position);
  EXPECT_EQ(out[1].normal, -Vec3::UnitX());  // the capsule was A of the call: turned round
  EXPECT_EQ(out[1].body_a, (BodyID{1, 1}));
  EXPECT_EQ(out[1].body_b, (BodyID{2, 1}));
  EXPECT_EQ(out[1].sub_shape_a, 7u);
  EXPECT_EQ(out[1].sub_shape_b, 0u);
  EXPECT_EQ(out[1].points[0].position_a, at_box.position);
  EXPECT_EQ(out[1].points[0].position_b, at_capsule.position);
  // A form registered for the reverse pair itself takes its place there, and only there.
  table.RegisterCollide(ShapeType::kBox, ShapeType::kCapsule, CollideConvexByGjk);
  g_calls = 0;
  out.clear();
  table.Collide(*box, at_box, *capsule, at_capsule, ContactReach{0.02f}, prototype, out, scratch);
  table.Collide(*capsule, at_capsule, *box, at_box, ContactReach{0.02f}, prototype, out, scratch);
  EXPECT_EQ(g_calls, 1);
}

// What Collide finds with a step's reach: `travel` is B's motion relative to A over the step.
std::vector<ContactManifold> ContactsWithin(const ShapeRef& a, const Pose& pose_a, const ShapeRef& b,
                                            const Pose& pose_b, const Vec3& travel) {
  std::vector<ContactManifold> out;
  CollisionScratch scratch;
  CollisionDispatch::Default().Collide(*a, pose_a, *b, pose_b, ContactReach{0.02f, travel}, ContactManifold{},
                                       out, scratch);
  return out;
}

TEST(CollisionDispatch, AStepsReachRunsAlongTheWayTheShapesCloseAndNoFurtherAnywhereElse) {
  // Each convex shape 0.1 to 0.3 m above each kind of floor (top at y = 0), in both orders of the pair.
  const std::vector<ShapeRef> floors = {Box(5.0f, 0.5f, 5.0f), Ground(5.0f), Terrain(5.0f)};
  const std::vector<Vec3> floor_origins = {Vec3(0.0f, -0.5f, 0.0f), Vec3::Zero(), Vec3(-5.0f, 0.0f, -5.0f)};
  const std::vector<ShapeRef> movers = {Sphere(0.5f), Box(0.5f, 0.5f, 0.5f), Capsule(0.3f, 0.3f), Hull()};
  const Pose above{Vec3(0.0f, 0.7f, 0.0f), Quat::Identity()};
  const float closing = 0.35f;  // further than any of the gaps
  for (std::size_t f = 0; f < floors.size(); ++f) {
    const Pose floor_pose{floor_origins[f], Quat::Identity()};
    for (const ShapeRef& mover : movers) {
      const std::string which = std::string(ToString(mover->type())) + " over " + ToString(floors[f]->type());
      // Falling onto the floor: the floor comes up towards the shape by more than the gap.
      const auto falling = ContactsWithin(mover, above, floors[f], floor_pose, Vec3(0.0f, closing, 0.0f));
      ASSERT_FALSE(falling.empty()) << which;
      for (const ContactManifold& manifold : falling) {
        EXPECT_LT(manifold.normal.y(), -0.99f) << which;
        EXPECT_GT(manifold.MinSeparation(), 0.05f) << which;
        EXPECT_LT(manifold.MinSeparation(), closing) << which;
      }
      // The same pair the other way round: the shape comes down towards the floor.
      const auto turned = ContactsWithin(floors[f], floor_pose, mover, above, Vec3(0.0f, -closing, 0.0f));
      ASSERT_EQ(turned.size(), falling.size()) << which;
      EXPECT_GT(turned[0].normal.y(), 0.99f) << which;
      // Rising away or sliding sideways, it closes nothing along the normal: only the 2 cm all round, which
      // the gap exceeds.
      for (const Vec3& travel :
           {Vec3(0.0f, -closing, 0.0f), Vec3(closing, 0.0f, 0.0f), Vec3(0.0f, 0.0f, -closing)})
        EXPECT_TRUE(ContactsWithin(mover, above, floors[f], floor_pose, travel).empty())
            << which << ", travel " << travel.transpose();
    }
  }
}

TEST(CollisionDispatch, AMeshWallIsReachedOnlyWhenAShapeTravelsTowardsIt) {
  // A wall of two triangles facing -x, 0.3 m beyond a box's side: further than the box's bounds reach.
  const std::vector<Vec3> vertices = {
      {0.6f, -2.0f, -2.0f}, {0.6f, 2.0f, -2.0f}, {0.6f, 2.0f, 2.0f}, {0.6f, -2.0f, 2.0f}};
  const std::vector<TriangleMeshShape::Indices> triangles = {{0, 2, 1}, {0, 3, 2}};
  const ShapeRef wall = *TriangleMeshShape::Create(vertices, triangles);
  const ShapeRef box = Box(0.3f, 0.3f, 0.3f);
  const Pose origin{Vec3::Zero(), Quat::Identity()};
  // The box moves 0.4 m towards the wall over the step: the wall comes 0.4 m closer in the box's frame.
  const auto towards = ContactsWithin(box, origin, wall, Pose{}, Vec3(-0.4f, 0.0f, 0.0f));
  ASSERT_EQ(towards.size(), 1u);
  EXPECT_GT(towards[0].normal.x(), 0.999f);
  EXPECT_NEAR(towards[0].MinSeparation(), 0.3f, 1e-3f);
  // Moving away, or along the wall, the box cannot reach it this step.
  EXPECT_TRUE(ContactsWithin(box, origin, wall, Pose{}, Vec3(0.4f, 0.0f, 0.0f)).empty());
  EXPECT_TRUE(ContactsWithin(box, origin, wall, Pose{}, Vec3(0.0f, 0.4f, 0.0f)).empty());
  // A reach as a query gives it, the same all round, finds the wall whichever way: 0.4 m in every direction.
  std::vector<ContactManifold> all_round;
  CollideShapes(*box, origin, *wall, Pose{}, 0.4f, ContactManifold{}, all_round);
  EXPECT_EQ(all_round.size(), 1u);
}

TEST(CollisionDispatch, AKinematicMeshPlatformCarriesABoxItOwnsThePairOf) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  // The platform is active, so it is A of its pair with the box (the owner finds the pair).
  BodyCreationSettings platform;
  platform.shape = Ground(4.0f);
  platform.motion_type = MotionType::kKinematic;
  platform.object_layer = layers::kMoving;
  platform.linear_velocity = Vec3(0.0f, 0.5f, 0.0f);
  const BodyID lift = Add(*world, platform);
  const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0.0f, 0.5f, 0.0f)));
  StepFor(*world, 120);  // two seconds up at 0.5 m/s
  const float top = Position(*world, lift).y();
  EXPECT_NEAR(top, 1.0f, 1e-3f);
  // Carried up, resting on the platform (not sunk through it, not thrown off).
  EXPECT_NEAR(Position(*world, box).y(), top + 0.5f, 0.02f);
  EXPECT_NEAR(Velocity(*world, box).y(), 0.5f, 0.05f);
  EXPECT_LT(std::abs(Position(*world, box).x()) + std::abs(Position(*world, box).z()), 0.01f);
}

}  // namespace
}  // namespace strata::test
