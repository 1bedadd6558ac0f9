#include "assets/import/ObjReader.h"

#include <charconv>
#include <string>
#include <vector>

namespace strata {

namespace {

Error ObjError(const std::filesystem::path& path, std::size_t line, const std::string& why) {
  return MakeError(ErrorCode::kParseError, path.string() + ": OBJ line " + std::to_string(line) + ": " + why);
}

bool IsBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

// The next blank-separated word of `line` from `at`, moving `at` past it; empty at the end.
std::string_view NextWord(std::string_view line, std::size_t& at) {
  while (at < line.size() && IsBlank(line[at])) ++at;
  const std::size_t start = at;
  while (at < line.size() && !IsBlank(line[at])) ++at;
  return line.substr(start, at - start);
}

// A face corner's vertex index ("7", "7/2", "7//3", "-1/2/3"), or 0 when it is not a whole number.
long long CornerIndex(std::string_view corner) {
  const std::string_view vertex = corner.substr(0, corner.find('/'));
  long long index = 0;
  const auto [end, error] = std::from_chars(vertex.data(), vertex.data() + vertex.size(), index);
  return error == std::errc() && end == vertex.data() + vertex.size() ? index : 0;
}

// Splits the text into logical lines: a backslash at the end of a line continues it on the next.
template <class Visit>
bool ForEachLine(std::string_view text, Visit&& visit) {
  std::size_t number = 0;
  std::string joined;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++number;
    while (!line.empty() && IsBlank(line.back())) line.remove_suffix(1);
    if (!line.empty() && line.back() == '\\') {
      joined.append(line.substr(0, line.size() - 1)).push_back(' ');
      continue;
    }
    if (!joined.empty()) {
      joined.append(line);
      if (!visit(std::string_view(joined), number)) return false;
      joined.clear();
      continue;
    }
    if (!visit(line, number)) return false;
  }
  return joined.empty() || visit(std::string_view(joined), number);
}

}  // namespace

Result<ImportedMesh> ReadObj(std::string_view bytes, const std::filesystem::path& path) {
  // A UTF-8 byte order mark (some Windows tools write one) would hide the first statement's keyword.
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (bytes.substr(0, kByteOrderMark.size()) == kByteOrderMark) bytes.remove_prefix(kByteOrderMark.size());
  ImportedMesh mesh;
  // Faces may name vertices given later in the file (positive indices): checked once all are read.
  struct Face {
    std::size_t line;
    std::uint32_t first_corner;
    std::uint32_t corners;
  };
  std::vector<Face> faces;
  std::vector<long long> corners;  // 1-based vertex indices, negative ones already resolved
  Status status = Status::Ok();
  const bool read = ForEachLine(bytes, [&](std::string_view line, std::size_t number) {
    std::size_t at = 0;
    const std::string_view keyword = NextWord(line, at);
    if (keyword == "v") {
      float xyz[3];
      for (float& coordinate : xyz) {
        const std::string_view word = NextWord(line, at);
        const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), coordinate);
        if (word.empty() || error != std::errc() || end != word.data() + word.size()) {
          status = ObjError(path, number, "a vertex needs three numbers");
          return false;
        }
      }
      mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
    } else if (keyword == "f") {
      Face face{number, static_cast<std::uint32_t>(corners.size()), 0};
      for (std::string_view corner = NextWord(line, at); !corner.empty(); corner = NextWord(line, at)) {
        long long index = CornerIndex(corner);
        if (index < 0) index += static_cast<long long>(mesh.vertices.size()) + 1;  // counting back from here
        if (index <= 0) {
          status = ObjError(path, number, "face corner '" + std::string(corner) + "' names no vertex");
          return false;
        }
        corners.push_back(index);
        ++face.corners;
      }
      if (face.corners < 3) {
        status = ObjError(path, number, "a face needs three corners or more");
        return false;
      }
      faces.push_back(face);
    }
    return true;  // every other statement (vt, vn, g, o, usemtl, mtllib, s, l, p, comments) is not geometry
  });
  if (!read) return status.error();
  mesh.triangles.reserve(faces.size());
  for (const Face& face : faces) {
    for (std::uint32_t k = 0; k < face.corners; ++k)
      if (corners[face.first_corner + k] > static_cast<long long>(mesh.vertices.size()))
        return ObjError(path, face.line,
                        "face names vertex " + std::to_string(corners[face.first_corner + k]) + " of " +
                            std::to_string(mesh.vertices.size()));
    const auto corner = [&](std::uint32_t k) {
      return static_cast<std::uint32_t>(corners[face.first_corner + k] - 1);
    };
    for (std::uint32_t k = 2; k < face.corners; ++k)
      mesh.triangles.push_back({corner(0), corner(k - 1), corner(k)});
  }
  return mesh;
}

}  // namespace strata
