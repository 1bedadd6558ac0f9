// BakeLevel, the one bake the CLI, demo and benches share: levels of any extent bake every tile (extents that
// are not a multiple of the tile, levels off the origin), a request wider than a small level still builds it,
// too large or empty levels are clear errors, and the saved file (and the OBJ and the triangles by island
// that the viewer draws) is the same however many threads built it and in whatever order its tiles were
// published or rebuilt, or when it was baked in shards and merged.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "NavMeshTestWorld.h"
#include "assets/import/MeshExporter.h"
#include "assets/level/LevelLoader.h"
#include "navmesh/LevelBake.h"
#include "navmesh/Validation.h"
#include "tests/TempPath.h"
#include "tools/levelgen/LevelGenerator.h"

namespace strata::test {
namespace {

using navmesh::TileCoord;

navmesh::LevelBakeOptions Options(int workers) {
  navmesh::LevelBakeOptions options;
  options.service = FastServiceConfig(workers);
  options.timeout = std::chrono::seconds(120);
  return options;
}

/// The bounds a level loader would report for a floor slab.
AABB SlabBounds(float min_x, float max_x, float min_z, float max_z) {
  return {Vec3(min_x, -1.0f, min_z), Vec3(max_x, 0.0f, max_z)};
}

std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

std::string SavedBytes(const navmesh::NavMesh& navmesh, const std::string& name,
                       std::optional<navmesh::SetCoverage> coverage = std::nullopt) {
  const std::filesystem::path path = TempPath(name + ".bin");
  EXPECT_TRUE(navmesh.Save(path, coverage).ok());
  return ReadBytes(path);
}

std::string ObjBytes(const navmesh::NavMesh& navmesh, const std::string& name) {
  const std::filesystem::path path = TempPath(name + ".obj");
  EXPECT_TRUE(navmesh.WriteObj(path).ok());
  return ReadBytes(path);
}

// What a navmesh writes and draws: its file, its OBJ and its triangles by island and tile.
void ExpectSameOutputs(const navmesh::NavMesh& navmesh, const navmesh::NavMesh& reference,
                       const std::string& name) {
  EXPECT_EQ(SavedBytes(navmesh, name), SavedBytes(reference, name + "_reference")) << name;
  EXPECT_EQ(ObjBytes(navmesh, name), ObjBytes(reference, name + "_reference")) << name;
  const navmesh::NavMeshTriangles triangles = navmesh::TrianglesByIsland(navmesh);
  const navmesh::NavMeshTriangles expected = navmesh::TrianglesByIsland(reference);
  EXPECT_EQ(triangles.islands, expected.islands) << name;
  EXPECT_EQ(triangles.island, expected.island) << name;
  EXPECT_EQ(triangles.tile, expected.tile) << name;
  EXPECT_EQ(triangles.vertices, expected.vertices) << name;
}

TEST(LevelBake, FloorsOfOddSizesAndPlacesBakeEveryTile) {
  struct Floor {
    float min_x, max_x, min_z, max_z;
  };
  // A 20 m floor around the origin, a 6 m floor inside one tile, an 80 x 90 m floor off the origin: each
  // once failed with "box covers more tiles than max_tiles".
  for (const Floor floor : {Floor{-10, 10, -10, 10}, Floor{3, 9, 3, 9}, Floor{-41.3f, 38.9f, 7.7f, 97.9f}}) {
    auto world = MakeWorld();
    AddSlab(*world, floor.min_x, floor.max_x, floor.min_z, floor.max_z, 0.0f);
    const AABB bounds = SlabBounds(floor.min_x, floor.max_x, floor.min_z, floor.max_z);
    const Result<navmesh::LevelBake> bake = navmesh::BakeLevel(*world, bounds, Options(2));
    ASSERT_TRUE(bake.ok()) << bake.error().message;
    const std::vector<TileCoord> covered = bake->service->grid().TilesInBox(bounds);
    EXPECT_EQ(bake->tiles, covered.size());
    for (const TileCoord tile : covered)
      EXPECT_EQ(bake->service->GetTileState(tile), navmesh::TileState::kReady) << tile.x << ", " << tile.z;
    // A strip of floor narrower than the agent (0.5 m of the 80 m floor in its last column) has no polygon.
    for (const TileCoord tile : bake->service->navmesh().Tiles())
      EXPECT_NE(std::find(covered.begin(), covered.end(), tile), covered.end()) << tile.x << ", " << tile.z;
    EXPECT_GE(bake->service->navmesh().tile_count() + 8, static_cast<int>(covered.size()));
    EXPECT_EQ(bake->service->stats().failures, 0u);
    // Corner to corner, inside the agent radius from the edges.
    const Vec3 from(floor.min_x + 1.0f, 0.0f, floor.min_z + 1.0f),
        to(floor.max_x - 1.0f, 0.0f, floor.max_z - 1.0f);
    const auto path = MakeQuery(bake->service->navmesh())->FindPath(from, to);
    ASSERT_TRUE(path.ok()) << path.error().message;
    EXPECT_TRUE(path->reached_end);
  }
}

TEST(LevelBake, AGeneratedFieldIsTheSameForItsSeedAndWalkableCornerToCorner) {
  // 100 m is not a whole number of 25.6 m cells: the ground still ends exactly at the size.
  const levelgen::GeneratedLevel field = levelgen::Field(100.0f, 5);
  const levelgen::GeneratedLevel again = levelgen::Field(100.0f, 5);
  const levelgen::GeneratedLevel other = levelgen::Field(100.0f, 6);
  ASSERT_EQ(field.mesh.vertices.size(), again.mesh.vertices.size());
  EXPECT_TRUE(
      std::equal(field.mesh.vertices.begin(), field.mesh.vertices.end(), again.mesh.vertices.begin()));
  EXPECT_FALSE(
      other.mesh.vertices.size() == field.mesh.vertices.size() &&
      std::equal(field.mesh.vertices.begin(), field.mesh.vertices.end(), other.mesh.vertices.begin()))
      << "another seed, other features";
  AABB bounds;
  for (const Vec3& vertex : field.mesh.vertices) bounds.Encapsulate(vertex);
  EXPECT_EQ(bounds.min.x(), 0.0f);
  EXPECT_EQ(bounds.min.z(), 0.0f);
  EXPECT_EQ(bounds.max.x(), 100.0f);
  EXPECT_EQ(bounds.max.z(), 100.0f);
  EXPECT_EQ(bounds.min.y(), 0.0f);
  EXPECT_LE(bounds.max.y(), 8.0f);

  const std::filesystem::path path = TempPath("field.obj");
  ASSERT_TRUE(ExportMesh(field.mesh, path, "objnomtl").ok());
  auto world = MakeWorld();
  const Result<LoadedLevel> level = LoadLevel(*world, path);
  ASSERT_TRUE(level.ok()) << level.error().message;
  const Result<navmesh::LevelBake> bake = navmesh::BakeLevel(*world, level->bounds, Options(2));
  ASSERT_TRUE(bake.ok()) << bake.error().message;
  const navmesh::NavMesh& navmesh = bake->service->navmesh();
  // Features cover at most a sixth of a cell, and roofs add walkable area back.
  EXPECT_GT(navmesh.WalkableArea(), 0.8f * 100.0f * 100.0f);
  // Features keep 2 m from their cell's edges, so the lanes along the edges link every corner.
  const auto path_across = MakeQuery(navmesh)->FindPath({1.0f, 0.0f, 1.0f}, {99.0f, 0.0f, 99.0f});
  ASSERT_TRUE(path_across.ok()) << path_across.error().message;
  EXPECT_TRUE(path_across->reached_end);
}

TEST(LevelBake, EmptyAndOversizedLevelsAreClearErrors) {
  auto world = MakeWorld();
  const Result<navmesh::LevelBake> empty = navmesh::BakeLevel(*world, AABB(), Options(1));
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().message.find("no geometry"), std::string::npos) << empty.error().message;
  // 100 km across (a unit mix-up): refused before a tile table or a tile list is allocated.
  const Result<navmesh::LevelBake> huge =
      navmesh::BakeLevel(*world, SlabBounds(0, 1e5f, 0, 1e5f), Options(1));
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.error().message.find("more than a navmesh holds"), std::string::npos)
      << huge.error().message;
}

TEST(LevelBake, ARequestWiderThanASmallLevelBuildsIt) {
  // The demo's agents ask for 16 m around them; on a level of one tile that circle touches nine tiles.
  // The tiles off the level hold nothing walkable and take no slot, so the request is a normal one.
  auto world = MakeWorld();
  AddSlab(*world, 3, 9, 3, 9, 0.0f);
  const Result<navmesh::NavMeshServiceConfig> config =
      navmesh::ConfigForLevel(FastServiceConfig(), SlabBounds(3, 9, 3, 9));
  ASSERT_TRUE(config.ok()) << config.error().message;
  EXPECT_EQ(config->max_tiles, 1);
  const auto service = MakeService(*world, *config);
  ASSERT_TRUE(service->RequestAround(Vec3(6, 0, 6), 16.0f).ok());
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
  EXPECT_EQ(service->stats().failures, 0u) << service->last_error();
  EXPECT_EQ(service->navmesh().Tiles(), (std::vector<TileCoord>{TileCoord{0, 0}}));
  EXPECT_EQ(service->GetTileState({0, 0}), navmesh::TileState::kReady);
  // An absurd radius is still refused.
  EXPECT_FALSE(service->RequestAround(Vec3(6, 0, 6), 1.0e6f).ok());
}

/// Bakes a 20 m slab whose corner is `corner` metres out on x and z, and walks across it.
void ExpectFarSlabBakesAndPathsCrossIt(float corner) {
  auto world = MakeWorld();
  AddSlab(*world, corner, corner + 20.0f, corner, corner + 20.0f, 0.0f);
  const AABB bounds = SlabBounds(corner, corner + 20.0f, corner, corner + 20.0f);
  const Result<navmesh::LevelBake> bake = navmesh::BakeLevel(*world, bounds, Options(1));
  ASSERT_TRUE(bake.ok()) << bake.error().message;
  const navmesh::NavMesh& navmesh = bake->service->navmesh();
  EXPECT_EQ(navmesh.tile_count(), 4) << "a 20 m slab on a 12.8 m grid";
  // The same walkable area as the slab at the world origin gives.
  auto near_world = MakeWorld();
  AddSlab(*near_world, 0.0f, 20.0f, 0.0f, 20.0f, 0.0f);
  const auto near_bake = navmesh::BakeLevel(*near_world, SlabBounds(0.0f, 20.0f, 0.0f, 20.0f), Options(1));
  ASSERT_TRUE(near_bake.ok());
  EXPECT_NEAR(navmesh.WalkableArea(), near_bake->service->navmesh().WalkableArea(), 1.0);
  const Vec3 from(corner + 2.0f, 0.0f, corner + 2.0f), to(corner + 18.0f, 0.0f, corner + 18.0f);
  const auto path = MakeQuery(navmesh)->FindPath(from, to);
  ASSERT_TRUE(path.ok()) << path.error().message;
  EXPECT_TRUE(path->reached_end);
  ASSERT_FALSE(path->points.empty());
  EXPECT_LT((path->points.front() - from).norm(), 1.0f) << "path points come back in world coordinates";
  // Saved and loaded, the navmesh keeps its origin: the same path from the file.
  const std::filesystem::path file = TempPath("far_slab.bin");
  ASSERT_TRUE(navmesh.Save(file).ok());
  const auto loaded = navmesh::NavMesh::Load(file);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ((*loaded)->origin_tile(), navmesh.origin_tile());
  EXPECT_EQ((*loaded)->Tiles(), navmesh.Tiles());
  const auto loaded_path = MakeQuery(**loaded)->FindPath(from, to);
  ASSERT_TRUE(loaded_path.ok());
  EXPECT_EQ(loaded_path->points, path->points);
  std::filesystem::remove(file);
}

TEST(LevelBake, LevelsFarFromTheOriginBakeRelativeToTheirOwnOrigin) {
  // 100 km out the navmesh origin moves to the level (a float there resolves 8 mm); at 8,000 km, where
  // Recast's rasterizer once overran a stack buffer on world coordinates, it works on coordinates relative
  // to the level's own tile.
  ExpectFarSlabBakesAndPathsCrossIt(1.0e5f);
  ExpectFarSlabBakesAndPathsCrossIt(8.0e6f);
  ExpectFarSlabBakesAndPathsCrossIt(-8.0e6f);
}

TEST(LevelBake, AServiceRefusesRequestsBeyondReachOfItsOrigin) {
  // A service whose navmesh origin is the world origin cannot build 8,000 km out: a clear error that says
  // how far the request reaches, from which origin, and the limit.
  auto world = MakeWorld();
  AddSlab(*world, 8.0e6f, 8.0e6f + 20.0f, 8.0e6f, 8.0e6f + 20.0f, 0.0f);
  const auto service = MakeService(*world, FastServiceConfig());
  const Status request = service->RequestAround(Vec3(8.0e6f + 10.0f, 0.0f, 8.0e6f + 10.0f), 16.0f);
  ASSERT_FALSE(request.ok());
  EXPECT_NE(request.message().find("the request reaches 8e+06 m from the navmesh origin (0, 0)"),
            std::string::npos)
      << request.message();
  EXPECT_NE(request.message().find("within 8.389e+05 m"), std::string::npos) << request.message();
  // Moved to the level, the same request builds.
  navmesh::NavMeshServiceConfig config = FastServiceConfig();
  config.settings.origin_tile =
      navmesh::TileGrid(config.settings.tile_size()).TileAt(Vec3(8.0e6f, 0, 8.0e6f));
  const auto moved = MakeService(*world, config);
  ASSERT_TRUE(moved->RequestAround(Vec3(8.0e6f + 10.0f, 0.0f, 8.0e6f + 10.0f), 16.0f).ok());
  ASSERT_TRUE(moved->WaitUntilIdle(std::chrono::seconds(60)));
  EXPECT_EQ(moved->stats().failures, 0u) << moved->last_error();
  EXPECT_GT(moved->navmesh().WalkableArea(), 200.0);
}

TEST(LevelBake, ATriangleReachingFarOutFailsItsTileInsteadOfRecast) {
  // A tile near the origin with a triangle whose far corners are 10,000 km away (a corrupt vertex).
  navmesh::TileGeometry geometry;
  geometry.AddTriangle({{Vec3(1, 0, 1), Vec3(1.0e7f, 0, 1), Vec3(1, 0, 1.0e7f)}});
  const Result<navmesh::BuiltTile> built = navmesh::BuildTile(navmesh::NavMeshSettings{}, {0, 0}, geometry);
  ASSERT_FALSE(built.ok());
  EXPECT_NE(built.error().message.find("a triangle in tile (0, 0) reaches 1e+07 m"), std::string::npos)
      << built.error().message;
}

/// Four by four tiles of floor with a block and a raised slab, so tiles differ and link to each other.
std::unique_ptr<PhysicsSystem> FourByFourLevel() {
  auto world = MakeWorld();
  AddFloor(*world, 4);
  AddSlab(*world, 10.0f, 16.0f, 10.0f, 16.0f, 2.0f, 2.0f);
  AddSlab(*world, 30.0f, 34.0f, 5.0f, 40.0f, 0.6f, 0.6f);
  return world;
}

TEST(LevelBake, WhatANavMeshWritesIsTheSameForAnyThreadCountAndPublishOrder) {
  const AABB level = TileArea(4);
  auto world = FourByFourLevel();
  const Result<navmesh::LevelBake> one = navmesh::BakeLevel(*world, level, Options(1));
  ASSERT_TRUE(one.ok()) << one.error().message;
  const navmesh::NavMesh& reference = one->service->navmesh();
  ASSERT_GT(reference.tile_count(), 10);
  ASSERT_GT(navmesh::TrianglesByIsland(reference).vertices.size(), 100u);

  for (const int workers : {2, 4}) {
    const Result<navmesh::LevelBake> bake = navmesh::BakeLevel(*world, level, Options(workers));
    ASSERT_TRUE(bake.ok()) << bake.error().message;
    ExpectSameOutputs(bake->service->navmesh(), reference, std::to_string(workers) + "_workers");
  }

  // Published in another order (from the far corner inwards, one tile at a time, so every tile sits in
  // another slot) ...
  const Result<navmesh::NavMeshServiceConfig> config = navmesh::ConfigForLevel(FastServiceConfig(1), level);
  ASSERT_TRUE(config.ok());
  const auto reversed = MakeService(*world, *config);
  for (int z = 3; z >= 0; --z)
    for (int x = 3; x >= 0; --x) {
      ASSERT_TRUE(reversed->RequestBox(reversed->grid().Bounds({x, z}, -0.5f)).ok());
      ASSERT_TRUE(reversed->WaitUntilIdle(std::chrono::seconds(60)));
    }
  ExpectSameOutputs(reversed->navmesh(), reference, "reversed");
  // ... and after every tile was rebuilt (Detour gives a rebuilt tile a new reference).
  const std::size_t builds = reversed->stats().builds;
  ASSERT_TRUE(reversed->Invalidate(level).ok());
  ASSERT_TRUE(WaitForRebuilds(*reversed, builds));
  EXPECT_GE(reversed->stats().rebuilds, builds);
  ExpectSameOutputs(reversed->navmesh(), reference, "rebuilt");

  // The file loads and answers as the navmesh it came from.
  const std::filesystem::path path = TempPath("rebuilt.bin");
  const auto loaded = navmesh::NavMesh::Load(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Vec3 from(2, 0, 2), to(49, 0, 49);
  const auto original = MakeQuery(one->service->navmesh())->FindPath(from, to);
  const auto reloaded = MakeQuery(**loaded)->FindPath(from, to);
  ASSERT_TRUE(original.ok() && reloaded.ok());
  EXPECT_TRUE(reloaded->reached_end);
  EXPECT_EQ(reloaded->points, original->points);
}

TEST(LevelBake, AHeightFieldBakesTheNavMeshOfItsTriangles) {
  // Terrain off the origin and across tile borders: the same bytes as the mesh of its triangles.
  constexpr std::uint32_t kColumns = 31, kRows = 23;
  constexpr float kCell = 1.0f;
  std::vector<float> heights = RollingHeights(kColumns, kRows, kCell);
  const ShapeRef field = HeightField(kColumns, kRows, kCell, heights);
  const ShapeRef mesh = MeshOf(static_cast<const HeightFieldShape&>(*field));
  const Vec3 corner(7.3f, -0.4f, 3.1f);
  std::string baked[2];
  for (int k = 0; k < 2; ++k) {
    auto world = MakeWorld();
    Add(*world, Static(k == 0 ? field : mesh, corner));
    AABB bounds = (k == 0 ? field : mesh)->WorldBounds(Pose{corner, Quat::Identity()});
    const Result<navmesh::LevelBake> bake = navmesh::BakeLevel(*world, bounds, Options(1));
    ASSERT_TRUE(bake.ok()) << bake.error().message;
    ASSERT_GT(bake->service->navmesh().tile_count(), 1);
    baked[k] = SavedBytes(bake->service->navmesh(), k == 0 ? "field" : "mesh");
  }
  EXPECT_EQ(baked[0], baked[1]);
}

TEST(LevelBake, ShardsMergeIntoTheBytesOfOneBake) {
  // An 80 x 90 m floor off the origin with a few boxes on it: 56 tiles, split 3 and 8 ways (the farm's job
  // array), each shard baked on its own world and saved, then merged.
  auto world = MakeWorld();
  AddSlab(*world, -41.3f, 38.9f, 7.7f, 97.9f, 0.0f);
  for (int i = 0; i < 6; ++i) AddSlab(*world, -30.0f + 11.0f * i, -28.0f + 11.0f * i, 20.0f, 24.0f, 1.5f);
  const AABB bounds = SlabBounds(-41.3f, 38.9f, 7.7f, 97.9f);
  Result<navmesh::LevelBake> whole = navmesh::BakeLevel(*world, bounds, Options(2));
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  const std::string expected = SavedBytes(whole->service->navmesh(), "whole", whole->coverage);
  for (const int count : {3, 8}) {
    std::vector<std::filesystem::path> files;
    std::size_t tiles = 0;
    int stored = 0;  // tiles with walkable polygons (an eroded edge tile holds none and is not kept)
    for (int shard = 0; shard < count; ++shard) {
      navmesh::LevelBakeOptions options = Options(1);
      options.shard = shard;
      options.shard_count = count;
      Result<navmesh::LevelBake> part = navmesh::BakeLevel(*world, bounds, options);
      ASSERT_TRUE(part.ok()) << part.error().message;
      tiles += part->tiles;
      stored += part->service->navmesh().tile_count();
      files.push_back(TempPath("shard" + std::to_string(shard) + "of" + std::to_string(count) + ".bin"));
      ASSERT_TRUE(part->service->navmesh().Save(files.back(), part->coverage).ok());
    }
    EXPECT_EQ(tiles, whole->tiles) << "the shards share the tiles out";
    EXPECT_EQ(stored, whole->service->navmesh().tile_count());
    std::reverse(files.begin(), files.end());  // the order of the files does not matter
    Result<navmesh::MergedShards> merged = navmesh::MergeShards(files);
    ASSERT_TRUE(merged.ok()) << merged.error().message;
    EXPECT_EQ(SavedBytes(*merged->navmesh, "merged" + std::to_string(count), merged->coverage), expected)
        << count << " shards";
    // The same shard twice, or a shard of another level, is refused.
    EXPECT_FALSE(navmesh::MergeShards({files[0], files[0]}).ok());
  }

  auto other = MakeWorld();
  AddSlab(*other, 0.0f, 20.0f, 0.0f, 20.0f, 0.0f);
  Result<navmesh::LevelBake> small = navmesh::BakeLevel(*other, SlabBounds(0, 20, 0, 20), Options(1));
  ASSERT_TRUE(small.ok());
  const std::string small_file = TempPath("small.bin").string();
  ASSERT_TRUE(small->service->navmesh().Save(small_file).ok());
  const Result<navmesh::MergedShards> mixed = navmesh::MergeShards({TempPath("shard0of3.bin"), small_file});
  ASSERT_FALSE(mixed.ok());
  EXPECT_NE(mixed.error().message.find("small.bin"), std::string::npos) << mixed.error().message;
  EXPECT_FALSE(navmesh::MergeShards({}).ok());
  for (const auto& [shard, count] : {std::pair{0, 0}, {2, 2}, {-1, 3}}) {
    navmesh::LevelBakeOptions options = Options(1);
    options.shard = shard;
    options.shard_count = count;
    EXPECT_FALSE(navmesh::BakeLevel(*other, SlabBounds(0, 20, 0, 20), options).ok()) << shard << "/" << count;
  }
}

TEST(LevelBake, MergingAnIncompleteShardSetFailsAndListsTheMissingTiles) {
  auto world = MakeWorld();
  AddSlab(*world, 0.0f, 38.4f, 0.0f, 38.4f, 0.0f);
  const AABB bounds = SlabBounds(0.5f, 37.9f, 0.5f, 37.9f);  // 3 x 3 tiles
  std::vector<std::filesystem::path> files;
  std::size_t tiles_in_files = 0;
  for (int shard = 0; shard < 2; ++shard) {  // shards 0 and 1 of 3: shard 2 is lost
    navmesh::LevelBakeOptions options = Options(1);
    options.shard = shard;
    options.shard_count = 3;
    Result<navmesh::LevelBake> part = navmesh::BakeLevel(*world, bounds, options);
    ASSERT_TRUE(part.ok()) << part.error().message;
    tiles_in_files += part->tiles;
    files.push_back(TempPath("partial" + std::to_string(shard) + ".bin"));
    ASSERT_TRUE(part->service->navmesh().Save(files.back(), part->coverage).ok());
  }
  const Result<navmesh::MergedShards> refused = navmesh::MergeShards(files);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("1 of 3 shards are missing (shard 2)"), std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find("3 tiles are in no file"), std::string::npos)
      << refused.error().message;
  const Result<navmesh::MergedShards> partial = navmesh::MergeShards(files, /*allow_partial=*/true);
  ASSERT_TRUE(partial.ok()) << partial.error().message;
  EXPECT_EQ(tiles_in_files, 6u);
  EXPECT_EQ(partial->missing_shards, std::vector<int>{2});
  EXPECT_EQ(partial->missing_tiles.size(), 3u);
  EXPECT_FALSE(partial->coverage.known()) << "a partial merge does not claim the whole level";
}

}  // namespace
}  // namespace strata::test
