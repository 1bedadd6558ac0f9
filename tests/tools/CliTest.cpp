// The `strata` CLI as a user runs it: simulate writes JSON lines; a bad scene exits 2 and writes nothing.
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>

#include "CliRunner.h"

namespace strata::test {
namespace {

TEST(Cli, SimulateWarnsWhenVelocitiesWereClamped) {
  const auto scene = TempPath("clamped.json");
  std::ofstream(scene) << R"({"settings": {"gravity": [0, 0, 0]}, "bodies": [{"name": "b", "shape":
      {"type": "sphere", "radius": 0.5}, "linear_velocity": [50, 0, 0], "max_linear_velocity": 10}]})";
  // Standard error only: the warning names the limit to raise.
  auto errors_of = [](const std::string& arguments) {
    const auto captured = TempPath("stderr.txt");
    const int status = std::system(
        (std::string(STRATA_CLI) + " " + arguments + " > /dev/null 2> " + captured.string()).c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << arguments;
    std::ifstream file(captured);
    return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  };
  std::string errors = errors_of("simulate " + scene.string() + " --steps 3 --every 3");
  EXPECT_NE(errors.find("clamped to their limits 1 time(s) (linear)"), std::string::npos) << errors;
  errors = errors_of("simulate " + (kScenes / "bounce.json").string() + " --steps 3");
  EXPECT_EQ(errors.find("clamped"), std::string::npos) << errors;
  std::filesystem::remove(scene);
}

TEST(Cli, AccuracyWritesJsonMarkdownAndPlot) {
  const auto dir = TempPath("accuracy");
  std::string output;
  ASSERT_EQ(RunCliCapture("accuracy --quick --case free_fall --case fast_thin_wall --out-dir " + dir.string(),
                          output),
            0);
  const nlohmann::json json = ReadJson(dir / "accuracy.json");
  ASSERT_EQ(json["cases"].size(), 2u);
  std::set<std::string> engines;
  for (const auto& run : json["runs"]) {
    EXPECT_TRUE(run["finite"].get<bool>());
    EXPECT_TRUE(run["default"].get<bool>());
    if (run["engine"] == "strata") {
      EXPECT_TRUE(run["passed"].get<bool>()) << run.dump();
    }
    engines.insert(run["engine"].get<std::string>());
  }
  EXPECT_TRUE(engines.count("strata"));
  std::ifstream markdown(dir / "accuracy.md");
  const std::string table((std::istreambuf_iterator<char>(markdown)), std::istreambuf_iterator<char>());
  EXPECT_NE(table.find("## fast_thin_wall"), std::string::npos);
  std::ifstream png(dir / "accuracy.png", std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_EQ(RunCli("accuracy --quick --case no_such_case --out-dir " + dir.string()), 2);
  std::filesystem::remove_all(dir);
}

TEST(Cli, AccuracyRunsOnlyTheSettingsAsked) {
  const auto dir = TempPath("accuracy-settings");
  std::string output;
  ASSERT_EQ(RunCliCapture("accuracy --no-bullet --timing-runs 1 --case free_fall --setting \"dt1/30 sub1\" "
                          "--setting \"dt1/120 sub8\" --out-dir " +
                              dir.string(),
                          output),
            0);
  const nlohmann::json json = ReadJson(dir / "accuracy.json");
  std::multiset<std::string> settings;
  for (const auto& run : json["runs"]) settings.insert(run["setting"].get<std::string>());
  EXPECT_EQ(settings, (std::multiset<std::string>{"dt1/120 sub8", "dt1/30 sub1"}));
  EXPECT_EQ(RunCli("accuracy --no-bullet --setting \"dt1/7 sub1\" --out-dir " + dir.string()), 2);
  std::filesystem::remove_all(dir);
}

TEST(Cli, SimulateWritesOneLinePerRecordedStep) {
  const auto out = TempPath("states.jsonl");
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

TEST(Cli, SimulateWritesContactAndSensorEventsAsJsonLines) {
  const auto events = TempPath("events.jsonl");
  ASSERT_EQ(RunCli("simulate " + (kScenes / "playground.json").string() + " --steps 600 --events " +
                   events.string()),
            0);
  std::ifstream file(events);
  std::string line;
  std::map<std::string, int> kinds;
  std::map<std::string, int> touching;  // begins less ends, per pair
  int previous_step = 0;
  while (std::getline(file, line)) {
    const auto json = nlohmann::json::parse(line);
    const std::string kind = json["event"].get<std::string>();
    ++kinds[kind];
    EXPECT_GE(json["step"].get<int>(), previous_step);
    previous_step = json["step"].get<int>();
    if (kind.rfind("sensor", 0) == 0) {
      // The boulder rolls through the gate once.
      EXPECT_EQ(json["sensor"], "gate");
      EXPECT_EQ(json["visitor"], "boulder");
      continue;
    }
    // Only the balls ask for contact events; each pair begins, persists and ends in that order.
    EXPECT_EQ(json["body_b"].get<std::string>().rfind("ball", 0), 0u) << line;
    const std::string pair = json["body_a"].get<std::string>() + "/" + json["body_b"].get<std::string>();
    if (kind == "contact_end") {
      EXPECT_EQ(--touching[pair], 0) << line;
      continue;
    }
    EXPECT_EQ(json["normal"].size(), 3u);
    EXPECT_GE(json["points"].size(), 1u);
    EXPECT_LE(json["points"].size(), 4u);
    EXPECT_GE(json["normal_impulse"].get<double>(), 0.0);
    const int touches = kind == "contact_begin" ? ++touching[pair] : touching[pair];
    EXPECT_EQ(touches, 1) << line;
  }
  EXPECT_EQ(kinds["sensor_begin"], 1);
  EXPECT_EQ(kinds["sensor_end"], 1);
  EXPECT_GE(kinds["contact_begin"], 4);  // every ball lands, most bounce
  EXPECT_GT(kinds["contact_end"], 0);
  // The same file as --out is refused before anything runs.
  EXPECT_EQ(RunCli("simulate " + (kScenes / "playground.json").string() + " --steps 10 --events " +
                   events.string() + " --out " + events.string()),
            2);
  std::filesystem::remove(events);
}

TEST(Cli, SimulateWritesConstraintForcesWhenAsked) {
  const auto out = TempPath("joints.jsonl");
  ASSERT_EQ(RunCli("simulate " + (kScenes / "joints.json").string() +
                   " --steps 60 --every 60 --constraint-forces --out " + out.string()),
            0);
  std::ifstream file(out);
  std::string line;
  ASSERT_TRUE(std::getline(file, line));
  const auto json = nlohmann::json::parse(line);
  ASSERT_EQ(json["constraints"].size(), 9u);
  const auto& rod = json["constraints"][1];
  EXPECT_EQ(rod["name"], "pendulum_rod");
  EXPECT_EQ(rod["force"].size(), 3u);
  EXPECT_GT(rod["force"][1].get<float>(), 0.0f) << "the rod holds the bob up";
  EXPECT_FALSE(rod["broken"].get<bool>());
  std::filesystem::remove(out);
  // Without the flag the lines have no constraints, and a bad joint exits 2 naming its JSON path.
  ASSERT_EQ(RunCli("simulate " + (kScenes / "joints.json").string() + " --steps 1 --out " + out.string()), 0);
  std::ifstream plain(out);
  ASSERT_TRUE(std::getline(plain, line));
  EXPECT_FALSE(nlohmann::json::parse(line).contains("constraints"));
  std::filesystem::remove(out);
  const auto bad = TempPath("bad_joint.json");
  std::ofstream(bad) << R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}}],
                            "constraints": [{"type": "hinge", "body_b": "a", "limits": [10, 20]}]})";
  std::string errors;
  EXPECT_EQ(RunCliErrors("simulate " + bad.string() + " --steps 1", errors), 2);
  EXPECT_NE(errors.find("/constraints/0/limits"), std::string::npos) << errors;
  std::filesystem::remove(bad);
}

TEST(Cli, BadSceneExitsWithTwoAndWritesNothing) {
  const auto scene = TempPath("bad.json");
  std::ofstream(scene) << R"({"bodies": [{"shape": {"type": "sphere", "radius": -2}}]})";
  const auto out = TempPath("never.jsonl");
  EXPECT_EQ(RunCli("simulate " + scene.string() + " --steps 10 --out " + out.string()), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(RunCli("simulate " + TempPath("missing.json").string() + " --steps 10"), 2);
  EXPECT_EQ(RunCli("simulate"), 2);  // scene argument missing
  std::filesystem::remove(scene);
}

TEST(Cli, NavmeshBakeWritesSetObjAndReportThenPathQueriesIt) {
  const auto nav = TempPath("arena.bin"), obj = TempPath("arena.obj"), report = TempPath("arena.json");
  ASSERT_EQ(RunCli("navmesh bake " + (kLevels / "arena.glb").string() + " --out " + nav.string() + " --obj " +
                   obj.string() + " --json " + report.string()),
            0);
  const nlohmann::json json = ReadJson(report);
  EXPECT_EQ(json["tiles"].get<int>(), 4);
  EXPECT_GT(json["polygons"].get<int>(), 4);
  // 25.6 m square minus the agent radius at the edges and the pillars' footprints.
  EXPECT_GT(json["walkable_area_m2"].get<double>(), 500.0);
  EXPECT_LT(json["walkable_area_m2"].get<double>(), 25.6 * 25.6);
  // The report carries the per-tile split (speed itself is bench-navmesh's business, not a test's).
  for (const char* part : {"gather", "recast", "total"})
    for (const char* figure : {"median", "max"})
      EXPECT_TRUE(json["build_ms"][part][figure].is_number()) << part;
  EXPECT_GT(std::filesystem::file_size(obj), 100u);

  std::string output;
  ASSERT_EQ(RunCliCapture("navmesh path " + nav.string() + " --from 2,0,2 --to 23,0,23 --json", output), 0);
  const auto path = nlohmann::json::parse(output);
  EXPECT_TRUE(path["found"].get<bool>());
  EXPECT_TRUE(path["reached_end"].get<bool>());
  EXPECT_GE(path["length"].get<float>(), std::hypot(21.0f, 21.0f) - 0.1f);
  const auto last = path["points"].back();
  EXPECT_NEAR(last[0].get<float>(), 23.0f, 0.5f);
  EXPECT_NEAR(last[2].get<float>(), 23.0f, 0.5f);
  // Off the navmesh at the far end: found, not reached, and a warning on standard error says why.
  const auto errors = TempPath("path_errors.txt");
  ASSERT_EQ(
      RunCliCapture(
          "navmesh path " + nav.string() + " --from 2,0,2 --to 60,0,60 --json 2> " + errors.string(), output),
      0);
  EXPECT_FALSE(nlohmann::json::parse(output)["reached_end"].get<bool>());
  std::ifstream error_file(errors);
  const std::string warning((std::istreambuf_iterator<char>(error_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(warning.find("--to 60,0,60 is not on or near the navmesh"), std::string::npos) << warning;
  ASSERT_EQ(RunCliCapture("navmesh path " + nav.string() + " --from 2,0,2 --to 23,0,23 2> " + errors.string(),
                          output),
            0);
  EXPECT_EQ(std::filesystem::file_size(errors), 0u);  // no warning for a path that arrives
}

TEST(Cli, NavmeshBakeAndPathTakeAProfile) {
  const auto person = TempPath("arena_person.bin"), machine = TempPath("arena_machine.bin");
  const auto report = TempPath("arena_person.json"), errors = TempPath("profile_errors.txt");
  const auto never = TempPath("never.bin");
  std::filesystem::remove(never);  // one left by an earlier process with the same id would spoil the check
  const std::string level = (kLevels / "arena.glb").string();
  ASSERT_EQ(RunCli("navmesh bake " + level + " --profile person --out " + person.string() + " --json " +
                   report.string()),
            0);
  ASSERT_EQ(RunCli("navmesh bake " + level + " --profile machine --out " + machine.string()), 0);
  const nlohmann::json json = ReadJson(report);
  EXPECT_EQ(json["profile"].get<std::string>(), "person");
  EXPECT_FLOAT_EQ(json["settings"]["agent_radius"].get<float>(), 0.4f);
  std::string output;
  ASSERT_EQ(
      RunCliCapture("navmesh path " + person.string() + " --profile person --from 2,0,2 --to 23,0,23 --json",
                    output),
      0);
  EXPECT_EQ(nlohmann::json::parse(output)["profile"].get<std::string>(), "person");
  EXPECT_TRUE(nlohmann::json::parse(output)["reached_end"].get<bool>());
  // The machine's set, read for a person, is refused by name; so is a profile given with an agent option.
  std::string message;
  EXPECT_EQ(RunCliErrors("navmesh path " + machine.string() + " --profile person --from 2,0,2 --to 23,0,23",
                         message),
            2);
  EXPECT_NE(message.find("baked for profile 'machine', not 'person'"), std::string::npos) << message;
  EXPECT_EQ(
      RunCliErrors("navmesh bake " + level + " --profile person --agent-radius 0.3 --out " + never.string(),
                   message),
      2);
  EXPECT_NE(message.find("give --profile or --agent-radius, not both"), std::string::npos) << message;
  EXPECT_EQ(RunCli("navmesh bake " + level + " --profile thunderjaw --out " + never.string()), 2);
  EXPECT_FALSE(std::filesystem::exists(never));
}

TEST(Cli, NavmeshBadInputExitsWithTwo) {
  const auto nav = TempPath("bad.bin");
  std::filesystem::remove(nav);  // one left by an earlier process with the same id would pass for a new one
  EXPECT_EQ(RunCli("navmesh bake " + TempPath("missing.obj").string() + " --out " + nav.string()), 2);
  EXPECT_EQ(RunCli("navmesh bake " + (kLevels / "arena.glb").string() + " --out " + nav.string() +
                   " --max-slope 120"),
            2);
  EXPECT_FALSE(std::filesystem::exists(nav));
  std::ofstream(nav) << "not a navmesh";
  EXPECT_EQ(RunCli("navmesh path " + nav.string() + " --from 0,0,0 --to 1,0,1"), 2);
  ASSERT_EQ(RunCli("navmesh bake " + (kLevels / "arena.glb").string() + " --out " + nav.string()), 0);
  EXPECT_EQ(RunCli("navmesh path " + nav.string() + " --from 0,0 --to 1,0,1"), 2);
  EXPECT_EQ(RunCli("navmesh path " + nav.string() + " --from 0,nan,0 --to 1,0,1"), 2);
}

// Every input that is not a regular file is refused at once (exit 2), never read: a directory used to abort
// the process, /dev/zero and a pipe with no writer used to hang it. `timeout` turns a hang into a failure.
TEST(Cli, InputsThatAreNotRegularFilesExitTwoAtOnce) {
  const auto fifo = TempPath("fifo"), never = TempPath("never.bin");
  std::filesystem::remove(fifo);  // left by an earlier process with the same id
  std::filesystem::remove(never);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string directory = std::filesystem::temp_directory_path().string();
  for (const std::string& input : {directory, std::string("/dev/zero"), fifo.string()}) {
    EXPECT_EQ(RunCli("simulate " + input + " --steps 1"), 2) << input;
    EXPECT_EQ(RunCli("navmesh path " + input + " --from 1,0,1 --to 2,0,2"), 2) << input;
    EXPECT_EQ(RunCli("navmesh bake " + input + " --out " + never.string()), 2) << input;
  }
  EXPECT_FALSE(std::filesystem::exists(never));
  std::filesystem::remove(fifo);
}

// A regression that allocated for what a corrupt file declares would fail fast under a 4 GB address space
// instead of swapping; AddressSanitizer reserves terabytes of shadow memory up front, so not under it.
#if defined(__SANITIZE_ADDRESS__)
constexpr const char* kAddressSpaceLimit = "";
#else
constexpr const char* kAddressSpaceLimit = "ulimit -v 4000000; ";
#endif

// Counts that a file cannot back and coordinates that make a level astronomically large are refused before
// anything is allocated for them (a 227-byte PLY declaring 1e9 vertices took 11-23 GB; one flipped byte in
// arena.glb put a vertex 3e16 m away and the tile list ran out of memory).
TEST(Cli, CorruptCountsAndCoordinatesAreRefusedBeforeAllocating) {
  const auto ply = TempPath("huge.ply");
  std::ofstream(ply)
      << "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n3 0 0 0\n";
  std::string errors;
  const auto stderr_of = [&](const std::string& arguments) {
    const auto captured = TempPath("stderr.txt");
    const int status = std::system((std::string(kAddressSpaceLimit) + STRATA_CLI + " " + arguments +
                                    " > /dev/null 2> " + captured.string())
                                       .c_str());
    std::ifstream file(captured);
    errors.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(stderr_of("navmesh bake " + ply.string() + " --out " + TempPath("ply.bin").string()), 2);
  EXPECT_NE(errors.find("declares 1000000000 entries"), std::string::npos) << errors;
  const auto glb = TempPath("flipped.glb");
  std::filesystem::copy_file(kLevels / "arena.glb", glb, std::filesystem::copy_options::overwrite_existing);
  {
    std::fstream file(glb, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(919);
    file.put(static_cast<char>(0xDA));  // a vertex's exponent byte: 7.5 becomes -3.4e16
  }
  EXPECT_EQ(stderr_of("navmesh bake " + glb.string() + " --out " + TempPath("glb.bin").string()), 2);
  EXPECT_NE(errors.find("x 3.378e+16 m"), std::string::npos) << errors;
  EXPECT_NE(errors.find("more than a navmesh holds"), std::string::npos) << errors;
  EXPECT_EQ(stderr_of("demo " + glb.string() + " --steps 10 --out-dir " + TempPath("demo").string()), 2);
  EXPECT_NE(errors.find("x 3.378e+16 m"), std::string::npos) << errors;
  std::filesystem::remove(ply);
  std::filesystem::remove(glb);
}

// A write that fails is an error (exit 2), and --out is replaced only once the run has written all of it.
TEST(Cli, FailedWritesExitTwoAndOutputsAreReplacedWhole) {
  const std::string scene = (kScenes / "stack.json").string();
  EXPECT_EQ(RunCli("simulate " + scene + " --steps 5 --out /dev/full"), 2);
  EXPECT_EQ(RunCli("navmesh bake " + (kLevels / "arena.glb").string() + " --out " +
                   TempPath("a.bin").string() + " --report /dev/full"),
            2);
  const auto out = TempPath("replaced.jsonl");
  std::ofstream(out) << "old\n";
  // (A run that stops before its end leaves the old file whole: OutputFile's tests.)
  ASSERT_EQ(RunCli("simulate " + scene + " --steps 5 --out " + out.string()), 0);
  std::ifstream replaced(out);
  std::string first;
  std::getline(replaced, first);
  EXPECT_NE(first, "old");
  EXPECT_FALSE(std::filesystem::exists(out.string() + ".tmp"));
  std::filesystem::remove(out);
  std::filesystem::remove(TempPath("a.bin"));
}

// Options out of range (NaN included: CLI11's own checks let it through) and an --out-dir that cannot be
// made are refused before the run; crates beyond the old fixed body table are all added, not capped.
TEST(Cli, BundledLevelsAreWhatTheGeneratorWrites) {
  const auto out = TempPath("levels");
  ASSERT_EQ(RunCli("level generate --out " + out.string()), 0);
  for (const char* name : {"courtyard.obj", "courtyard_zup.obj", "arena.glb"}) {
    std::ifstream generated(out / name, std::ios::binary), bundled(kLevels / name, std::ios::binary);
    const std::string a((std::istreambuf_iterator<char>(generated)), std::istreambuf_iterator<char>());
    const std::string b((std::istreambuf_iterator<char>(bundled)), std::istreambuf_iterator<char>());
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, b) << name << " is out of date: run `strata level generate`";
  }
}

}  // namespace
}  // namespace strata::test
