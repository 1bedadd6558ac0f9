// The floors of the source tree: a file may include headers of its own floor and the floors below it, never
// one above (core/math < shapes < broadphase < body < narrowphase < constraints/solver < world <
// navmesh/assets < tools). The check reads the #include lines of every source file; a second test plants an
// upward include in a scratch tree to show the check catches one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace strata::test {
namespace {

namespace fs = std::filesystem;

struct Floor {
  std::string_view prefix;  // a folder, or a single file's path without its extension
  int level;
};

// The physics root holds the vocabulary every floor shares (PhysicsSettings, BodyID): floor 0, with core.
constexpr Floor kFloors[] = {
    {"physics/core/", 0},
    {"physics/math/", 0},
    {"physics/PhysicsSettings", 0},
    {"physics/BodyID", 0},
    {"physics/shapes/", 1},
    {"physics/broadphase/", 2},
    {"physics/body/", 3},
    {"physics/narrowphase/", 4},
    {"physics/constraints/", 5},
    {"physics/solver/", 5},
    {"physics/world/", 6},
    {"physics/character/", 6},
    {"navmesh/", 7},
    {"assets/", 7},
    {"tools/", 8},
};
constexpr std::string_view kLayeredFolders[] = {"physics", "navmesh", "assets", "tools"};

std::optional<Floor> FloorOf(std::string_view path) {
  std::optional<Floor> best;
  for (const Floor& floor : kFloors)
    if (path.starts_with(floor.prefix) && (!best || floor.prefix.size() > best->prefix.size())) best = floor;
  return best;
}

bool IsSource(const fs::path& path) {
  const std::string extension = path.extension().string();
  return extension == ".h" || extension == ".cpp";
}

// The header a line includes with quotes (`#include "physics/..."`), or nothing.
std::optional<std::string> QuotedInclude(std::string_view line) {
  auto skip_blanks = [&] {
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
  };
  skip_blanks();
  if (!line.starts_with('#')) return std::nullopt;
  line.remove_prefix(1);
  skip_blanks();
  if (!line.starts_with("include")) return std::nullopt;
  line.remove_prefix(7);
  skip_blanks();
  if (!line.starts_with('"')) return std::nullopt;
  line.remove_prefix(1);
  const std::size_t end = line.find('"');
  if (end == std::string_view::npos) return std::nullopt;
  return std::string(line.substr(0, end));
}

struct Layering {
  std::vector<std::string> upward;     // "file:line: header (floor a above floor b)"
  std::vector<std::string> unfloored;  // source files no floor names
};

Layering CheckLayering(const fs::path& root) {
  Layering result;
  for (const std::string_view folder : kLayeredFolders) {
    if (!fs::exists(root / folder)) continue;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root / folder)) {
      if (!entry.is_regular_file() || !IsSource(entry.path())) continue;
      const std::string file = fs::relative(entry.path(), root).generic_string();
      const std::optional<Floor> own = FloorOf(file);
      if (!own) {
        result.unfloored.push_back(file);
        continue;
      }
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        const std::optional<std::string> header = QuotedInclude(line);
        if (!header) continue;
        const std::optional<Floor> included = FloorOf(*header);
        if (included && included->level > own->level)
          result.upward.push_back(file + ":" + std::to_string(number) + ": " + *header + " (" +
                                  std::string(included->prefix) + " above " + std::string(own->prefix) + ")");
      }
    }
  }
  return result;
}

std::string Lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

TEST(Layering, NoFileIncludesAHeaderFromAHigherFloor) {
  const Layering layering = CheckLayering(STRATA_SOURCE_DIR);
  EXPECT_TRUE(layering.upward.empty()) << Lines(layering.upward);
  EXPECT_TRUE(layering.unfloored.empty()) << "files in no floor (add their folder to kFloors):\n"
                                          << Lines(layering.unfloored);
}

TEST(Layering, APlantedUpwardIncludeIsFound) {
  const fs::path root = fs::temp_directory_path() / ("strata-layering-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "physics/shapes");
  fs::create_directories(root / "physics/world");
  fs::create_directories(root / "physics/gadgets");
  std::ofstream(root / "physics/shapes/Planted.h") << "#pragma once\n#include \"physics/math/Math.h\"\n"
                                                      "#include \"physics/world/PhysicsSystem.h\"\n";
  std::ofstream(root / "physics/world/Fine.cpp") << "#include \"physics/shapes/Planted.h\"\n";
  std::ofstream(root / "physics/gadgets/Loose.cpp") << "int x;\n";
  const Layering layering = CheckLayering(root);
  fs::remove_all(root);
  ASSERT_EQ(layering.upward.size(), 1u) << Lines(layering.upward);
  EXPECT_EQ(
      layering.upward[0],
      "physics/shapes/Planted.h:3: physics/world/PhysicsSystem.h (physics/world/ above physics/shapes/)");
  ASSERT_EQ(layering.unfloored.size(), 1u);
  EXPECT_EQ(layering.unfloored[0], "physics/gadgets/Loose.cpp");
}

}  // namespace
}  // namespace strata::test
