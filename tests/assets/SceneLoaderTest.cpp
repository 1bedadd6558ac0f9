// Scene files: the bundled scenes load and simulate; bad files give one clear error naming the JSON path.
#include <gtest/gtest.h>

#include <fstream>

#include <stb/stb_image_write.h>
#include "assets/scene/SceneBuilder.h"
#include "assets/scene/SceneLoader.h"
#include "physics/body/BodyInterface.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/shapes/ConvexShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/TriangleMeshShape.h"
#include "tests/TempPath.h"

namespace strata::test {
namespace {

const std::filesystem::path kScenes = STRATA_SCENES_DIR;

// The settings Strata makes for body `index` of a loaded scene.
BodyCreationSettings Built(const Scene& scene, std::size_t index) {
  return ToBodySettings(scene.description.bodies[index], scene.shapes[index]);
}

std::string ParseError(const std::string& text) {
  Result<Scene> scene = ParseScene(text, "test.json", kScenes);
  EXPECT_FALSE(scene.ok());
  return scene.ok() ? "" : scene.error().message;
}

TEST(SceneLoader, BundledScenesLoadAndRun) {
  for (const char* name : {"playground.json", "stack.json", "bounce.json", "terrain.json", "joints.json"}) {
    Result<Scene> scene = LoadScene(kScenes / name);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    Result<SceneWorld> world = BuildSceneWorld(*scene);
    ASSERT_TRUE(world.ok()) << world.error().message;
    EXPECT_EQ(world->ids.size(), scene->description.bodies.size());
    for (int step = 0; step < 120; ++step) ASSERT_TRUE(world->system->Step(scene->description.dt).ok());
  }
}

TEST(SceneLoader, JointsHoldTheirBodiesAndTheLampCordBreaks) {
  Result<Scene> scene = LoadScene(kScenes / "joints.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->description.joints.size(), 9u);
  Result<SceneWorld> world = BuildSceneWorld(*scene);
  ASSERT_TRUE(world.ok()) << world.error().message;
  ASSERT_EQ(world->constraint_ids.size(), 9u);
  for (int step = 0; step < 180; ++step) ASSERT_TRUE(world->system->Step(scene->description.dt).ok());
  auto index_of = [&](const std::string& name) {
    for (std::size_t i = 0; i < scene->description.joints.size(); ++i)
      if (scene->description.joints[i].name == name) return i;
    ADD_FAILURE() << name;
    return std::size_t{0};
  };
  ConstraintManager& joints = world->system->constraints();
  // The 10 kg lamp weighs 98 N, its cord gives at 80 N; everything else holds.
  for (std::size_t i = 0; i < scene->description.joints.size(); ++i)
    EXPECT_EQ(*joints.IsBroken(world->constraint_ids[i]), scene->description.joints[i].name == "lamp_cord")
        << scene->description.joints[i].name;
  // The chain's top joint carries three links and the 30 kg weight as they swing: about their 33 g.
  const float top = joints.GetForces(world->constraint_ids[index_of("chain_top")])->force.norm();
  EXPECT_GT(top, 0.5f * 33.0f * 9.81f);
  EXPECT_LT(top, 2.0f * 33.0f * 9.81f);
  // The motor turns the wheel at its speed; the rail's carriage stops at its limit.
  BodyInterface& bodies = world->system->bodies();
  EXPECT_NEAR(bodies.GetAngularVelocity(world->ids[8])->y(), 2.0f, 0.05f);
  EXPECT_NEAR(bodies.GetPosition(world->ids[9])->x(), 4.0f, 0.01f);
}

TEST(SceneLoader, BadJointsNameTheirJsonPath) {
  const std::string bodies = R"("bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}},
                                           {"name": "wall", "shape": {"type": "box", "half_extents": [1, 1, 1]},
                                            "motion": "static"}])";
  auto error = [&](const std::string& constraints) {
    return ParseError("{" + bodies + R"(, "constraints": [)" + constraints + "]}");
  };
  EXPECT_NE(error(R"({"type": "point", "body_b": "nobody"})").find("/constraints/0/body_b: no body is named"),
            std::string::npos);
  EXPECT_NE(error(R"({"type": "rope", "body_b": "a"})").find("/constraints/0/type"), std::string::npos);
  EXPECT_NE(error(R"({"type": "point", "body_b": "wall"})").find("at least one dynamic body"),
            std::string::npos);
  EXPECT_NE(error(R"({"type": "point", "body_b": "a", "axis": [0, 1, 0]})")
                .find("/constraints/0/axis: unknown key"),
            std::string::npos);
  EXPECT_NE(error(R"({"type": "hinge", "body_b": "a", "limits": [30, 60]})").find("/constraints/0/limits"),
            std::string::npos);
  EXPECT_NE(error(R"({"type": "hinge", "body_b": "a", "axis": [0, 0, 0]})").find("/constraints/0"),
            std::string::npos);
  EXPECT_NE(error(R"({"type": "distance", "body_b": "a", "anchor_b": [0, 2, 0], "min_distance": 3,
                      "max_distance": 1})")
                .find("min_distance"),
            std::string::npos);
  EXPECT_NE(error(R"({"type": "point", "body_b": "a", "max_force": -5})").find("max_force"),
            std::string::npos);
  EXPECT_NE(
      error(R"({"type": "point", "body_b": "a", "anchor": [1e300, 0, 0]})").find("/constraints/0/anchor"),
      std::string::npos);
  EXPECT_NE(error(R"({"type": "point", "body_b": "a"}, {"type": "point", "body_b": "a", "body_a": "a"})")
                .find("/constraints/1/body_b"),
            std::string::npos);
  EXPECT_NE(ParseError("{" + bodies + R"(, "constraints": {}})").find("/constraints: must be an array"),
            std::string::npos);
}

TEST(SceneLoader, FieldsAreRead) {
  Result<Scene> scene =
      ParseScene(R"({"settings": {"gravity": [0, -5, 0], "dt": 0.01, "velocity_iterations": 7,
      "substeps": 6, "relax_iterations": 3, "restitution_iterations": 2, "gyroscopic_torque": false, "sleeping": false,
      "exact_small_islands": false, "sleep_rule": "point_movement", "sleep_point_velocity": 0.02},
      "bodies": [{"name": "a", "shape": {"type": "capsule", "radius": 0.5, "half_height": 1},
                  "position": [1, 2, 3], "rotation": [0, 0, 1, 0], "motion": "kinematic", "friction": 0.9,
                  "restitution": 0.3, "linear_velocity": [1, 0, 0], "max_linear_velocity": 40,
                  "max_angular_velocity": 9},
                 {"name": "b", "shape": {"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,0,1]], "indices": [0, 2, 1]},
                  "motion": "static"},
                 {"shape": {"type": "sphere", "radius": 1}, "mass": 3, "report_contacts": true},
                 {"name": "trigger", "shape": {"type": "box", "half_extents": [1, 1, 1]}, "motion": "static",
                  "sensor": true, "sensor_detects_static": true}]})",
                 "inline", kScenes);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const PhysicsSettings physics = ToPhysicsSettings(scene->description);
  EXPECT_FLOAT_EQ(physics.gravity.y(), -5.0f);
  EXPECT_FLOAT_EQ(scene->description.dt, 0.01f);
  EXPECT_EQ(physics.velocity_iterations, 7);
  EXPECT_EQ(physics.substeps, 6);
  EXPECT_EQ(physics.relax_iterations, 3);
  EXPECT_EQ(physics.restitution_iterations, 2);
  EXPECT_FALSE(physics.gyroscopic_torque);
  EXPECT_FALSE(physics.allow_sleeping);
  EXPECT_FALSE(physics.exact_small_islands);
  EXPECT_EQ(physics.sleep_rule, SleepRule::kPointMovement);
  EXPECT_FLOAT_EQ(physics.sleep_point_velocity, 0.02f);
  ASSERT_EQ(scene->description.bodies.size(), 4u);
  ASSERT_EQ(scene->shapes.size(), 4u);
  const BodyCreationSettings a = Built(*scene, 0);
  EXPECT_EQ(a.motion_type, MotionType::kKinematic);
  EXPECT_EQ(a.shape->type(), ShapeType::kCapsule);
  EXPECT_TRUE(a.position.isApprox(Vec3(1, 2, 3)));
  EXPECT_FLOAT_EQ(a.friction, 0.9f);
  EXPECT_FLOAT_EQ(a.restitution, 0.3f);
  EXPECT_FLOAT_EQ(a.max_linear_velocity, 40.0f);
  EXPECT_FLOAT_EQ(a.max_angular_velocity, 9.0f);
  EXPECT_EQ(Built(*scene, 1).shape->type(), ShapeType::kTriangleMesh);
  EXPECT_EQ(Built(*scene, 1).object_layer, layers::kNonMoving);
  EXPECT_EQ(scene->description.bodies[2].name, "body2");
  EXPECT_FLOAT_EQ(*Built(*scene, 2).mass, 3.0f);
  EXPECT_TRUE(Built(*scene, 2).report_contacts);
  EXPECT_FALSE(a.report_contacts);
  const BodyCreationSettings trigger = Built(*scene, 3);
  EXPECT_TRUE(trigger.is_sensor);
  EXPECT_TRUE(trigger.sensor_detects_static);
  EXPECT_EQ(trigger.object_layer, layers::kMoving);  // so that it can pair with the static level
  EXPECT_FALSE(a.is_sensor);
}

TEST(SceneLoader, BadSensorsNameTheirKey) {
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,0,1]],
                          "indices": [0, 2, 1]}, "motion": "static", "sensor": true}]})")
                .find("/bodies/0/sensor: a sensor's shape must be convex"),
            std::string::npos);
  EXPECT_NE(
      ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "sensor_detects_static": true}]})")
          .find("/bodies/0/sensor_detects_static"),
      std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "sensor": 1}]})")
                .find("/bodies/0/sensor: must be true or false"),
            std::string::npos);
}

TEST(SceneLoader, ErrorsNameTheFileAndJsonPath) {
  EXPECT_NE(ParseError("{ not json").find("test.json: invalid JSON"), std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": -1}}]})")
                .find("/bodies/0/shape/radius"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "box", "half_extents": [1, 2]}}]})")
                .find("/bodies/0/shape/half_extents"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": 0}]})")
                .find("/bodies/0/mass"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "positon": [0, 0, 0]}]})")
                .find("/bodies/0/positon: unknown key"),
            std::string::npos);
  EXPECT_NE(
      ParseError(
          R"({"bodies": [{"shape": {"type": "convex_hull", "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}}]})")
          .find("coplanar"),
      std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "mesh", "vertices": [], "indices": []}}]})")
                .find("/bodies/0/shape"),
            std::string::npos);
  EXPECT_NE(
      ParseError(R"({"bodies": [{"shape": {"type": "mesh", "file": "missing.obj"}, "motion": "static"}]})")
          .find("missing.obj: file not found"),
      std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"dt": 0}, "bodies": []})").find("/settings/dt"), std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"sleep_rule": "nap"}, "bodies": []})")
                .find("/settings/sleep_rule: must be velocity or point_movement (got 'nap')"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"sleep_rule": 1}, "bodies": []})").find("/settings/sleep_rule"),
            std::string::npos);
  EXPECT_NE(
      ParseError(R"({"settings": {"sleep_point_velocity": -1}, "bodies": []})").find("sleep_point_velocity"),
      std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "cone"}}]})").find("/bodies/0/shape/type"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"name": "x", "shape": {"type": "sphere", "radius": 1}},
                                       {"name": "x", "shape": {"type": "sphere", "radius": 1}}]})")
                .find("duplicate"),
            std::string::npos);
  EXPECT_NE(LoadScene(kScenes / "nope.json").error().message.find("file not found"), std::string::npos);
}

TEST(SceneLoader, MeshIndicesAndGravityOutsideTheirRangesAreErrors) {
  // 4294967298 read as 32 bits is 2, a valid index of another vertex: refused, with its JSON path.
  const std::string wrapped = ParseError(R"({"bodies": [{"motion": "static", "shape": {"type": "mesh",
      "vertices": [[0, 0, 0], [1, 0, 0], [0, 0, 1]], "indices": [0, 1, 4294967298]}}]})");
  EXPECT_NE(wrapped.find("/bodies/0/shape/indices/2: 4294967298 is not a vertex index (there are 3"),
            std::string::npos)
      << wrapped;
  EXPECT_NE(ParseError(R"({"bodies": [{"motion": "static", "shape": {"type": "mesh",
      "vertices": [[0, 0, 0], [1, 0, 0], [0, 0, 1]], "indices": [0, 1, 3]}}]})")
                .find("indices/2: 3 is not a vertex index"),
            std::string::npos);
  // A position the broad phase cannot hold is named by its JSON path, not as "body 1" of the batch.
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}},
      {"shape": {"type": "sphere", "radius": 1}, "position": [0, 1e19, 0]}]})")
                .find("/bodies/1/position: must be within 1e9 m"),
            std::string::npos);
  const std::string gravity = ParseError(R"({"settings": {"gravity": [0, -1e30, 0]}, "bodies": []})");
  EXPECT_NE(gravity.find("gravity"), std::string::npos) << gravity;
  EXPECT_NE(gravity.find("at most 1e4"), std::string::npos) << gravity;
}

TEST(SceneLoader, NumbersOutsideTheirTypesAreErrorsNotAborts) {
  // Beyond a double: nlohmann reports out_of_range while parsing.
  EXPECT_NE(
      ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1e400}}]})").find("invalid JSON"),
      std::string::npos);
  // Beyond a float, and integers that would wrap.
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1e39}}]})")
                .find("/bodies/0/shape/radius: does not fit a 32-bit float"),
            std::string::npos);
  EXPECT_NE(
      ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "position": [0, 1e39, 0]}]})")
          .find("/bodies/0/position/1"),
      std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"velocity_iterations": 4294967297}, "bodies": []})")
                .find("/settings/velocity_iterations: is out of range"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"substeps": 0}, "bodies": []})").find("substeps"), std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"exact_small_islands": 1}, "bodies": []})")
                .find("/settings/exact_small_islands: must be true or false"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"restitution_iterations": 0}, "bodies": []})")
                .find("restitution_iterations' must be in [1, 1000]"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"settings": {"position_iterations": 2}, "bodies": []})").find("relax_iterations"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "motion_quality": "ccd"}]})")
                .find("/bodies/0/motion_quality"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": 1e-30}]})")
                .find("/bodies/0/mass: body mass must be in [1e-6, 1e10] kg"),
            std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "density": 1e-40}]})")
                .find("/bodies/0/density: body mass must be in"),
            std::string::npos);
  EXPECT_NE(
      ParseError(R"({"bodies": [{"shape": {"type": "box", "half_extents": [0.0002, 1, 1]}, "mass": 1}]})")
          .find("/bodies/0/shape: a dynamic body's shape must be at least 2 mm across"),
      std::string::npos);
  // A static body has no mass to overflow: any size.
  EXPECT_TRUE(ParseScene(R"({"bodies": [{"shape": {"type": "box", "half_extents": [0.0002, 1, 1]},
                                         "motion": "static"}]})",
                         "inline", kScenes)
                  .ok());
  Result<Scene> cast = ParseScene(
      R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "motion_quality": "linear_cast"}]})",
      "inline", kScenes);
  ASSERT_TRUE(cast.ok()) << cast.error().message;
  EXPECT_EQ(Built(*cast, 0).motion_quality, MotionQuality::kLinearCast);
}

TEST(SceneLoader, MeshFilesImportThroughAssimp) {
  const std::filesystem::path directory = TempPath("scene_test");
  std::filesystem::create_directories(directory);
  std::ofstream(directory / "quad.obj") << "v 0 0 0\nv 4 0 0\nv 4 0 4\nv 0 0 4\nf 1 3 2\nf 1 4 3\n";
  std::ofstream(directory / "broken.obj") << "this is not a mesh\n";
  Result<Scene> scene =
      ParseScene(R"({"bodies": [{"shape": {"type": "mesh", "file": "quad.obj"}, "motion": "static"}]})",
                 "inline", directory);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto& mesh = static_cast<const TriangleMeshShape&>(*scene->shapes[0]);
  EXPECT_EQ(mesh.triangle_count(), 2u);
  Result<Scene> broken =
      ParseScene(R"({"bodies": [{"shape": {"type": "mesh", "file": "broken.obj"}, "motion": "static"}]})",
                 "inline", directory);
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.error().message.find("broken.obj"), std::string::npos);
  std::filesystem::remove_all(directory);
}

const HeightFieldShape& FieldOf(const Scene& scene) {
  return static_cast<const HeightFieldShape&>(*scene.shapes.front());
}

TEST(SceneLoader, HeightFieldsComeFromArraysPicturesAndRawFiles) {
  // An array, null for a hole (the cell with that corner), rows along +z.
  Result<Scene> scene = ParseScene(R"({"bodies": [{"motion": "static", "shape": {"type": "heightfield",
      "columns": 3, "rows": 3, "cell_size": 2, "heights": [0, 1, 2, 3, 4, 5, 6, 7, null]}}]})",
                                   "inline", kScenes);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const HeightFieldShape& field = FieldOf(*scene);
  EXPECT_EQ(field.columns(), 3u);
  EXPECT_EQ(field.rows(), 3u);
  EXPECT_EQ(field.cell_size(), 2.0f);
  EXPECT_EQ(field.Height(2, 0), 2.0f);
  EXPECT_EQ(field.Height(0, 2), 6.0f);
  EXPECT_TRUE(field.IsHole(1, 1));
  EXPECT_FALSE(field.IsHole(0, 1));

  // A grey picture: black at the low end of height_range, white at the high end.
  const std::filesystem::path dir = TempPath("heightfield_scene");
  std::filesystem::create_directories(dir);
  const unsigned char grey[6] = {0, 51, 102, 153, 204, 255};
  ASSERT_NE(stbi_write_png((dir / "terrain.png").string().c_str(), 3, 2, 1, grey, 3), 0);
  scene =
      ParseScene(R"({"bodies": [{"motion": "static", "shape": {"type": "heightfield", "file": "terrain.png",
      "cell_size": 0.5, "height_range": [-1, 4]}}]})",
                 "inline", dir);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(FieldOf(*scene).columns(), 3u);
  EXPECT_EQ(FieldOf(*scene).rows(), 2u);
  for (std::uint32_t i = 0; i < 6; ++i)
    EXPECT_NEAR(FieldOf(*scene).Height(i % 3, i / 3), -1.0f + i, 1e-5f) << i;

  // Raw little-endian floats, NaN for a hole; the size comes from the scene and must match the file.
  const float raw[6] = {0.5f, 1.5f, 2.5f, 3.5f, 4.5f, HeightFieldShape::kHole};
  {
    std::ofstream file(dir / "terrain.r32", std::ios::binary);
    file.write(reinterpret_cast<const char*>(raw), sizeof(raw));
  }
  scene =
      ParseScene(R"({"bodies": [{"motion": "static", "shape": {"type": "heightfield", "file": "terrain.r32",
      "columns": 3, "rows": 2}}]})",
                 "inline", dir);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(FieldOf(*scene).Height(1, 1), 4.5f);
  EXPECT_TRUE(FieldOf(*scene).IsHole(1, 0));
  EXPECT_FALSE(FieldOf(*scene).IsHole(0, 0));
  Result<SceneWorld> world = BuildSceneWorld(*scene);
  ASSERT_TRUE(world.ok()) << world.error().message;

  const std::string prefix = R"({"bodies": [{"motion": "static", "shape": {"type": "heightfield", )";
  auto error = [&](const std::string& fields, const std::filesystem::path& base = kScenes) {
    Result<Scene> bad = ParseScene(prefix + fields + "}}]}", "test.json", base);
    EXPECT_FALSE(bad.ok()) << fields;
    return bad.ok() ? std::string() : bad.error().message;
  };
  EXPECT_NE(error(R"("columns": 2, "rows": 2, "heights": [0, "a", 0, 0])")
                .find("/bodies/0/shape/heights/1: must be a number"),
            std::string::npos);
  EXPECT_NE(error(R"("rows": 2, "heights": [0, 0, 0, 0])").find("/bodies/0/shape/columns: is required"),
            std::string::npos);
  EXPECT_NE(error(R"("columns": 1, "rows": 2, "heights": [0, 0])").find("columns: must be a whole number"),
            std::string::npos);
  EXPECT_NE(error(R"("columns": 2, "rows": 2, "heights": [0, 0, 0])").find("got 3 heights"),
            std::string::npos);
  EXPECT_NE(error(R"("columns": 2, "rows": 2, "cell_size": -1, "heights": [0, 0, 0, 0])").find("cell size"),
            std::string::npos);
  EXPECT_NE(error(R"("file": "terrain.png", "columns": 3)", dir).find("leave out columns and rows"),
            std::string::npos);
  EXPECT_NE(error(R"("file": "terrain.r32", "columns": 2, "rows": 2)", dir).find("24 bytes, but 2 x 2"),
            std::string::npos);
  {
    std::ofstream file(dir / "not_a_picture.png");
    file << "hello";
  }
  EXPECT_NE(error(R"("file": "not_a_picture.png")", dir).find("not a PNG picture"), std::string::npos);
  EXPECT_NE(error(R"("file": "missing.png")", dir).find("missing.png"), std::string::npos);
  EXPECT_NE(
      error(R"("columns": 2, "rows": 2, "heights": [0, 0, 0, 0], "spacing": 1)").find("spacing: unknown key"),
      std::string::npos);
}

TEST(SceneLoader, BoxesAndHullsTakeAConvexRadiusAndRefuseOneThatDoesNotFit) {
  const std::string hull = R"("points": [[0,1,0],[1,0,0],[-1,0,0],[0,0,1],[0,0,-1]])";
  Result<Scene> scene = ParseScene(R"({"bodies": [
      {"shape": {"type": "box", "half_extents": [1, 1, 1]}},
      {"shape": {"type": "box", "half_extents": [1, 1, 1], "convex_radius": 0}},
      {"shape": {"type": "box", "half_extents": [1, 1, 1], "convex_radius": 0.2}},
      {"shape": {"type": "convex_hull", )" +
                                       hull + R"(, "convex_radius": 0.08}},
      {"shape": {"type": "convex_hull", )" +
                                       hull + R"(}}]})",
                                   "test.json", kScenes);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto radius = [&](std::size_t i) {
    return static_cast<const ConvexShape&>(*scene->shapes[i]).convex_radius();
  };
  EXPECT_FLOAT_EQ(radius(0), kDefaultConvexRadius);
  EXPECT_FLOAT_EQ(radius(1), 0.0f);
  EXPECT_FLOAT_EQ(radius(2), 0.2f);
  EXPECT_FLOAT_EQ(radius(3), 0.08f);
  EXPECT_FLOAT_EQ(radius(4), kDefaultConvexRadius);
  for (const char* bad : {R"(-0.1)", R"("round")", R"(1.5)", R"(null)"}) {
    const std::string error = ParseError(
        std::string(R"({"bodies": [{"shape": {"type": "box", "half_extents": [1, 1, 1], "convex_radius": )") +
        bad + "}}]}");
    EXPECT_NE(error.find("convex_radius"), std::string::npos) << bad << ": " << error;
  }
  EXPECT_NE(
      ParseError(R"({"bodies": [{"shape": {"type": "convex_hull", )" + hull + R"(, "convex_radius": 0.5}}]})")
          .find("convex_radius"),
      std::string::npos);
  EXPECT_NE(ParseError(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1, "convex_radius": 0.1}}]})")
                .find("convex_radius"),
            std::string::npos);
}

}  // namespace
}  // namespace strata::test
