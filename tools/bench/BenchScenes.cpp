#include "tools/bench/BenchScenes.h"

#include <cmath>

namespace strata::bench {

BenchScene MakePyramid() {
  BenchScene scene;
  scene.name = "pyramid";
  scene.bodies.push_back({BenchShape::kBox, Vec3(50, 1, 50), 0, 0, Vec3(0, -1, 0), false, 0.5f, 0.0f});
  constexpr int kLevels = 15;
  for (int i = 0; i < kLevels; ++i) {
    const float offset = (i % 2 == 1) ? 1.0f : 0.0f;
    for (int j = i / 2; j < kLevels - (i + 1) / 2; ++j) {
      for (int k = i / 2; k < kLevels - (i + 1) / 2; ++k) {
        const Vec3 position(-15.0f + 2.0f * j + offset, 1.0f + 2.5f * i, -15.0f + 2.0f * k + offset);
        scene.bodies.push_back({BenchShape::kBox, Vec3(1, 1, 1), 0, 0, position, true, 0.5f, 0.0f});
      }
    }
  }
  scene.sleeping = false;  // the world's default substeps and iterations
  return scene;
}

BenchScene MakeConvexVsMesh() {
  BenchScene scene;
  scene.name = "convex_vs_mesh";
  constexpr int kCells = 100;
  constexpr float kCellSize = 3.0f;
  const float half = 0.5f * kCells * kCellSize;
  for (int z = 0; z <= kCells; ++z)
    for (int x = 0; x <= kCells; ++x)
      scene.mesh_vertices.emplace_back(x * kCellSize - half, 5.0f * std::sin(x * 0.5f) * std::cos(z * 0.5f),
                                       z * kCellSize - half);
  for (int z = 0; z < kCells; ++z) {
    for (int x = 0; x < kCells; ++x) {
      const std::uint32_t i0 = z * (kCells + 1) + x, i1 = i0 + 1, i2 = i0 + kCells + 1, i3 = i2 + 1;
      scene.mesh_triangles.push_back({i0, i2, i1});  // counter-clockwise seen from above
      scene.mesh_triangles.push_back({i1, i2, i3});
    }
  }
  scene.bodies.push_back({BenchShape::kMesh, Vec3::Zero(), 0, 0, Vec3(0, 5, 0), false, 0.5f, 0.6f});
  scene.hull_points = {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  for (int x = -10; x <= 10; ++x) {
    for (int y = 0; y < 4; ++y) {
      for (int z = -10; z <= 10; ++z) {
        BenchBody body{BenchShape::kBox,
                       Vec3::Zero(),
                       0,
                       0,
                       Vec3(7.5f * x, 15.0f + 2.0f * y, 7.5f * z),
                       true,
                       0.5f,
                       0.6f};
        switch (y) {
          case 0:
            body.shape = BenchShape::kBox, body.half_extents = Vec3(0.5f, 0.75f, 1.0f);
            break;
          case 1:
            body.shape = BenchShape::kSphere, body.radius = 0.5f;
            break;
          case 2:
            body.shape = BenchShape::kCapsule, body.half_height = 0.75f, body.radius = 0.5f;
            break;
          default:
            body.shape = BenchShape::kHull;
            break;
        }
        scene.bodies.push_back(body);
      }
    }
  }
  // A cheap setting for many small bodies: one substep of four velocity passes and one relax pass.
  scene.substeps = 1;
  scene.velocity_iterations = 4;
  scene.relax_iterations = 1;
  scene.sleeping = true;
  return scene;
}

BenchScene MakeBenchScene(const std::string& name) {
  if (name == "pyramid") return MakePyramid();
  if (name == "convex_vs_mesh") return MakeConvexVsMesh();
  return {};
}

}  // namespace strata::bench
