#include "tools/bench/BenchScenes.h"

#include <cmath>

namespace strata::bench {

namespace {

BodyDescription Body(SceneShape shape, const Vec3& position, SceneMotion motion, float friction,
                     float restitution) {
  BodyDescription body;
  body.shape = shape, body.position = position, body.motion = motion;
  body.friction = friction, body.restitution = restitution;
  return body;
}

BodyDescription Box(const Vec3& half_extents, const Vec3& position, SceneMotion motion, float friction,
                    float restitution) {
  BodyDescription body = Body(SceneShape::kBox, position, motion, friction, restitution);
  body.half_extents = half_extents;
  return body;
}

}  // namespace

BenchScene MakePyramid() {
  BenchScene scene;
  scene.name = "pyramid";
  // Jolt's pyramid leaves friction and restitution at its defaults (0.2 and 0) on the floor and the boxes.
  constexpr float kFriction = 0.2f;
  scene.bodies.push_back(Box(Vec3(50, 1, 50), Vec3(0, -1, 0), SceneMotion::kStatic, kFriction, 0.0f));
  constexpr int kLevels = 15;
  for (int i = 0; i < kLevels; ++i) {
    const float offset = (i % 2 == 1) ? 1.0f : 0.0f;
    for (int j = i / 2; j < kLevels - (i + 1) / 2; ++j) {
      for (int k = i / 2; k < kLevels - (i + 1) / 2; ++k) {
        const Vec3 position(-15.0f + 2.0f * j + offset, 1.0f + 2.5f * i, -15.0f + 2.0f * k + offset);
        scene.bodies.push_back(Box(Vec3(1, 1, 1), position, SceneMotion::kDynamic, kFriction, 0.0f));
      }
    }
  }
  // Jolt builds these boxes, floor too, with no convex radius ("to force more collisions").
  for (BodyDescription& body : scene.bodies) body.convex_radius = 0.0f;
  scene.sleeping = false;
  return scene;
}

BenchScene MakeConvexVsMesh() {
  BenchScene scene;
  scene.name = "convex_vs_mesh";
  constexpr int kCells = 100;
  constexpr float kCellSize = 3.0f;
  const float half = 0.5f * kCells * kCellSize;
  MeshGeometry& mesh = scene.meshes.emplace_back();
  for (int z = 0; z <= kCells; ++z)
    for (int x = 0; x <= kCells; ++x)
      mesh.vertices.emplace_back(x * kCellSize - half, 5.0f * std::sin(x * 0.5f) * std::cos(z * 0.5f),
                                 z * kCellSize - half);
  for (int z = 0; z < kCells; ++z) {
    for (int x = 0; x < kCells; ++x) {
      const std::uint32_t i0 = z * (kCells + 1) + x, i1 = i0 + 1, i2 = i0 + kCells + 1, i3 = i2 + 1;
      mesh.triangles.push_back({i0, i2, i1});  // counter-clockwise seen from above
      mesh.triangles.push_back({i1, i2, i3});
    }
  }
  scene.bodies.push_back(Body(SceneShape::kMesh, Vec3(0, 5, 0), SceneMotion::kStatic, 0.5f, 0.6f));
  // Jolt's box and hull here take its default convex radius (cDefaultConvexRadius), rounded edges.
  constexpr float kJoltConvexRadius = 0.05f;
  scene.hulls.push_back({{Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)}});
  for (int x = -10; x <= 10; ++x) {
    for (int y = 0; y < 4; ++y) {
      for (int z = -10; z <= 10; ++z) {
        BodyDescription body = Body(SceneShape::kBox, Vec3(7.5f * x, 15.0f + 2.0f * y, 7.5f * z),
                                    SceneMotion::kDynamic, 0.5f, 0.6f);
        switch (y) {
          case 0:
            body.shape = SceneShape::kBox, body.half_extents = Vec3(0.5f, 0.75f, 1.0f);
            body.convex_radius = kJoltConvexRadius;
            break;
          case 1:
            body.shape = SceneShape::kSphere, body.radius = 0.5f;
            break;
          case 2:
            body.shape = SceneShape::kCapsule, body.half_height = 0.75f, body.radius = 0.5f;
            break;
          default:
            body.shape = SceneShape::kHull;
            body.convex_radius = kJoltConvexRadius;
            break;
        }
        scene.bodies.push_back(body);
      }
    }
  }
  // Jolt lowers its passes for this scene, which has no joints.
  scene.jolt_velocity_steps = 4;
  scene.jolt_position_steps = 1;
  // Jolt's sleep rule and threshold, which decide much of this scene's cost.
  scene.sleeping = true;
  scene.sleep_rule = SleepRule::kPointMovement;
  scene.sleep_point_velocity = 0.03f;
  return scene;
}

void AddRagdoll(BenchScene& scene, const Vec3& pelvis, const Quat& rotation) {
  // Standing, facing +z, arms down, in metres from the pelvis; a part's capsule runs along y.
  auto part = [&](SceneShape shape, const Vec3& at, const Vec3& half_extents, float radius,
                  float half_height) {
    BodyDescription body = Body(shape, pelvis + rotation * at, SceneMotion::kDynamic, 0.5f, 0.0f);
    body.half_extents = half_extents, body.radius = radius, body.half_height = half_height;
    body.rotation = rotation;
    scene.bodies.push_back(body);
    return static_cast<int>(scene.bodies.size()) - 1;
  };
  auto capsule = [&](const Vec3& at, float half_height, float radius) {
    return part(SceneShape::kCapsule, at, Vec3::Zero(), radius, half_height);
  };
  const int hips = part(SceneShape::kBox, Vec3::Zero(), Vec3(0.15f, 0.1f, 0.1f), 0, 0);
  const int belly = capsule(Vec3(0.0f, 0.22f, 0.0f), 0.04f, 0.1f);
  const int chest = part(SceneShape::kBox, Vec3(0.0f, 0.46f, 0.0f), Vec3(0.17f, 0.12f, 0.1f), 0, 0);
  const int head = part(SceneShape::kSphere, Vec3(0.0f, 0.72f, 0.0f), Vec3::Zero(), 0.11f, 0);
  auto joint = [&](JointKind kind, int a, int b, const Vec3& at, const Vec3& axis, float low, float high,
                   float cone) {
    JointDescription j;
    j.kind = kind;
    j.body_a = a;
    j.body_b = b;
    j.anchor = pelvis + rotation * at;
    j.axis = rotation * axis;
    j.normal = rotation * (std::abs(axis.z()) < 0.9f ? Vec3::UnitZ() : Vec3::UnitX());
    j.limits = true;
    j.min_limit = low;
    j.max_limit = high;
    j.cone = cone;
    scene.joints.push_back(j);
  };
  const Vec3 up = Vec3::UnitY(), down = -Vec3::UnitY(), side = Vec3::UnitX();
  joint(JointKind::kSwingTwist, hips, belly, Vec3(0.0f, 0.1f, 0.0f), up, -0.3f, 0.3f, 0.4f);
  joint(JointKind::kSwingTwist, belly, chest, Vec3(0.0f, 0.34f, 0.0f), up, -0.3f, 0.3f, 0.4f);
  joint(JointKind::kSwingTwist, chest, head, Vec3(0.0f, 0.6f, 0.0f), up, -0.8f, 0.8f, 0.6f);
  for (const float x : {-1.0f, 1.0f}) {
    const int upper_arm = capsule(Vec3(0.24f * x, 0.42f, 0.0f), 0.1f, 0.05f);
    const int forearm = capsule(Vec3(0.24f * x, 0.12f, 0.0f), 0.1f, 0.045f);
    const int thigh = capsule(Vec3(0.09f * x, -0.33f, 0.0f), 0.15f, 0.07f);
    const int shin = capsule(Vec3(0.09f * x, -0.79f, 0.0f), 0.15f, 0.06f);
    joint(JointKind::kSwingTwist, chest, upper_arm, Vec3(0.22f * x, 0.56f, 0.0f), down, -0.8f, 0.8f, 1.2f);
    joint(JointKind::kHinge, upper_arm, forearm, Vec3(0.24f * x, 0.27f, 0.0f), side, -2.4f, 0.0f, 0.0f);
    joint(JointKind::kSwingTwist, hips, thigh, Vec3(0.09f * x, -0.1f, 0.0f), down, -0.4f, 0.4f, 0.8f);
    joint(JointKind::kHinge, thigh, shin, Vec3(0.09f * x, -0.565f, 0.0f), side, 0.0f, 2.4f, 0.0f);
  }
}

BenchScene MakeRagdolls() {
  BenchScene scene;
  scene.name = "ragdolls";
  // A 64 m x 64 m field of gentle hills, 1 m cells.
  HeightFieldGeometry& field = scene.height_fields.emplace_back();
  field.columns = field.rows = 65;
  field.cell = 1.0f;
  for (std::uint32_t z = 0; z < field.rows; ++z)
    for (std::uint32_t x = 0; x < field.columns; ++x)
      field.heights.push_back(0.6f * std::sin(0.3f * x) * std::cos(0.25f * z));
  const BodyDescription ground =
      Body(SceneShape::kHeightField, Vec3(-32.0f, 0.0f, -32.0f), SceneMotion::kStatic, 0.6f, 0.0f);
  scene.bodies.push_back(ground);
  // Five heaps of twenty, each ragdoll lying at its own turn, 0.9 m above the one below.
  for (int heap = 0; heap < 5; ++heap) {
    const Vec3 base(-12.0f + 6.0f * heap, 2.0f, 0.0f);
    for (int k = 0; k < 20; ++k) {
      const Quat lying = Quat(Eigen::AngleAxisf(0.37f * k + heap, Vec3::UnitY())) *
                         Quat(Eigen::AngleAxisf(0.5f * kPi, Vec3::UnitX()));
      AddRagdoll(scene, base + Vec3(0.1f * (k % 3), 0.9f * k, 0.1f * (k % 2)), lying);
    }
  }
  scene.sleeping = false;
  return scene;
}

BenchScene MakeChains() {
  BenchScene scene;
  scene.name = "chains";
  scene.bodies.push_back(Box(Vec3(30, 1, 30), Vec3(0, -1, 0), SceneMotion::kStatic, 0.5f, 0.0f));
  constexpr int kChains = 20, kLinks = 40;
  constexpr float kHalf = 0.1f, kRadius = 0.03f, kBall = 0.25f;
  const float angle = 60.0f * kPi / 180.0f;
  for (int c = 0; c < kChains; ++c) {
    // Anchors 12 m up on a line; neighbouring chains swing towards each other.
    const Vec3 top(-9.5f + 1.0f * c, 12.0f, 0.0f);
    const float sign = c % 2 == 0 ? 1.0f : -1.0f;
    const Vec3 along(0.0f, -std::cos(angle), sign * std::sin(angle));
    const Quat laid = Quat::FromTwoVectors(Vec3(0.0f, -1.0f, 0.0f), along);
    int previous = -1;
    for (int i = 0; i <= kLinks; ++i) {
      const bool ball = i == kLinks;
      const float reach = ball ? 2 * kLinks * kHalf + kBall : (2 * i + 1) * kHalf;
      BodyDescription body = Body(ball ? SceneShape::kSphere : SceneShape::kCapsule, top + reach * along,
                                  SceneMotion::kDynamic, 0.5f, 0.0f);
      body.radius = ball ? kBall : kRadius, body.half_height = ball ? 0.0f : kHalf;
      body.rotation = laid;
      if (ball) body.mass = 10.0f;
      scene.bodies.push_back(body);
      JointDescription joint;
      joint.kind = JointKind::kPoint;
      joint.body_a = previous;
      joint.body_b = static_cast<int>(scene.bodies.size()) - 1;
      joint.anchor = top + (2 * i * kHalf) * along;
      scene.joints.push_back(joint);
      previous = joint.body_b;
    }
  }
  scene.sleeping = false;
  return scene;
}

BenchScene WithSolverBudget(BenchScene scene, SolverBudget budget) {
  const PhysicsSettings defaults;
  const bool jolt = budget == SolverBudget::kJolt;
  scene.substeps = jolt ? 1 : defaults.substeps;
  scene.velocity_iterations = jolt ? scene.jolt_velocity_steps : defaults.velocity_iterations;
  scene.relax_iterations = jolt ? scene.jolt_position_steps : defaults.relax_iterations;
  scene.restitution_iterations = jolt ? 1 : defaults.restitution_iterations;
  return scene;
}

const char* ToString(SolverBudget budget) {
  return budget == SolverBudget::kJolt ? "jolt" : "strata";
}

BenchScene MakeBenchScene(const std::string& name) {
  if (name == "pyramid") return MakePyramid();
  if (name == "convex_vs_mesh") return MakeConvexVsMesh();
  if (name == "ragdolls") return MakeRagdolls();
  if (name == "chains") return MakeChains();
  return {};
}

}  // namespace strata::bench
