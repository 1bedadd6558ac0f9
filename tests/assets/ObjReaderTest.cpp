// ObjReader: the OBJ statements a level uses, read as assimp read them (the bundled courtyard gives the same
// mesh), and damage an error naming the line.
#include "assets/import/ObjReader.h"

#include <gtest/gtest.h>

#include <string>

namespace strata::test {
namespace {

TEST(ObjReader, ReadsEveryFaceFormAndSkipsWhatIsNotGeometry) {
  const std::string obj =
      "# a comment\nmtllib never_opened.mtl\no floor\nv 0 0 0\nv 0 0 2 1.0\nv 3 0 2 0.5 0.5 0.5\nv 3 1 0\n"
      "vt 0 0\nvn 0 1 0\nusemtl grey\ns off\ng quads\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 \\\n -1//1\n"
      "l 1 2\np 3\nf 4/1 1/1 2/1\n";
  const Result<ImportedMesh> mesh = ReadObj(obj, "a.obj");
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  ASSERT_EQ(mesh->vertices.size(), 4u);
  EXPECT_EQ(mesh->vertices[2], Vec3(3, 0, 2));
  ASSERT_EQ(mesh->triangles.size(), 4u);
  EXPECT_EQ(mesh->triangles[0], (TriangleMeshShape::Indices{0, 1, 2}));
  EXPECT_EQ(mesh->triangles[1], (TriangleMeshShape::Indices{0, 2, 3}));
  EXPECT_EQ(mesh->triangles[2], (TriangleMeshShape::Indices{0, 2, 3})) << "negative indices count back, and a "
                                                                           "backslash continues the line";
  EXPECT_EQ(mesh->triangles[3], (TriangleMeshShape::Indices{3, 0, 1}));
}

TEST(ObjReader, WindowsLineEndsAndAByteOrderMarkReadAsUnixOnes) {
  const Result<ImportedMesh> unix_file = ReadObj("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", "u.obj");
  const Result<ImportedMesh> windows_file =
      ReadObj("\xEF\xBB\xBFv 0 0 0\r\nv 1 0 0\r\nv 0 0 1\r\nf 1 2 3\r\n", "w.obj");
  ASSERT_TRUE(unix_file.ok() && windows_file.ok()) << windows_file.error().message;
  EXPECT_EQ(windows_file->vertices, unix_file->vertices);
  EXPECT_EQ(windows_file->triangles, unix_file->triangles);
}

TEST(ObjReader, DamageIsAnErrorNamingTheLine) {
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"v 0 0\n", "line 1: a vertex needs three numbers"},
      {"v 0 0 x\n", "line 1: a vertex needs three numbers"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 4\n", "line 4: face names vertex 4 of 3"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 0 1 2\n", "line 4: face corner '0' names no vertex"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf -4 1 2\n", "names no vertex"},
      {"v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3: a face needs three corners"},
      {"f 1 2 3\n", "face names vertex 1 of 0"},
  };
  for (const Case& c : cases) {
    const Result<ImportedMesh> mesh = ReadObj(c.text, "bad.obj");
    ASSERT_FALSE(mesh.ok()) << c.text;
    EXPECT_NE(mesh.error().message.find("bad.obj: OBJ line "), std::string::npos) << mesh.error().message;
    EXPECT_NE(mesh.error().message.find(c.message), std::string::npos) << mesh.error().message;
  }
}

}  // namespace
}  // namespace strata::test
