// glTF export: layers of coloured triangles and lines come back through assimp's importer with their names,
// primitive kinds, counts, positions and colours; bad layers are refused and leave no file; the demo's
// scene.glb holds the level, the navmesh coloured by island and the agents' paths.
#include <gtest/gtest.h>

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <map>

#include "assets/import/GltfExporter.h"

#include "tests/TempPath.h"

namespace strata::test {
namespace {

/// Each mesh of the file by name.
std::map<std::string, const aiMesh*> MeshesByName(const aiScene& scene) {
  std::map<std::string, const aiMesh*> meshes;
  for (unsigned i = 0; i < scene.mNumMeshes; ++i) meshes[scene.mMeshes[i]->mName.C_Str()] = scene.mMeshes[i];
  return meshes;
}

GltfLayer Quad() {
  // Two triangles of a 2 x 3 m floor at y = 1, far from the origin (a level's coordinates).
  GltfLayer layer{"floor", {}, {}, {0, 1, 2, 0, 2, 3}, false};
  layer.vertices = {{1000, 1, 2000}, {1002, 1, 2000}, {1002, 1, 2003}, {1000, 1, 2003}};
  layer.colors.assign(4, Vec4(0.25f, 0.5f, 0.75f, 1.0f));
  return layer;
}

TEST(GltfExporter, LayersComeBackThroughAssimpWithNamesKindsAndColours) {
  GltfLayer path{"paths", {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}}, {}, {0, 1, 1, 2}, true};
  const GltfLayer empty{"nothing", {}, {}, {}, false};
  const auto file = TempPath("layers.glb");
  ASSERT_TRUE(ExportGltf({Quad(), path, empty}, file).ok());
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(file.string(), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  const auto meshes = MeshesByName(*scene);
  ASSERT_EQ(meshes.size(), 2u) << "the empty layer is left out";
  const aiMesh& floor = *meshes.at("floor");
  EXPECT_EQ(floor.mPrimitiveTypes, static_cast<unsigned>(aiPrimitiveType_TRIANGLE));
  EXPECT_EQ(floor.mNumFaces, 2u);
  ASSERT_NE(floor.mColors[0], nullptr);
  for (unsigned f = 0; f < floor.mNumFaces; ++f)
    for (unsigned k = 0; k < 3; ++k) {
      const aiVector3D& v = floor.mVertices[floor.mFaces[f].mIndices[k]];
      EXPECT_FLOAT_EQ(v.y, 1.0f);
      EXPECT_TRUE(v.x >= 1000.0f && v.x <= 1002.0f && v.z >= 2000.0f && v.z <= 2003.0f);
      EXPECT_NEAR(floor.mColors[0][floor.mFaces[f].mIndices[k]].b, 0.75f, 1e-3f);
    }
  const aiMesh& lines = *meshes.at("paths");
  EXPECT_EQ(lines.mPrimitiveTypes, static_cast<unsigned>(aiPrimitiveType_LINE));
  EXPECT_EQ(lines.mNumFaces, 2u);
  EXPECT_EQ(lines.mColors[0], nullptr) << "a layer without colours has none";
}

TEST(GltfExporter, BadLayersAreRefusedAndWriteNothing) {
  const auto file = TempPath("refused.glb");
  std::filesystem::remove(file);
  GltfLayer past = Quad();
  past.indices.back() = 4;
  GltfLayer partial = Quad();
  partial.indices.pop_back();
  GltfLayer not_finite = Quad();
  not_finite.vertices[1].y() = std::numeric_limits<float>::quiet_NaN();
  GltfLayer colours = Quad();
  colours.colors.pop_back();
  GltfLayer odd_lines{"lines", {{0, 0, 0}, {1, 0, 0}}, {}, {0, 1, 1}, true};
  for (const GltfLayer& bad : {past, partial, not_finite, colours, odd_lines}) {
    const Status written = ExportGltf({Quad(), bad}, file);
    EXPECT_FALSE(written.ok());
    EXPECT_NE(written.message().find(file.string()), std::string::npos) << written.message();
    EXPECT_FALSE(std::filesystem::exists(file));
  }
  EXPECT_FALSE(ExportGltf({GltfLayer{"empty", {}, {}, {}, false}}, file).ok());
  EXPECT_FALSE(ExportGltf({Quad()}, TempPath("no_such_folder") / "x.glb").ok());
}

}  // namespace
}  // namespace strata::test
