// Uses an installed Strata through its public headers only: a box dropped on a floor comes to rest on it;
// with strata::navmesh the floor bakes into a navmesh; with strata::assets a scene file's text builds a world
// that steps. Exits non-zero, saying why, when any of it does not hold.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "physics/body/BodyInterface.h"
#include "physics/shapes/BoxShape.h"
#include "physics/world/PhysicsSystem.h"
#ifdef STRATA_CONSUMER_WITH_NAVMESH
#include "navmesh/LevelBake.h"
#endif
#ifdef STRATA_CONSUMER_WITH_ASSETS
#include "assets/scene/SceneLoader.h"
#endif

namespace {

int Fail(const std::string& why) {
  std::fprintf(stderr, "strata_consumer: %s\n", why.c_str());
  return 1;
}

strata::BodyCreationSettings Box(const strata::Vec3& half, const strata::Vec3& position, bool moves) {
  strata::BodyCreationSettings settings;
  settings.shape = *strata::BoxShape::Create(half);
  settings.position = position;
  settings.motion_type = moves ? strata::MotionType::kDynamic : strata::MotionType::kStatic;
  if (!moves) settings.object_layer = strata::layers::kNonMoving;
  return settings;
}

}  // namespace

int main() {
  using namespace strata;
  Result<std::unique_ptr<PhysicsSystem>> created = PhysicsSystem::Create(PhysicsSystemConfig{});
  if (!created) return Fail("PhysicsSystem::Create: " + created.error().message);
  PhysicsSystem& world = **created;
  const float floor_half = 12.0f;
  if (!world.bodies().CreateAndAddBody(Box(Vec3(floor_half, 0.5f, floor_half), Vec3(0, -0.5f, 0), false)))
    return Fail("the floor was not added");
  const Result<BodyID> box =
      world.bodies().CreateAndAddBody(Box(Vec3(0.5f, 0.5f, 0.5f), Vec3(0, 3, 0), true));
  if (!box) return Fail("the box was not added: " + box.error().message);
  for (int step = 0; step < 180; ++step)
    if (!world.Step(1.0f / 60.0f)) return Fail("a step failed");
  const float height = world.bodies().GetPosition(*box)->y();
  if (std::abs(height - 0.5f) > 0.02f) return Fail("the box rests at y = " + std::to_string(height));
  std::printf("physics: the box came to rest at y = %.3f\n", height);

#ifdef STRATA_CONSUMER_WITH_NAVMESH
  navmesh::LevelBakeOptions options;
  options.service.worker_threads = 1;
  const AABB level(Vec3(-floor_half, -1, -floor_half), Vec3(floor_half, 0, floor_half));
  const Result<navmesh::LevelBake> bake = navmesh::BakeLevel(world, level, options);
  if (!bake) return Fail("BakeLevel: " + bake.error().message);
  const int polygons = bake->service->navmesh().polygon_count();
  if (bake->tiles == 0 || polygons == 0) return Fail("the bake has no polygons");
  std::printf("navmesh: %zu tiles, %d polygons\n", bake->tiles, polygons);
#endif

#ifdef STRATA_CONSUMER_WITH_ASSETS
  const std::string text = R"({"bodies": [
    {"name": "floor", "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "position": [0, -0.5, 0],
     "motion": "static"},
    {"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "position": [0, 2, 0]}]})";
  const Result<Scene> scene = ParseScene(text, "consumer scene", ".");
  if (!scene) return Fail("ParseScene: " + scene.error().message);
  Result<SceneWorld> scene_world = BuildSceneWorld(*scene);
  if (!scene_world) return Fail("BuildSceneWorld: " + scene_world.error().message);
  for (int step = 0; step < 120; ++step)
    if (!scene_world->system->Step(1.0f / 60.0f)) return Fail("a scene step failed");
  const float ball = scene_world->system->bodies().GetPosition(scene_world->ids[1])->y();
  if (std::abs(ball - 0.5f) > 0.02f) return Fail("the scene's ball rests at y = " + std::to_string(ball));
  std::printf("assets: the scene's ball came to rest at y = %.3f\n", ball);
#endif
  return 0;
}
