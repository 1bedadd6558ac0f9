// DeclaredCounts: what a GLB or glTF file declares is checked against what it holds before assimp
// allocates for it. The GLB is the arena as the exporter writes it, edited in place (lengths unchanged).
#include "assets/import/DeclaredCounts.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "assets/import/MeshExporter.h"
#include "assets/import/MeshImporter.h"
#include "tools/levelgen/LevelGenerator.h"

#include "tests/TempPath.h"

namespace strata::test {
namespace {

std::string Read(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

// The message CheckDeclaredCounts gives for `bytes` written to a file, or "ok".
std::string Check(const std::string& bytes, const std::string& name) {
  const auto path = TempPath(name);
  std::ofstream(path, std::ios::binary) << bytes;
  const Status status = CheckDeclaredCounts(path, bytes.size());
  std::filesystem::remove(path);
  return status ? "ok" : status.message();
}

// `text` replaced by `replacement` of the same length, once.
std::string Edited(std::string bytes, const std::string& text, const std::string& replacement) {
  EXPECT_EQ(text.size(), replacement.size());
  const std::size_t at = bytes.find(text);
  EXPECT_NE(at, std::string::npos) << text;
  if (at != std::string::npos) bytes.replace(at, text.size(), replacement);
  return bytes;
}

class DeclaredCounts : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto path = TempPath("arena.glb");
    ASSERT_TRUE(ExportMesh(levelgen::Arena().mesh, path, "glb2").ok());
    glb_ = Read(path);
    std::filesystem::remove(path);
    ASSERT_EQ(glb_.compare(0, 4, "glTF"), 0);
  }
  std::string glb_;
};

TEST_F(DeclaredCounts, AWellFormedGlbPasses) {
  EXPECT_EQ(Check(glb_, "good.glb"), "ok");
}

TEST_F(DeclaredCounts, AGlbChunkLongerThanTheFileIsRefused) {
  // What fuzz_mesh found: a 3 KB file whose JSON chunk claims 3.9 GB; assimp took 3.8 GB and 10 s for it.
  std::string bytes = glb_;
  const std::uint32_t huge = 3876324136u;
  std::memcpy(bytes.data() + 12, &huge, sizeof(huge));
  EXPECT_NE(Check(bytes, "chunk.glb").find("GLB chunk at byte 12 claims 3876324136 bytes"),
            std::string::npos);
  EXPECT_NE(Check(glb_.substr(0, glb_.size() / 2), "cut.glb").find("GLB header says"), std::string::npos);
}

TEST_F(DeclaredCounts, AccessorsAndBuffersLargerThanTheirDataAreRefused) {
  EXPECT_NE(Check(Edited(glb_, "\"count\":56,", "\"count\":99,"), "count.glb")
                .find("glTF accessor 0 declares 99 elements, more than its buffer view holds"),
            std::string::npos);
  EXPECT_NE(Check(Edited(glb_, "\"byteLength\":1704}", "\"byteLength\":9704}"), "buffer.glb")
                .find("glTF buffer 0 declares 9704 bytes but has 1704"),
            std::string::npos);
  EXPECT_NE(Check(Edited(glb_, "\"byteOffset\":672,", "\"byteOffset\":972,"), "view.glb")
                .find("glTF buffer view 1 lies outside its buffer"),
            std::string::npos);
}

TEST(MeshFuzzFindings, AnObjWhoseFacesNameNoVertexIsAnErrorNotACrash) {
  // Crashed Debian's assimp 5.2 OBJ reader (fuzz_mesh_obj); ObjReader reads OBJ now.
  const auto found = std::filesystem::path(STRATA_FUZZ_FOUND_DIR) / "obj_faces_without_vertices.obj";
  const Result<ImportedMesh> mesh = ImportMesh(found);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("OBJ line 2: face names vertex 1 of 0"), std::string::npos)
      << mesh.error().message;
}

TEST(MeshFuzzFindings, AFileAssimpWouldReadAsAnotherFormatIsRefused) {
  // A ".glb" that is a Quick3D file by its bytes: assimp's Quick3D loader asked for 2 TB (fuzz_mesh_glb).
  // Only the loaders of the formats Strata supports are left to assimp.
  const auto found = std::filesystem::path(STRATA_FUZZ_FOUND_DIR) / "glb_quick3d_claims_2tb.glb";
  const Result<ImportedMesh> mesh = ImportMesh(found);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("No suitable reader"), std::string::npos) << mesh.error().message;
}

TEST(MeshFuzzFindings, TheGlbClaimingAFourGigabyteChunkIsAnErrorAtOnce) {
  const auto found = std::filesystem::path(STRATA_FUZZ_FOUND_DIR) / "glb_chunk_claims_4gb.glb";
  const Result<ImportedMesh> mesh = ImportMesh(found);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("GLB header says"), std::string::npos) << mesh.error().message;
}

TEST(DeclaredCountsOther, FormatsWithoutDeclarationsPass) {
  EXPECT_EQ(Check("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", "plain.obj"), "ok");
  EXPECT_EQ(Check("ply\nformat ascii 1.0\nelement vertex 1000000000\nend_header\n", "left.ply"), "ok")
      << "PLY counts are PlyReader's to check";
}

}  // namespace
}  // namespace strata::test
