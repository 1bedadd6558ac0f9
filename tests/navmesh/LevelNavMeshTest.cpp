// The bundled courtyard level through the whole pipeline (assimp import -> chunked static bodies ->
// background tiles): a Z-up and a Y-up copy give the same navmesh, and the level's features behave as
// built: the 30 degree ramp and the stairs lead onto the platform, the bridge crosses the trench, the
// 50 degree ramp does not reach its ledge.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "NavMeshTestWorld.h"
#include "assets/level/LevelLoader.h"
#include "navmesh/Validation.h"

namespace strata::test {
namespace {

const std::filesystem::path kLevels = STRATA_LEVELS_DIR;

struct LevelNavMesh {
  std::unique_ptr<PhysicsSystem> world;
  std::unique_ptr<navmesh::NavMeshService> service;
};

LevelNavMesh Bake(const std::filesystem::path& file, bool z_up) {
  LevelNavMesh result{MakeWorld(), nullptr};
  LevelLoadOptions options;
  options.import.z_up = z_up;
  const auto level = LoadLevel(*result.world, file, options);
  EXPECT_TRUE(level.ok()) << (level.ok() ? "" : level.error().message);
  if (!level.ok()) return result;
  result.service = BuildArea(*result.world, level->bounds, FastServiceConfig(2));
  return result;
}

/// Every tile's polygon vertices, in tile order: equal only if the navmeshes are the same.
std::vector<std::vector<float>> TileVertices(const navmesh::NavMesh& navmesh) {
  return navmesh.Read([](const dtNavMesh& mesh) {
    std::map<navmesh::TileCoord, std::vector<float>> by_tile;
    for (int i = 0; i < mesh.getMaxTiles(); ++i) {
      const dtMeshTile* tile = mesh.getTile(i);
      if (tile && tile->header)
        by_tile[{tile->header->x, tile->header->y}].assign(tile->verts,
                                                           tile->verts + 3 * tile->header->vertCount);
    }
    std::vector<std::vector<float>> vertices;
    for (auto& [coord, v] : by_tile) vertices.push_back(std::move(v));
    return vertices;
  });
}

TEST(LevelNavMesh, ZUpAndYUpCopiesGiveTheSameNavmesh) {
  const LevelNavMesh y_up = Bake(kLevels / "courtyard.obj", false);
  const LevelNavMesh z_up = Bake(kLevels / "courtyard_zup.obj", true);
  ASSERT_TRUE(y_up.service && z_up.service);
  EXPECT_EQ(y_up.service->navmesh().Tiles(), z_up.service->navmesh().Tiles());
  EXPECT_GT(y_up.service->navmesh().polygon_count(), 50);
  EXPECT_EQ(TileVertices(y_up.service->navmesh()), TileVertices(z_up.service->navmesh()));
}

TEST(LevelNavMesh, CourtyardFeaturesConnectAsBuilt) {
  const LevelNavMesh level = Bake(kLevels / "courtyard.obj", false);
  ASSERT_TRUE(level.service);
  const auto query = MakeQuery(level.service->navmesh());
  const Vec3 yard(8.0f, 0.0f, 30.0f);
  // Up the 30 degree ramp (west) or the stairs (east) onto the 3 m platform.
  const auto platform = query->FindPath(yard, Vec3(17.0f, 3.0f, 44.0f));
  ASSERT_TRUE(platform.ok());
  EXPECT_TRUE(platform->reached_end);
  const auto via_stairs = query->FindPath(Vec3(32.0f, 0.0f, 44.0f), Vec3(17.0f, 3.0f, 44.0f));
  ASSERT_TRUE(via_stairs.ok());
  EXPECT_TRUE(via_stairs->reached_end);
  EXPECT_LT(via_stairs->length, 20.0f);  // straight up the stairs, not round to the ramp
  // Across the trench only by the bridge (z 30..34).
  const auto across = query->FindPath(Vec3(30.0f, 0.0f, 20.0f), Vec3(56.0f, 0.0f, 20.0f));
  ASSERT_TRUE(across.ok());
  EXPECT_TRUE(across->reached_end);
  EXPECT_TRUE(navmesh::PathCrossesBox(*across, AABB(Vec3(40, -1, 30), Vec3(48, 1, 34))));
  EXPECT_FALSE(navmesh::PathCrossesBox(*across, AABB(Vec3(40, -7, 8), Vec3(48, 1, 29.8f))));
  // The trench floor and the ledge behind the 50 degree ramp are navmesh, but unreachable from the yard.
  const auto trench = query->FindPath(yard, Vec3(44.0f, -6.0f, 20.0f));
  ASSERT_TRUE(trench.ok());
  EXPECT_FALSE(trench->reached_end);
  const auto ledge = query->FindPath(yard, Vec3(59.0f, 3.0f, 59.0f));
  ASSERT_TRUE(ledge.ok());
  EXPECT_FALSE(ledge->reached_end);
  EXPECT_TRUE(query->FindNearestPoly(Vec3(59.0f, 3.0f, 59.0f)).ok());
}

}  // namespace
}  // namespace strata::test
