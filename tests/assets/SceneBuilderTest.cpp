// SceneBuilder: a scene described in code and the same scene read from JSON make the same world; shapes are
// shared per hull, mesh or height field; a Scene made or changed in code that cannot be built is refused.
#include <gtest/gtest.h>

#include "assets/scene/SceneBuilder.h"
#include "assets/scene/SceneLoader.h"
#include "physics/body/BodyInterface.h"

namespace strata::test {
namespace {

// A floor, a kinematic paddle, a swinging bar on a hinge (limits and motor), a cart on a slider and a ball on
// a spring: the same scene in JSON and in code.
constexpr const char* kSceneJson = R"({
  "settings": {"gravity": [0, -9.81, 0], "substeps": 3, "sleeping": false},
  "bodies": [
    {"name": "floor", "shape": {"type": "box", "half_extents": [10, 0.5, 10]}, "position": [0, -0.5, 0],
     "motion": "static", "friction": 0.7},
    {"name": "paddle", "shape": {"type": "box", "half_extents": [1, 0.1, 0.2]}, "position": [3, 0.5, 0],
     "motion": "kinematic", "angular_velocity": [0, 2, 0]},
    {"name": "bar", "shape": {"type": "capsule", "radius": 0.1, "half_height": 0.5}, "position": [0, 2, 0],
     "linear_damping": 0.2, "mass": 2},
    {"name": "cart", "shape": {"type": "sphere", "radius": 0.3}, "position": [-2, 1, 0], "density": 500},
    {"name": "ball", "shape": {"type": "sphere", "radius": 0.2}, "position": [2, 3, 0], "restitution": 0.4}],
  "constraints": [
    {"type": "hinge", "body_b": "bar", "anchor": [0, 2.5, 0], "axis": [0, 0, 1], "limits": [-60, 60],
     "motor": {"speed": 1.5, "max_torque": 4}},
    {"type": "slider", "body_b": "cart", "anchor": [-2, 1, 0], "axis": [1, 0, 0], "limits": [-1, 1],
     "max_friction_force": 0.5},
    {"type": "distance", "body_b": "ball", "anchor_a": [2, 4, 0], "anchor_b": [2, 3, 0],
     "spring_hertz": 2, "spring_damping_ratio": 0.3, "min_distance": 0.5, "max_distance": 2}]})";

SceneDescription SceneInCode() {
  SceneDescription scene;
  scene.substeps = 3;
  const auto body = [&](SceneShape shape, const Vec3& position, SceneMotion motion) -> BodyDescription& {
    BodyDescription& added = scene.bodies.emplace_back();
    added.shape = shape, added.position = position, added.motion = motion;
    added.friction = BodyCreationSettings().friction;
    return added;
  };
  body(SceneShape::kBox, Vec3(0, -0.5f, 0), SceneMotion::kStatic).half_extents = Vec3(10, 0.5f, 10);
  scene.bodies.back().friction = 0.7f;
  BodyDescription& paddle = body(SceneShape::kBox, Vec3(3, 0.5f, 0), SceneMotion::kKinematic);
  paddle.half_extents = Vec3(1, 0.1f, 0.2f), paddle.angular_velocity = Vec3(0, 2, 0);
  BodyDescription& bar = body(SceneShape::kCapsule, Vec3(0, 2, 0), SceneMotion::kDynamic);
  bar.radius = 0.1f, bar.half_height = 0.5f, bar.linear_damping = 0.2f, bar.mass = 2.0f;
  body(SceneShape::kSphere, Vec3(-2, 1, 0), SceneMotion::kDynamic).radius = 0.3f;
  scene.bodies.back().density = 500.0f;
  BodyDescription& ball = body(SceneShape::kSphere, Vec3(2, 3, 0), SceneMotion::kDynamic);
  ball.radius = 0.2f, ball.restitution = 0.4f;
  constexpr float kDegree = kPi / 180.0f;
  JointDescription& hinge = scene.joints.emplace_back();
  hinge.kind = JointKind::kHinge, hinge.body_b = 2, hinge.anchor = Vec3(0, 2.5f, 0),
  hinge.axis = Vec3::UnitZ();
  hinge.normal = Vec3::Zero(), hinge.limits = true, hinge.min_limit = -60 * kDegree,
  hinge.max_limit = 60 * kDegree;
  hinge.motor = true, hinge.motor_speed = 1.5f, hinge.motor_max = 4.0f;
  JointDescription& slider = scene.joints.emplace_back();
  slider.kind = JointKind::kSlider, slider.body_b = 3, slider.anchor = Vec3(-2, 1, 0),
  slider.axis = Vec3::UnitX();
  slider.limits = true, slider.min_limit = -1.0f, slider.max_limit = 1.0f, slider.max_friction = 0.5f;
  JointDescription& spring = scene.joints.emplace_back();
  spring.kind = JointKind::kDistance, spring.body_b = 4, spring.anchor = Vec3(2, 4, 0),
  spring.anchor_b = Vec3(2, 3, 0);
  spring.spring_hertz = 2.0f, spring.spring_damping_ratio = 0.3f, spring.min_distance = 0.5f,
  spring.max_distance = 2.0f;
  return scene;
}

std::vector<Vec3> PositionsAfterTwoSeconds(const Scene& scene) {
  Result<SceneWorld> world = BuildSceneWorld(scene);
  EXPECT_TRUE(world.ok()) << world.error().message;
  if (!world) return {};
  for (int step = 0; step < 120; ++step) EXPECT_TRUE(world->system->Step(scene.description.dt).ok());
  std::vector<Vec3> positions;
  for (BodyID id : world->ids) positions.push_back(*world->system->bodies().GetPosition(id));
  return positions;
}

TEST(SceneBuilder, ASceneInCodeAndTheSameSceneInJsonMakeTheSameWorld) {
  Result<Scene> loaded = ParseScene(kSceneJson, "inline", ".");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  Scene written;
  written.description = SceneInCode();
  Result<std::vector<ShapeRef>> shapes = MakeShapes(written.description);
  ASSERT_TRUE(shapes.ok()) << shapes.error().message;
  written.shapes = std::move(*shapes);
  const std::vector<Vec3> from_json = PositionsAfterTwoSeconds(*loaded);
  const std::vector<Vec3> from_code = PositionsAfterTwoSeconds(written);
  ASSERT_EQ(from_json.size(), 5u);
  ASSERT_EQ(from_code.size(), 5u);
  for (std::size_t i = 0; i < from_json.size(); ++i) EXPECT_EQ(from_json[i], from_code[i]) << "body " << i;
  // The joints held: the cart stayed within its slider's limits and on its axis, the bar on its hinge.
  EXPECT_LE(std::abs(from_json[3].x() + 2.0f), 1.01f);
  EXPECT_NEAR(from_json[3].y(), 1.0f, 0.01f);
  EXPECT_NEAR((from_json[2] - Vec3(0, 2.5f, 0)).norm(), 0.5f, 0.02f);
}

TEST(SceneBuilder, BodiesOfOneHullMeshOrHeightFieldShareOneShape) {
  SceneDescription scene;
  scene.hulls.push_back({{Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)}});
  scene.hulls.push_back({{Vec3(0, 2, 0), Vec3(2, 0, 0), Vec3(-2, 0, 0), Vec3(0, 0, 2), Vec3(0, 0, -2)}});
  for (std::uint32_t geometry : {0u, 1u, 0u}) {
    BodyDescription& body = scene.bodies.emplace_back();
    body.shape = SceneShape::kHull, body.geometry = geometry;
  }
  scene.bodies.emplace_back().shape = SceneShape::kSphere;
  scene.bodies.emplace_back().shape = SceneShape::kSphere;
  Result<std::vector<ShapeRef>> shapes = MakeShapes(scene);
  ASSERT_TRUE(shapes.ok()) << shapes.error().message;
  ASSERT_EQ(shapes->size(), 5u);
  EXPECT_EQ((*shapes)[0], (*shapes)[2]);
  EXPECT_NE((*shapes)[0], (*shapes)[1]);
  EXPECT_GT((*shapes)[1]->LocalBounds().max.y(), 1.5f);
  EXPECT_NE((*shapes)[3], (*shapes)[4]);  // primitives are each their own
}

TEST(SceneBuilder, AGeometryPastTheListIsAnErrorNamingTheBody) {
  SceneDescription scene;
  scene.bodies.emplace_back().shape = SceneShape::kSphere;
  BodyDescription& terrain = scene.bodies.emplace_back();
  terrain.shape = SceneShape::kHeightField, terrain.geometry = 2, terrain.motion = SceneMotion::kStatic;
  Result<std::vector<ShapeRef>> shapes = MakeShapes(scene);
  ASSERT_FALSE(shapes.ok());
  EXPECT_EQ(shapes.error().message, "body 1: height field 2 is not in the scene (it has 0)");
}

TEST(SceneBuilder, BodySettingsKeepStrataDefaultsForUnsetTunings) {
  BodyDescription body;
  body.shape = SceneShape::kSphere;
  const BodyCreationSettings defaults = ToBodySettings(body, *MakeShape({}, body));
  EXPECT_EQ(defaults.linear_damping, BodyCreationSettings().linear_damping);
  EXPECT_EQ(defaults.max_angular_velocity, BodyCreationSettings().max_angular_velocity);
  EXPECT_EQ(defaults.density, BodyCreationSettings().density);
  EXPECT_FALSE(defaults.mass.has_value());
  EXPECT_EQ(defaults.object_layer, layers::kMoving);
  body.angular_damping = 0.0f, body.gravity_factor = 0.5f, body.linear_cast = true;
  body.motion = SceneMotion::kStatic, body.sensor = true;
  const BodyCreationSettings set = ToBodySettings(body, *MakeShape({}, body));
  EXPECT_EQ(set.angular_damping, 0.0f);
  EXPECT_EQ(set.gravity_factor, 0.5f);
  EXPECT_EQ(set.motion_quality, MotionQuality::kLinearCast);
  EXPECT_EQ(set.motion_type, MotionType::kStatic);
  EXPECT_EQ(set.object_layer, layers::kMoving);  // a static sensor still pairs with the static level
}

TEST(SceneBuilder, ASceneThatCannotBeBuiltIsRefusedWhole) {
  Result<Scene> scene = ParseScene(kSceneJson, "inline", ".");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  Scene missing_shape = *scene;
  missing_shape.shapes.pop_back();
  Result<SceneWorld> refused = BuildSceneWorld(missing_shape);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message, "the scene has 4 shapes for 5 bodies");
  Scene stray_joint = *scene;
  stray_joint.description.joints[1].body_b = 9;
  refused = BuildSceneWorld(stray_joint);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message, "/constraints/1: names a body the scene does not have (it has 5)");
}

}  // namespace
}  // namespace strata::test
