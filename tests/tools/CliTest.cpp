// The `strata` CLI as a user runs it: simulate writes JSON lines; a bad scene exits 2 and writes nothing.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace strata::test {
namespace {

const std::filesystem::path kScenes = STRATA_SCENES_DIR;

int RunCli(const std::string& arguments) {
  const int status = std::system((std::string(STRATA_CLI) + " " + arguments + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::filesystem::path TempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("strata_cli_test_" + std::to_string(::getpid()) + "_" + name);
}

TEST(Cli, SimulateWritesOneLinePerRecordedStep) {
  const auto out = TempFile("states.jsonl");
  ASSERT_EQ(RunCli("simulate " + (kScenes / "bounce.json").string() + " --steps 120 --every 30 --out " +
                   out.string()),
            0);
  std::ifstream file(out);
  std::string line;
  int lines = 0;
  float last_time = 0.0f;
  while (std::getline(file, line)) {
    const auto json = nlohmann::json::parse(line);
    EXPECT_EQ(json["step"].get<int>(), 30 * (lines + 1));
    last_time = json["time"].get<float>();
    ASSERT_EQ(json["bodies"].size(), 2u);
    EXPECT_EQ(json["bodies"][1]["name"], "ball");
    EXPECT_EQ(json["bodies"][1]["position"].size(), 3u);
    EXPECT_EQ(json["bodies"][1]["rotation"].size(), 4u);
    EXPECT_TRUE(json["bodies"][1].contains("sleeping"));
    ++lines;
  }
  EXPECT_EQ(lines, 4);
  EXPECT_NEAR(last_time, 2.0f, 1e-4f);
  std::filesystem::remove(out);
}

TEST(Cli, BadSceneExitsWithTwoAndWritesNothing) {
  const auto scene = TempFile("bad.json");
  std::ofstream(scene) << R"({"bodies": [{"shape": {"type": "sphere", "radius": -2}}]})";
  const auto out = TempFile("never.jsonl");
  EXPECT_EQ(RunCli("simulate " + scene.string() + " --steps 10 --out " + out.string()), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(RunCli("simulate " + TempFile("missing.json").string() + " --steps 10"), 2);
  EXPECT_EQ(RunCli("simulate"), 2);  // scene argument missing
  std::filesystem::remove(scene);
}

}  // namespace
}  // namespace strata::test
