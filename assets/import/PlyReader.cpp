#include "assets/import/PlyReader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace strata {

namespace {

constexpr std::size_t kMaxHeaderBytes = 64 * 1024;
constexpr std::size_t kMaxProperties = 256;     // per element
constexpr std::uint64_t kMaxListLength = 1024;  // vertices of one face

enum class Encoding { kAscii, kLittleEndian, kBigEndian };
enum class Type { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

struct Property {
  std::string name;
  Type type = Type::kFloat32;
  bool list = false;
  Type count_type = Type::kUInt8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

Error PlyError(const std::filesystem::path& path, const std::string& why) {
  return MakeError(ErrorCode::kParseError, path.string() + ": PLY: " + why);
}

std::optional<Type> TypeNamed(std::string_view name) {
  if (name == "char" || name == "int8") return Type::kInt8;
  if (name == "uchar" || name == "uint8") return Type::kUInt8;
  if (name == "short" || name == "int16") return Type::kInt16;
  if (name == "ushort" || name == "uint16") return Type::kUInt16;
  if (name == "int" || name == "int32") return Type::kInt32;
  if (name == "uint" || name == "uint32") return Type::kUInt32;
  if (name == "float" || name == "float32") return Type::kFloat32;
  if (name == "double" || name == "float64") return Type::kFloat64;
  return std::nullopt;
}

std::size_t SizeOf(Type type) {
  switch (type) {
    case Type::kInt8:
    case Type::kUInt8:
      return 1;
    case Type::kInt16:
    case Type::kUInt16:
      return 2;
    case Type::kInt32:
    case Type::kUInt32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 1;
}

bool IsInteger(Type type) {
  return type != Type::kFloat32 && type != Type::kFloat64;
}

std::vector<std::string_view> Words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

struct Header {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  std::size_t body = 0;  // byte where the elements' data starts
};

Result<Header> ReadHeader(std::string_view bytes, const std::filesystem::path& path) {
  Header header;
  bool has_format = false;
  std::size_t at = 0;
  for (int line_number = 1;; ++line_number) {
    const std::size_t end = bytes.find('\n', at);
    if (end == std::string_view::npos || end > kMaxHeaderBytes)
      return PlyError(path, "the header has no end_header line within its first " +
                                std::to_string(kMaxHeaderBytes) + " bytes");
    const std::vector<std::string_view> words = Words(bytes.substr(at, end - at));
    at = end + 1;
    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply") return PlyError(path, "does not start with \"ply\"");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    const std::string where = "header line " + std::to_string(line_number) + ": ";
    if (words[0] == "end_header") break;
    if (words[0] == "format") {
      if (words.size() != 3 || words[2] != "1.0")
        return PlyError(path, where + "format must be '<encoding> 1.0'");
      if (words[1] == "ascii")
        header.encoding = Encoding::kAscii;
      else if (words[1] == "binary_little_endian")
        header.encoding = Encoding::kLittleEndian;
      else if (words[1] == "binary_big_endian")
        header.encoding = Encoding::kBigEndian;
      else
        return PlyError(path, where + "unknown encoding '" + std::string(words[1]) + "'");
      has_format = true;
    } else if (words[0] == "element") {
      Element element;
      if (words.size() != 3 ||
          std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count).ec !=
              std::errc() ||
          std::to_string(element.count).size() != words[2].size())
        return PlyError(path, where + "an element needs a name and a whole count");
      element.name = words[1];
      header.elements.push_back(std::move(element));
    } else if (words[0] == "property") {
      if (header.elements.empty()) return PlyError(path, where + "a property before any element");
      Element& element = header.elements.back();
      if (element.properties.size() >= kMaxProperties)
        return PlyError(path, where + "more than " + std::to_string(kMaxProperties) + " properties");
      Property property;
      if (words.size() == 5 && words[1] == "list") {
        const std::optional<Type> count_type = TypeNamed(words[2]), item_type = TypeNamed(words[3]);
        if (!count_type || !item_type || !IsInteger(*count_type))
          return PlyError(path, where + "a list needs an integer count type and an item type");
        property = {std::string(words[4]), *item_type, true, *count_type};
      } else if (words.size() == 3 && TypeNamed(words[1])) {
        property = {std::string(words[2]), *TypeNamed(words[1]), false, Type::kUInt8};
      } else {
        return PlyError(path, where + "a property is '<type> <name>' or 'list <count type> <type> <name>'");
      }
      element.properties.push_back(std::move(property));
    } else {
      return PlyError(path, where + "unknown keyword '" + std::string(words[0]) + "'");
    }
  }
  if (!has_format) return PlyError(path, "the header has no format line");
  header.body = at;
  return header;
}

/// Reads values one at a time from the body, in the file's encoding; every read checks the bytes left.
class BodyReader {
 public:
  BodyReader(std::string_view bytes, std::size_t at, Encoding encoding)
      : bytes_(bytes), at_(at), encoding_(encoding) {}

  std::optional<double> Read(Type type) {
    return encoding_ == Encoding::kAscii ? ReadWord(type) : ReadBinary(type);
  }
  std::size_t offset() const { return at_; }
  std::size_t left() const { return bytes_.size() - at_; }
  /// The fewest bytes a value of `type` takes in this encoding (a digit and a separator in ASCII).
  std::size_t MinimumBytes(Type type) const { return encoding_ == Encoding::kAscii ? 1 : SizeOf(type); }

 private:
  static bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

  std::optional<double> ReadWord(Type type) {
    while (at_ < bytes_.size() && IsSpace(bytes_[at_])) ++at_;
    const std::size_t start = at_;
    while (at_ < bytes_.size() && !IsSpace(bytes_[at_])) ++at_;
    if (at_ == start) return std::nullopt;
    const char* first = bytes_.data() + start;
    const char* last = bytes_.data() + at_;
    if (IsInteger(type)) {
      long long value = 0;
      const auto [end, error] = std::from_chars(first, last, value);
      if (error != std::errc() || end != last) return std::nullopt;
      return static_cast<double>(value);
    }
    double value = 0.0;
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc() || end != last) return std::nullopt;
    return value;
  }

  template <typename T>
  T Take() {
    std::array<char, sizeof(T)> raw{};
    std::memcpy(raw.data(), bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    const bool swap = (encoding_ == Encoding::kBigEndian) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(raw.begin(), raw.end());
    T value;
    std::memcpy(&value, raw.data(), sizeof(T));
    return value;
  }

  std::optional<double> ReadBinary(Type type) {
    if (left() < SizeOf(type)) return std::nullopt;
    switch (type) {
      case Type::kInt8:
        return Take<std::int8_t>();
      case Type::kUInt8:
        return Take<std::uint8_t>();
      case Type::kInt16:
        return Take<std::int16_t>();
      case Type::kUInt16:
        return Take<std::uint16_t>();
      case Type::kInt32:
        return Take<std::int32_t>();
      case Type::kUInt32:
        return Take<std::uint32_t>();
      case Type::kFloat32:
        return static_cast<double>(Take<float>());
      case Type::kFloat64:
        return Take<double>();
    }
    return std::nullopt;
  }

  std::string_view bytes_;
  std::size_t at_;
  Encoding encoding_;
};

// The index of property `name` in `element`, or -1.
int PropertyIndex(const Element& element, std::initializer_list<std::string_view> names) {
  for (std::size_t i = 0; i < element.properties.size(); ++i)
    for (const std::string_view name : names)
      if (element.properties[i].name == name) return static_cast<int>(i);
  return -1;
}

Status ReadElement(const Element& element, BodyReader& reader, const std::filesystem::path& path,
                   ImportedMesh& mesh) {
  const bool vertices = element.name == "vertex";
  const bool faces = element.name == "face";
  int x = -1, y = -1, z = -1, indices = -1;
  if (vertices) {
    x = PropertyIndex(element, {"x"}), y = PropertyIndex(element, {"y"}), z = PropertyIndex(element, {"z"});
    if (x < 0 || y < 0 || z < 0) return PlyError(path, "the vertex element has no x, y and z");
    for (const int coordinate : {x, y, z})
      if (element.properties[static_cast<std::size_t>(coordinate)].list)
        return PlyError(path, "the vertex element's x, y and z must be numbers, not lists");
  }
  if (faces) {
    indices = PropertyIndex(element, {"vertex_indices", "vertex_index"});
    if (indices < 0 || !element.properties[static_cast<std::size_t>(indices)].list)
      return PlyError(path, "the face element has no vertex_indices list");
  }
  // Before reserving: every element takes at least a byte a property.
  std::size_t minimum = 0;
  for (const Property& property : element.properties)
    minimum += reader.MinimumBytes(property.list ? property.count_type : property.type);
  if (minimum > 0 && element.count > reader.left() / minimum)
    return PlyError(path, "element '" + element.name + "' declares " + std::to_string(element.count) +
                              " entries, more than the file's remaining " + std::to_string(reader.left()) +
                              " bytes could hold");
  if (element.properties.empty()) return Status::Ok();  // nothing to read, however many it declares
  if (vertices) mesh.vertices.reserve(static_cast<std::size_t>(element.count));
  if (faces) mesh.triangles.reserve(static_cast<std::size_t>(element.count));
  std::vector<double> values(element.properties.size());
  std::vector<std::uint32_t> polygon;
  for (std::uint64_t entry = 0; entry < element.count; ++entry) {
    const auto fail = [&](const std::string& why) {
      return PlyError(path, element.name + " " + std::to_string(entry) + " (byte " +
                                std::to_string(reader.offset()) + "): " + why);
    };
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const Property& property = element.properties[p];
      if (!property.list) {
        const std::optional<double> value = reader.Read(property.type);
        if (!value) return fail("'" + property.name + "' is missing or not a number");
        values[p] = *value;
        continue;
      }
      const std::optional<double> length = reader.Read(property.count_type);
      if (!length || *length < 0 || *length > static_cast<double>(kMaxListLength))
        return fail("list '" + property.name + "' has no valid length (0 to " +
                    std::to_string(kMaxListLength) + ")");
      polygon.clear();
      for (int i = 0; i < static_cast<int>(*length); ++i) {
        const std::optional<double> item = reader.Read(property.type);
        if (!item) return fail("list '" + property.name + "' is cut short");
        if (static_cast<int>(p) != indices) continue;
        if (!(*item >= 0.0) || *item >= static_cast<double>(mesh.vertices.size()))
          return fail("vertex index " + std::to_string(*item) + " is not one of the " +
                      std::to_string(mesh.vertices.size()) + " vertices read before the faces");
        polygon.push_back(static_cast<std::uint32_t>(*item));
      }
      for (std::size_t i = 2; i < polygon.size(); ++i)
        mesh.triangles.push_back({polygon[0], polygon[i - 1], polygon[i]});
    }
    if (vertices)
      mesh.vertices.emplace_back(static_cast<float>(values[static_cast<std::size_t>(x)]),
                                 static_cast<float>(values[static_cast<std::size_t>(y)]),
                                 static_cast<float>(values[static_cast<std::size_t>(z)]));
  }
  return Status::Ok();
}

}  // namespace

bool LooksLikePly(std::string_view bytes) {
  return bytes.size() >= 4 && bytes.substr(0, 3) == "ply" && (bytes[3] == '\n' || bytes[3] == '\r');
}

Result<ImportedMesh> ReadPly(std::string_view bytes, const std::filesystem::path& path) {
  Result<Header> header = ReadHeader(bytes, path);
  if (!header) return header.error();
  BodyReader reader(bytes, header->body, header->encoding);
  ImportedMesh mesh;
  for (const Element& element : header->elements)
    if (Status read = ReadElement(element, reader, path, mesh); !read) return read.error();
  return mesh;
}

}  // namespace strata
