// Level import: every supported format round-trips through assimp with transforms, welding and Z-up
// handled; levels are chunked per world tile and streamed in as one batch; bad files leave the world
// unchanged with an error naming the file and the reason.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "../physics/TestWorld.h"
#include "assets/import/MeshExporter.h"
#include "assets/level/LevelLoader.h"
#include "tools/levelgen/LevelGenerator.h"

#include <stb/stb_image_write.h>

#include "tests/TempPath.h"

namespace strata::test {
namespace {

AABB BoundsOf(const ImportedMesh& mesh) {
  AABB bounds;
  for (const Vec3& v : mesh.vertices) bounds.Encapsulate(v);
  return bounds;
}

void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
}

class LevelFormats : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(LevelFormats, RoundTripKeepsTrianglesAndBounds) {
  const auto [format, extension] = GetParam();
  const ImportedMesh arena = levelgen::Arena().mesh;
  const auto path = TempPath(std::string("arena_") + format + "." + extension);
  ASSERT_TRUE(ExportMesh(arena, path, format).ok());
  const auto imported = ImportMesh(path);
  ASSERT_TRUE(imported.ok()) << imported.error().message;
  // The generator writes each box corner once per face; importing welds them back together.
  EXPECT_EQ(imported->triangles.size(), arena.triangles.size());
  EXPECT_LT(imported->vertices.size(), arena.vertices.size());
  const AABB expected = BoundsOf(arena), got = BoundsOf(*imported);
  EXPECT_TRUE(got.min.isApprox(expected.min, 1e-4f) && got.max.isApprox(expected.max, 1e-4f))
      << format << ": " << got.min.transpose() << " / " << got.max.transpose();
}

INSTANTIATE_TEST_SUITE_P(Assimp, LevelFormats,
                         ::testing::Values(std::pair{"objnomtl", "obj"}, std::pair{"gltf2", "gltf"},
                                           std::pair{"glb2", "glb"}, std::pair{"fbxa", "fbx"},
                                           std::pair{"plyb", "ply"}, std::pair{"stlb", "stl"},
                                           std::pair{"collada", "dae"}),
                         [](const auto& param_info) { return std::string(param_info.param.first); });

TEST(LevelImport, ZUpFileComesInYUp) {
  const ImportedMesh courtyard = levelgen::Courtyard().mesh;
  const auto path = TempPath("courtyard_zup.glb");
  ASSERT_TRUE(ExportMesh(courtyard, path, "glb2", /*z_up=*/true).ok());
  const auto as_is = ImportMesh(path);
  MeshImportOptions options;
  options.z_up = true;
  const auto converted = ImportMesh(path, options);
  ASSERT_TRUE(as_is.ok() && converted.ok());
  const AABB expected = BoundsOf(courtyard);
  EXPECT_TRUE(BoundsOf(*converted).min.isApprox(expected.min) &&
              BoundsOf(*converted).max.isApprox(expected.max));
  EXPECT_FALSE(BoundsOf(*as_is).max.isApprox(expected.max));  // read without the option it lies on its side
  options.scale = 0.5f;
  const auto scaled = ImportMesh(path, options);
  ASSERT_TRUE(scaled.ok());
  EXPECT_TRUE(BoundsOf(*scaled).max.isApprox(0.5f * expected.max));
}

// A Z-up file read without --z-up (6 of 27 tiles baked, silently, before) is loaded but warned about,
// and so is a Y-up file converted as if it were Z-up; a level read the right way gets no warning.
TEST(LevelLoad, ALevelThatLooksZUpIsWarnedAbout) {
  const auto path = TempPath("courtyard_zup_warning.glb");
  ASSERT_TRUE(ExportMesh(levelgen::Courtyard().mesh, path, "glb2", /*z_up=*/true).ok());
  const auto warnings_of = [&](const std::filesystem::path& file, bool z_up) {
    auto world = MakeWorld();
    LevelLoadOptions options;
    options.import.z_up = z_up;
    Result<LoadedLevel> level = LoadLevel(*world, file, options);
    EXPECT_TRUE(level.ok()) << level.error().message;
    return level.ok() ? level->warnings : std::vector<std::string>{"failed"};
  };
  const std::vector<std::string> unconverted = warnings_of(path, false);
  ASSERT_EQ(unconverted.size(), 1u);
  EXPECT_NE(unconverted[0].find("looks Z-up; pass --z-up"), std::string::npos) << unconverted[0];
  EXPECT_TRUE(warnings_of(path, true).empty());
  const auto y_up = TempPath("courtyard_y_up_warning.obj");
  ASSERT_TRUE(ExportMesh(levelgen::Courtyard().mesh, y_up, "objnomtl").ok());
  EXPECT_TRUE(warnings_of(y_up, false).empty());
  const std::vector<std::string> converted_twice = warnings_of(y_up, true);
  ASSERT_EQ(converted_twice.size(), 1u);
  EXPECT_NE(converted_twice[0].find("drop --z-up"), std::string::npos) << converted_twice[0];
  EXPECT_TRUE(LooksZUp(*ImportMesh(path)));
  EXPECT_FALSE(LooksZUp(levelgen::Courtyard().mesh));
}

TEST(LevelImport, SceneGraphTransformsWeldingAndDegenerates) {
  const auto path = TempPath("nodes.dae");
  // Two nodes share one mesh: a unit quad moved by +10 x and by +20 x; plus a zero-area triangle.
  WriteText(path, R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
 <asset><unit meter="1"/><up_axis>Y_UP</up_axis></asset>
 <library_geometries><geometry id="quad"><mesh>
  <source id="p"><float_array id="pa" count="18">0 0 0 1 0 0 1 0 1 0 0 1 2 0 0 3 0 0</float_array>
   <technique_common><accessor source="#pa" count="6" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
  <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
  <triangles count="3"><input semantic="VERTEX" source="#v" offset="0"/><p>0 3 2 0 2 1 0 4 5</p></triangles>
 </mesh></geometry></library_geometries>
 <library_visual_scenes><visual_scene id="s">
  <node id="a"><matrix>1 0 0 10 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#quad"/></node>
  <node id="b"><matrix>1 0 0 20 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#quad"/></node>
 </visual_scene></library_visual_scenes>
 <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>)");
  const auto mesh = ImportMesh(path);
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  EXPECT_EQ(mesh->triangles.size(), 4u);  // 2 quads x 2 triangles; the collinear one is gone
  EXPECT_EQ(mesh->vertices.size(), 8u);
  const AABB bounds = BoundsOf(*mesh);
  EXPECT_FLOAT_EQ(bounds.min.x(), 10.0f);
  EXPECT_FLOAT_EQ(bounds.max.x(), 21.0f);
}

TEST(LevelLoad, ChunksPerWorldTileAndStreamsInOneBatch) {
  auto world = MakeWorld();
  const auto path = TempPath("courtyard_chunks.obj");
  ASSERT_TRUE(ExportMesh(levelgen::Courtyard().mesh, path, "objnomtl").ok());
  LevelLoadOptions options;
  options.world_tile_size = 32.0f;
  // The loading thread prepares while this thread keeps stepping a world with something falling in it.
  const BodyID falling = Add(*world, Dynamic(Box(0.3f, 0.3f, 0.3f), Vec3(5, 10, 5)));
  Result<PreparedLevel> prepared = MakeError(ErrorCode::kInvalidState, "not run");
  std::thread loader([&] { prepared = PrepareLevel(*world, path, options); });
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
  loader.join();
  ASSERT_TRUE(prepared.ok()) << prepared.error().message;
  EXPECT_EQ(world->body_count_in_world(), 1u);  // nothing visible until finalized
  const auto level = FinalizeLevel(*world, std::move(*prepared));
  ASSERT_TRUE(level.ok());
  // 64 m in 32 m tiles: 2 x 2, plus slivers (the outer wall faces at x = 64 and z = 64) in the next ones.
  EXPECT_GE(level->chunks, 4u);
  EXPECT_EQ(level->triangles, levelgen::Courtyard().mesh.triangles.size());
  EXPECT_EQ(world->body_count_in_world(), 1u + level->chunks);
  // The falling crate lands on the level's ground.
  StepFor(*world, 240);
  EXPECT_NEAR(Position(*world, falling).y(), 0.3f, 0.05f);
}

TEST(LevelLoad, ChunkTrianglesLieInTheirTile) {
  const ImportedMesh courtyard = levelgen::Courtyard().mesh;
  std::size_t triangles = 0;
  for (const LevelChunk& chunk : ChunkLevel(courtyard, 32.0f)) {
    triangles += chunk.mesh.triangles.size();
    for (const auto& t : chunk.mesh.triangles) {
      const Vec3 centroid =
          (chunk.mesh.vertices[t[0]] + chunk.mesh.vertices[t[1]] + chunk.mesh.vertices[t[2]]) / 3.0f;
      EXPECT_EQ(static_cast<int>(std::floor(centroid.x() / 32.0f)), chunk.tile_x);
      EXPECT_EQ(static_cast<int>(std::floor(centroid.z() / 32.0f)), chunk.tile_z);
    }
  }
  EXPECT_EQ(triangles, courtyard.triangles.size());
}

TEST(LevelLoad, BadFilesLeaveTheWorldUnchanged) {
  auto world = MakeWorld();
  Add(*world, Static(Box(5, 1, 5), Vec3(0, -1, 0)));
  const auto expect_error = [&](const std::filesystem::path& path, const std::string& why,
                                const LevelLoadOptions& options = {}) {
    const auto level = LoadLevel(*world, path, options);
    ASSERT_FALSE(level.ok()) << path;
    EXPECT_NE(level.error().message.find(path.filename().string()), std::string::npos)
        << level.error().message;
    EXPECT_NE(level.error().message.find(why), std::string::npos) << level.error().message;
    EXPECT_EQ(world->body_count_in_world(), 1u);
    EXPECT_EQ(world->body_manager().body_count(), 1u);
  };
  expect_error(TempPath("missing.obj"), "not found");
  const auto garbage = TempPath("garbage.xyzq");
  WriteText(garbage, "this is not a mesh\n");
  expect_error(garbage, "cannot import");
  const auto truncated = TempPath("truncated.glb");
  ASSERT_TRUE(ExportMesh(levelgen::Arena().mesh, truncated, "glb2").ok());
  std::filesystem::resize_file(truncated, std::filesystem::file_size(truncated) / 2);
  expect_error(truncated, "GLB header says");
  const auto empty = TempPath("empty.obj");
  WriteText(empty, "v 0 0 0\nv 1 0 0\nv 0 0 1\n");
  expect_error(empty, "no triangles");
  const auto nan = TempPath("nan.obj");
  WriteText(nan, "v 0 0 0\nv nan 0 0\nv 0 0 1\nf 1 2 3\n");
  expect_error(nan, "non-finite");
  const auto good = TempPath("good.obj");
  ASSERT_TRUE(ExportMesh(levelgen::Arena().mesh, good, "objnomtl").ok());
  LevelLoadOptions bad_tile;
  bad_tile.world_tile_size = -1.0f;
  expect_error(good, "world_tile_size", bad_tile);
  LevelLoadOptions bad_scale;
  bad_scale.import.scale = 0.0f;
  expect_error(good, "scale", bad_scale);
}

TEST(LevelLoad, AHeightMapPictureComesInAsOneTerrainBody) {
  // 37 x 23 pixels (odd sizes), grey rising along x: black at -2 m, white at 10 m, 0.5 m between pixels.
  constexpr int kWidth = 37, kHeight = 23;
  std::vector<unsigned char> grey(kWidth * kHeight);
  for (int z = 0; z < kHeight; ++z)
    for (int x = 0; x < kWidth; ++x)
      grey[z * kWidth + x] = static_cast<unsigned char>(x * 255 / (kWidth - 1));
  const auto path = TempPath("terrain.png");
  ASSERT_NE(stbi_write_png(path.string().c_str(), kWidth, kHeight, 1, grey.data(), kWidth), 0);
  auto world = MakeWorld();
  LevelLoadOptions options;
  options.height_map = {0.5f, -2.0f, 10.0f};
  const Result<LoadedLevel> level = LoadLevel(*world, path, options);
  ASSERT_TRUE(level.ok()) << level.error().message;
  EXPECT_EQ(level->bodies.size(), 1u);
  EXPECT_EQ(level->chunks, 1u);
  EXPECT_EQ(level->triangles, 2u * (kWidth - 1) * (kHeight - 1));
  EXPECT_TRUE(level->bounds.min.isApprox(Vec3(0.0f, -2.0f, 0.0f)));
  EXPECT_TRUE(level->bounds.max.isApprox(Vec3(18.0f, 10.0f, 11.0f)));
  // Halfway along x (pixel 18, grey 127 of 255) the ground is about halfway up.
  const auto hit = world->query().CastRay(Vec3(9.0f, 20.0f, 5.3f), Vec3(0.0f, -40.0f, 0.0f));
  ASSERT_TRUE(hit.ok() && hit->has_value());
  EXPECT_EQ((*hit)->body, level->bodies.front());
  EXPECT_NEAR((*hit)->position.y(), -2.0f + 12.0f * 127.0f / 255.0f, 1e-4f);

  // A picture too small to be terrain, and bad options, leave the world as it was.
  const auto tiny = TempPath("tiny.png");
  ASSERT_NE(stbi_write_png(tiny.string().c_str(), 1, 1, 1, grey.data(), 1), 0);
  EXPECT_FALSE(LoadLevel(*world, tiny).ok());
  options.height_map.cell_size = 0.0f;
  const Result<LoadedLevel> bad = LoadLevel(*world, path, options);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("cell size"), std::string::npos) << bad.error().message;
  EXPECT_EQ(world->body_manager().body_count(), 1u);
}

}  // namespace
}  // namespace strata::test
