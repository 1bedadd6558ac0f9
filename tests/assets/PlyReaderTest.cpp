// PlyReader against files written by hand in each encoding: the same mesh from ASCII, little- and
// big-endian binary, elements and properties it does not use skipped, polygons fanned, and every kind of
// damage an error that says where.
#include "assets/import/PlyReader.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <string>

namespace strata::test {
namespace {

const char* kHeader =
    "ply\nformat %s 1.0\ncomment written by hand\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
    "property float quality\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";

std::string Header(const char* format) {
  char text[1024];
  std::snprintf(text, sizeof(text), kHeader, format);
  return text;
}

template <typename T>
void Put(std::string& out, T value, bool big_endian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (big_endian == (std::endian::native == std::endian::little)) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

std::string Binary(bool big_endian) {
  std::string ply = Header(big_endian ? "binary_big_endian" : "binary_little_endian");
  const float vertices[4][3] = {{0, 0, 0}, {0, 0, 2}, {3, 0, 2}, {3, 1, 0}};
  for (const auto& v : vertices) {
    for (const float c : v) Put(ply, c, big_endian);
    Put<std::uint8_t>(ply, 200, big_endian);
  }
  Put<std::uint8_t>(ply, 4, big_endian);  // a quad
  for (const std::int32_t i : {0, 1, 2, 3}) Put(ply, i, big_endian);
  Put(ply, 0.5f, big_endian);
  Put<std::int32_t>(ply, 0, big_endian);
  Put<std::int32_t>(ply, 1, big_endian);
  return ply;
}

std::string Ascii() {
  return Header("ascii") +
         "0 0 0 200\n0 0 2 200\n3 0 2 200\n3 1 0 200\n4 0 1 2 3 0.5\n0 1";  // no last newline
}

TEST(PlyReader, EveryEncodingGivesTheSameMesh) {
  const Result<ImportedMesh> ascii = ReadPly(Ascii(), "a.ply");
  ASSERT_TRUE(ascii.ok()) << ascii.error().message;
  ASSERT_EQ(ascii->vertices.size(), 4u);
  ASSERT_EQ(ascii->triangles.size(), 2u) << "the quad is fanned into two triangles";
  EXPECT_EQ(ascii->triangles[1], (TriangleMeshShape::Indices{0, 2, 3}));
  for (const bool big_endian : {false, true}) {
    const Result<ImportedMesh> binary = ReadPly(Binary(big_endian), "b.ply");
    ASSERT_TRUE(binary.ok()) << binary.error().message;
    EXPECT_EQ(binary->vertices, ascii->vertices) << big_endian;
    EXPECT_EQ(binary->triangles, ascii->triangles) << big_endian;
  }
}

TEST(PlyReader, EveryTruncationOfABinaryFileIsAnError) {
  const std::string ply = Binary(false);
  const std::size_t body = ply.find("end_header\n") + 11;
  for (std::size_t size = 0; size < ply.size(); ++size) {
    const Result<ImportedMesh> cut = ReadPly(std::string_view(ply).substr(0, size), "cut.ply");
    EXPECT_FALSE(cut.ok()) << size << " of " << ply.size() << " bytes";
    if (size > body && !cut.ok()) {  // the message names the element that was cut
      const std::string& message = cut.error().message;
      EXPECT_TRUE(message.find("vertex") != std::string::npos || message.find("face") != std::string::npos ||
                  message.find("edge") != std::string::npos)
          << message;
    }
  }
}

TEST(PlyReader, DamageIsAnErrorNamingWhatIsWrong) {
  struct Case {
    std::string bytes;
    std::string message;
  };
  const std::string good = Ascii();
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string bytes = good;
    bytes.replace(bytes.find(from), from.size(), to);
    return bytes;
  };
  const std::vector<Case> cases = {
      {"ply\nformat ascii 1.0\n" + std::string(70000, 'x'), "no end_header"},
      {"plyx\n", "does not start"},
      {replaced("format ascii 1.0", "format ebcdic 1.0"), "unknown encoding"},
      {replaced("element vertex 4", "element vertex 4x"), "whole count"},
      {replaced("element vertex 4", "element vertex 99999999999"), "declares 99999999999 entries"},
      {replaced("property float x", "property quaternion x"), "a property is"},
      {replaced("property float x", "property float w"), "no x, y and z"},
      {replaced("4 0 1 2 3", "4 0 1 2 7"), "vertex index 7"},
      {replaced("4 0 1 2 3", "250 0 1 2 3"), "cut short"},
      {replaced("3 1 0 200", "3 nan? 0 200"), "not a number"},
      {replaced("format ascii 1.0\n", ""), "no format line"},
  };
  for (const Case& c : cases) {
    const Result<ImportedMesh> mesh = ReadPly(c.bytes, "bad.ply");
    ASSERT_FALSE(mesh.ok()) << c.message;
    EXPECT_NE(mesh.error().message.find(c.message), std::string::npos) << mesh.error().message;
    EXPECT_NE(mesh.error().message.find("bad.ply: PLY: "), std::string::npos) << mesh.error().message;
  }
}

TEST(PlyReader, AnElementWithoutPropertiesCostsNothingHoweverManyItDeclares) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement nothing 18446744073709551615\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar uint vertex_index\nend_header\n0 0 0 1 0 0 0 0 1 3 0 1 2\n";
  const Result<ImportedMesh> mesh = ReadPly(ply, "n.ply");
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  EXPECT_EQ(mesh->triangles.size(), 1u);
}

}  // namespace
}  // namespace strata::test
