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

namespace strata::test {
namespace {

const std::filesystem::path kScenes = STRATA_SCENES_DIR;
const std::filesystem::path kLevels = STRATA_LEVELS_DIR;

/// Runs the CLI with stdout captured into `output`.
int RunCliCapture(const std::string& arguments, std::string& output) {
  const std::filesystem::path captured =
      std::filesystem::temp_directory_path() / ("strata_cli_capture_" + std::to_string(::getpid()));
  const int status =
      std::system((std::string(STRATA_CLI) + " " + arguments + " > " + captured.string()).c_str());
  std::ifstream file(captured);
  output.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Runs the CLI with standard output discarded; `errors` gets what it wrote to standard error.
int RunCliErrors(const std::string& arguments, std::string& errors) {
  const std::filesystem::path captured =
      std::filesystem::temp_directory_path() / ("strata_cli_errors_" + std::to_string(::getpid()));
  const int status = std::system(
      (std::string(STRATA_CLI) + " " + arguments + " > /dev/null 2> " + captured.string()).c_str());
  std::ifstream file(captured);
  errors.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int RunCli(const std::string& arguments) {
  const int status = std::system((std::string(STRATA_CLI) + " " + arguments + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::filesystem::path TempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("strata_cli_test_" + std::to_string(::getpid()) + "_" + name);
}

nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream file(path);
  return nlohmann::json::parse(file);
}

TEST(Cli, SimulateWarnsWhenVelocitiesWereClamped) {
  const auto scene = TempFile("clamped.json");
  std::ofstream(scene) << R"({"settings": {"gravity": [0, 0, 0]}, "bodies": [{"name": "b", "shape":
      {"type": "sphere", "radius": 0.5}, "linear_velocity": [50, 0, 0], "max_linear_velocity": 10}]})";
  // Standard error only: the warning names the limit to raise.
  auto errors_of = [](const std::string& arguments) {
    const auto captured = TempFile("stderr.txt");
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
  const auto dir = TempFile("accuracy");
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
  const auto dir = TempFile("accuracy-settings");
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

TEST(Cli, SimulateWritesContactAndSensorEventsAsJsonLines) {
  const auto events = TempFile("events.jsonl");
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
  const auto out = TempFile("joints.jsonl");
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
  const auto bad = TempFile("bad_joint.json");
  std::ofstream(bad) << R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}}],
                            "constraints": [{"type": "hinge", "body_b": "a", "limits": [10, 20]}]})";
  std::string errors;
  EXPECT_EQ(RunCliErrors("simulate " + bad.string() + " --steps 1", errors), 2);
  EXPECT_NE(errors.find("/constraints/0/limits"), std::string::npos) << errors;
  std::filesystem::remove(bad);
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

TEST(Cli, NavmeshBakeWritesSetObjAndReportThenPathQueriesIt) {
  const auto nav = TempFile("arena.bin"), obj = TempFile("arena.obj"), report = TempFile("arena.json");
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
  const auto errors = TempFile("path_errors.txt");
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

TEST(Cli, NavmeshBadInputExitsWithTwo) {
  const auto nav = TempFile("bad.bin");
  EXPECT_EQ(RunCli("navmesh bake " + TempFile("missing.obj").string() + " --out " + nav.string()), 2);
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
  const auto fifo = TempFile("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string directory = std::filesystem::temp_directory_path().string();
  for (const std::string& input : {directory, std::string("/dev/zero"), fifo.string()}) {
    EXPECT_EQ(RunCli("simulate " + input + " --steps 1"), 2) << input;
    EXPECT_EQ(RunCli("navmesh path " + input + " --from 1,0,1 --to 2,0,2"), 2) << input;
    EXPECT_EQ(RunCli("navmesh bake " + input + " --out " + TempFile("never.bin").string()), 2) << input;
  }
  EXPECT_FALSE(std::filesystem::exists(TempFile("never.bin")));
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
  const auto ply = TempFile("huge.ply");
  std::ofstream(ply)
      << "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n3 0 0 0\n";
  std::string errors;
  const auto stderr_of = [&](const std::string& arguments) {
    const auto captured = TempFile("stderr.txt");
    const int status = std::system((std::string(kAddressSpaceLimit) + STRATA_CLI + " " + arguments +
                                    " > /dev/null 2> " + captured.string())
                                       .c_str());
    std::ifstream file(captured);
    errors.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(stderr_of("navmesh bake " + ply.string() + " --out " + TempFile("ply.bin").string()), 2);
  EXPECT_NE(errors.find("declares 1000000000 entries"), std::string::npos) << errors;
  const auto glb = TempFile("flipped.glb");
  std::filesystem::copy_file(kLevels / "arena.glb", glb, std::filesystem::copy_options::overwrite_existing);
  {
    std::fstream file(glb, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(919);
    file.put(static_cast<char>(0xDA));  // a vertex's exponent byte: 7.5 becomes -3.4e16
  }
  EXPECT_EQ(stderr_of("navmesh bake " + glb.string() + " --out " + TempFile("glb.bin").string()), 2);
  EXPECT_NE(errors.find("x 3.378e+16 m"), std::string::npos) << errors;
  EXPECT_NE(errors.find("more than a navmesh holds"), std::string::npos) << errors;
  EXPECT_EQ(stderr_of("demo " + glb.string() + " --steps 10 --out-dir " + TempFile("demo").string()), 2);
  EXPECT_NE(errors.find("x 3.378e+16 m"), std::string::npos) << errors;
  std::filesystem::remove(ply);
  std::filesystem::remove(glb);
}

// A write that fails is an error (exit 2), and --out is replaced only once the run has written all of it.
TEST(Cli, FailedWritesExitTwoAndOutputsAreReplacedWhole) {
  const std::string scene = (kScenes / "stack.json").string();
  EXPECT_EQ(RunCli("simulate " + scene + " --steps 5 --out /dev/full"), 2);
  EXPECT_EQ(RunCli("navmesh bake " + (kLevels / "arena.glb").string() + " --out " +
                   TempFile("a.bin").string() + " --report /dev/full"),
            2);
  const auto out = TempFile("replaced.jsonl");
  std::ofstream(out) << "old\n";
  // (A run that stops before its end leaves the old file whole: OutputFile's tests.)
  ASSERT_EQ(RunCli("simulate " + scene + " --steps 5 --out " + out.string()), 0);
  std::ifstream replaced(out);
  std::string first;
  std::getline(replaced, first);
  EXPECT_NE(first, "old");
  EXPECT_FALSE(std::filesystem::exists(out.string() + ".tmp"));
  std::filesystem::remove(out);
  std::filesystem::remove(TempFile("a.bin"));
}

// Options out of range (NaN included: CLI11's own checks let it through) and an --out-dir that cannot be
// made are refused before the run; crates beyond the old fixed body table are all added, not capped.
TEST(Cli, DemoRefusesBadOptionsBeforeRunningAndAddsEveryCrate) {
  const auto out_dir = TempFile("demo_out");
  for (const char* bad :
       {"--steps -1", "--steps 0", "--crates -1", "--request-radius nan", "--request-radius -3",
        "--agents 100000", "--threads 0", "--player-route 1,2,3", "--player-route 33,45",
        "--player-route 1,nan,3,4", "--player-speed 0", "--player-speed 51"})
    EXPECT_EQ(RunCli("demo --out-dir " + out_dir.string() + " " + std::string(bad)), 2) << bad;
  const auto file = TempFile("a_file");
  std::ofstream(file) << "x";
  EXPECT_EQ(RunCli("demo --steps 5 --out-dir " + (file / "pictures").string()), 2);
  std::string output;
  ASSERT_EQ(RunCliCapture("demo --steps 2 --crates 20000 --out-dir " + out_dir.string(), output), 0);
  const std::size_t bodies_at = output.find(" bodies, ");
  ASSERT_NE(bodies_at, std::string::npos) << output;
  const std::size_t line_start = output.rfind('\n', bodies_at) + 1;  // 0 when it is the first line
  EXPECT_GE(std::stoi(output.substr(line_start, bodies_at - line_start)), 20000) << output;
  std::filesystem::remove(file);
  std::filesystem::remove_all(out_dir);
}

TEST(Cli, DemoBuildsTilesWhileSteppingAndWritesPictures) {
  const auto out = TempFile("demo");
  std::string output;
  ASSERT_EQ(
      RunCliCapture("demo --steps 120 --crates 40 --boulders 2 --agents 3 --out-dir " + out.string(), output),
      0)
      << output;
  EXPECT_NE(output.find("longest frame"), std::string::npos);
  EXPECT_NE(output.find("0 failures"), std::string::npos) << output;
  std::ifstream png(out / "navmesh.png", std::ios::binary);
  char signature[8] = {};
  png.read(signature, 8);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  EXPECT_GT(std::filesystem::file_size(out / "navmesh.obj"), 1000u);
  // The same scene as glTF: the level, the navmesh by island (a colour per island) and the paths as lines.
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile((out / "scene.glb").string(), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  std::map<std::string, const aiMesh*> meshes;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i)
    meshes[scene->mMeshes[i]->mName.C_Str()] = scene->mMeshes[i];
  ASSERT_TRUE(meshes.contains("level") && meshes.contains("navmesh") && meshes.contains("paths"));
  EXPECT_GT(meshes["level"]->mNumFaces, 100u);
  const aiMesh& navmesh = *meshes["navmesh"];
  EXPECT_GT(navmesh.mNumFaces, 50u);
  ASSERT_NE(navmesh.mColors[0], nullptr);
  std::set<std::tuple<float, float, float>> colours;
  for (unsigned v = 0; v < navmesh.mNumVertices; ++v)
    colours.insert({navmesh.mColors[0][v].r, navmesh.mColors[0][v].g, navmesh.mColors[0][v].b});
  const auto islands_at = output.find("m^2 walkable, ");  // "... m^2 walkable, N islands"
  ASSERT_NE(islands_at, std::string::npos);
  const int islands = std::stoi(output.substr(islands_at + std::string("m^2 walkable, ").size()));
  EXPECT_EQ(static_cast<int>(colours.size()), islands) << "a colour per island";
  EXPECT_EQ(meshes["paths"]->mPrimitiveTypes, static_cast<unsigned>(aiPrimitiveType_LINE));
  EXPECT_GT(meshes["paths"]->mNumFaces, 0u);
}

TEST(Cli, DemoPlayerWalksTheCourtyardTourUpTheStairsAndOverTheBridge) {
  const auto out = TempFile("demo_player");
  std::string output;
  ASSERT_EQ(RunCliCapture("demo --out-dir " + out.string(), output), 0) << output;
  const auto at = output.find("player: reached ");
  ASSERT_NE(at, std::string::npos) << output;
  int reached = 0, waypoints = 0;
  float x = 0, y = 0, z = 0, walked = 0, highest = 0;
  ASSERT_EQ(
      std::sscanf(output.c_str() + at,
                  "player: reached %d of %d waypoints (the last at %*f s), ended at (%f, %f, %f) after %f m, "
                  "up to %f m",
                  &reached, &waypoints, &x, &y, &z, &walked, &highest),
      7)
      << output.substr(at, 300);
  EXPECT_EQ(reached, waypoints);
  EXPECT_NEAR(highest, 3.0f, 0.05f);  // on the platform, up the stairs
  EXPECT_GT(x, 50.0f);                // across the trench, over the bridge (x 38-50)
  EXPECT_NEAR(y, 0.0f, 0.05f);
  EXPECT_GT(walked, 60.0f);
  std::filesystem::remove_all(out);
}

TEST(Cli, DemoOnTheSmallArenaGivesEveryAgentANavmesh) {
  // The arena is four tiles; each agent asks for the tiles 16 m around it, which reach off the level. That
  // request was once refused as "more tiles than max_tiles", silently: no tile, every agent "no navmesh",
  // exit code 0.
  const auto out = TempFile("demo_arena");
  std::string output;
  ASSERT_EQ(RunCliCapture(std::string("demo ") + STRATA_LEVELS_DIR +
                              "/arena.glb --steps 60 --crates 0 "
                              "--boulders 0 --agents 4 --out-dir " +
                              out.string(),
                          output),
            0)
      << output;
  EXPECT_EQ(output.find("no navmesh"), std::string::npos) << output;
  EXPECT_NE(output.find("0 failures"), std::string::npos) << output;
  EXPECT_EQ(output.find("navmesh: 0 tiles"), std::string::npos) << output;
  std::filesystem::remove_all(out);
}

TEST(Cli, DemoFailsWhenItsNavmeshCannotBeBuilt) {
  // A level of walls only: nothing to walk on. The demo runs, says why, and exits non-zero.
  const auto level = TempFile("walls.obj");
  std::ofstream(level) << "v 0 0 0\nv 20 0 0\nv 20 10 0\nv 0 10 0\nv 0 0 20\nv 0 10 20\n"
                          "f 1 2 3\nf 1 3 4\nf 1 4 6\nf 1 6 5\n";
  const auto out = TempFile("demo_walls");
  std::string output;
  EXPECT_EQ(RunCliErrors("demo " + level.string() +
                             " --steps 10 --crates 0 --boulders 0 --agents 2 --out-dir " + out.string(),
                         output),
            1)
      << output;
  EXPECT_NE(output.find("navmesh could not be built"), std::string::npos) << output;
  std::filesystem::remove(level);
  std::filesystem::remove_all(out);
}

TEST(Cli, DemoOnAFloorWithOneFarTriangleStaysSmallAndFindsTheFloor) {
  // A 30 m floor and one triangle 3 km away: the level's bounds are 3 km wide. The picture once took the
  // bounds at 8 pixels a metre (tens of GB for such levels), and agents placed at random in the bounds
  // never landed on the floor.
  const auto level = TempFile("far_triangle.obj");
  std::ofstream(level) << "v 0 0 0\nv 30 0 0\nv 30 0 30\nv 0 0 30\nv 3000 0 3000\nv 3001 0 3000\n"
                          "v 3001 0 3001\nf 1 3 2\nf 1 4 3\nf 5 7 6\n";
  const auto out = TempFile("demo_far");
  std::string output;
  ASSERT_EQ(RunCliCapture("demo " + level.string() +
                              " --steps 30 --crates 0 --boulders 0 --agents 3 --out-dir " + out.string(),
                          output),
            0)
      << output;
  EXPECT_EQ(output.find("no navmesh"), std::string::npos) << output;
  std::ifstream png(out / "navmesh.png", std::ios::binary);
  unsigned char header[24] = {};
  png.read(reinterpret_cast<char*>(header), sizeof(header));
  const auto big_endian = [&](int at) {
    return (header[at] << 24) | (header[at + 1] << 16) | (header[at + 2] << 8) | header[at + 3];
  };
  EXPECT_GT(big_endian(16), 0);
  EXPECT_LE(big_endian(16), 4096);  // width
  EXPECT_LE(big_endian(20), 4096);  // height
  std::filesystem::remove(level);
  std::filesystem::remove_all(out);
}

TEST(Cli, BenchSweepsThreadCountsAndWritesJson) {
  const std::filesystem::path json = TempFile("bench.json");
  std::string output;
  ASSERT_EQ(RunCliCapture("bench --steps 12 --threads 1,2 --no-bullet --json " + json.string(), output), 0);
  EXPECT_NE(output.find("where a step goes"), std::string::npos);
  EXPECT_NE(output.find("serial stages"), std::string::npos);
  const nlohmann::json document = ReadJson(json);
  ASSERT_EQ(document["scenes"].size(), 4u);  // pyramid, convex_vs_mesh, ragdolls, chains
  for (const auto& scene : document["scenes"]) {
    const auto& runs = scene["strata"];
    ASSERT_EQ(runs.size(), 2u);
    EXPECT_EQ(runs[0]["threads"], 1);
    EXPECT_EQ(runs[1]["threads"], 2);
    // The same inputs give the same result whatever the thread count.
    EXPECT_EQ(runs[0]["state_hash"], runs[1]["state_hash"]) << scene["name"];
    EXPECT_DOUBLE_EQ(runs[0]["speedup"].get<double>(), 1.0);
    ASSERT_GE(runs[0]["stages"].size(), 6u);
    std::set<std::string> names;
    for (const auto& stage : runs[0]["stages"]) {
      EXPECT_TRUE(names.insert(stage["name"].get<std::string>()).second) << "stage listed twice";
      EXPECT_GE(stage["jobs"].get<int>(), 1);
      EXPECT_TRUE(stage["wall_ms"].is_number());
    }
    EXPECT_FALSE(names.count(""));
  }
  std::filesystem::remove(json);
  // Bad options are refused before anything runs.
  EXPECT_EQ(RunCli("bench --steps 2 --threads 0"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --threads 1,x"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --job-system fibers"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --json " + (TempFile("no-such-dir") / "bench.json").string()), 2);
}

TEST(Cli, ShardedBakeMergesIntoTheFileOfOneBake) {
  const std::string level = (kLevels / "courtyard.obj").string();
  const auto whole = TempFile("whole.bin"), merged = TempFile("merged.bin");
  ASSERT_EQ(RunCli("navmesh bake " + level + " --out " + whole.string()), 0);
  std::string shards;
  for (int k = 0; k < 3; ++k) {
    const auto shard = TempFile("courtyard-" + std::to_string(k) + ".bin");
    ASSERT_EQ(RunCli("navmesh bake " + level + " --threads 1 --shard " + std::to_string(k) + "/3 --out " +
                     shard.string()),
              0);
    shards += " " + shard.string();
  }
  ASSERT_EQ(RunCli("navmesh merge" + shards + " --out " + merged.string()), 0);
  std::ifstream a(whole, std::ios::binary), b(merged, std::ios::binary);
  const std::string whole_bytes{std::istreambuf_iterator<char>(a), {}},
      merged_bytes{std::istreambuf_iterator<char>(b), {}};
  EXPECT_EQ(whole_bytes, merged_bytes);
  for (const char* bad : {"3/3", "x/2", "1/0", "-1/2", "1/2/3"})
    EXPECT_EQ(RunCli("navmesh bake " + level + " --shard " + bad + " --out " + TempFile("bad.bin").string()),
              2)
        << bad;
  EXPECT_EQ(RunCli("navmesh merge" + shards + shards + " --out " + merged.string()), 2) << "a tile twice";
}

TEST(Cli, LongCommandsShowABarOnATerminalAndOneSummaryLineOtherwise) {
  const std::string level = (kLevels / "courtyard.obj").string();
  const std::string bake = "navmesh bake " + level + " --out " + TempFile("progress.bin").string();
  std::string errors;
  ASSERT_EQ(RunCliErrors(bake, errors), 0) << errors;
  EXPECT_EQ(errors.rfind("strata navmesh bake: ", 0), 0u) << errors;
  EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 1) << errors;
  EXPECT_EQ(errors.find('\r'), std::string::npos) << errors;
  ASSERT_EQ(RunCliErrors("simulate " + (kScenes / "bounce.json").string() + " --steps 30 --out " +
                             TempFile("progress.jsonl").string(),
                         errors),
            0);
  EXPECT_EQ(errors.rfind("strata simulate: 30 steps", 0), 0u) << errors;

  // On a terminal (util-linux `script` gives the command one) the bar is drawn, then the summary.
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` here";
  const std::filesystem::path typescript = TempFile("progress-terminal.txt");
  const std::string command = "script -qec '" + std::string(STRATA_CLI) + " " + bake + "' /dev/null > " +
                              typescript.string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream file(typescript);
  const std::string screen((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::size_t bar = screen.find("strata navmesh bake [");
  ASSERT_NE(bar, std::string::npos) << screen;
  EXPECT_NE(screen.find(" tiles, ", bar), std::string::npos) << screen;
  EXPECT_GT(screen.find("strata navmesh bake: "), bar) << screen;
}

TEST(Cli, GameplayBenchWritesItsFiguresAsJson) {
  const std::filesystem::path json = TempFile("gameplay.json");
  ASSERT_EQ(RunCli("bench-gameplay --bodies 2000 --tiles 4 --casts 300 --repeats 1 --event-steps 5 "
                   "--event-rounds 1 --walkers 3 --frames 20 --json " +
                   json.string()),
            0);
  const nlohmann::json figures = ReadJson(json);
  const auto is_figure = [](const nlohmann::json& value) {
    return value.is_number() && std::isfinite(value.get<double>());
  };
  ASSERT_EQ(figures["casts"].size(), 2u);  // a sphere and a capsule
  for (const auto& row : figures["casts"]) {
    EXPECT_GT(row["exact_hits"].get<int>(), 0);
    const nlohmann::json& strata = row["engines"][0];
    EXPECT_EQ(strata["engine"], "strata");
    EXPECT_TRUE(is_figure(strata["casts_per_second"]));
    // Every exact hit found, none made up, each within the cast's 0.1 mm tolerance of touching.
    EXPECT_EQ(strata["missed"].get<int>(), 0);
    EXPECT_EQ(strata["false_hits"].get<int>(), 0);
    EXPECT_EQ(strata["hits"].get<int>(), row["exact_hits"].get<int>());
    EXPECT_LE(strata["widest_gap_mm"].get<double>(), 0.11);
    EXPECT_LE(strata["deepest_overlap_mm"].get<double>(), 0.1);
    EXPECT_TRUE(is_figure(strata["mean_abs_mm"]));
#ifdef STRATA_HAVE_BULLET
    ASSERT_EQ(row["engines"].size(), 2u);
    EXPECT_EQ(row["engines"][1]["engine"], "bullet");
    EXPECT_TRUE(is_figure(row["engines"][1]["casts_per_second"]));
    EXPECT_GT(row["engines"][1]["hits"].get<int>(), 0);
#endif
  }
  ASSERT_EQ(figures["events"].size(), 1u);
  EXPECT_GT(figures["events"][0]["events_per_step"].get<double>(),
            1000.0);  // every box of the pyramid reports
  // Times are printed figures, not targets: here only that each was measured and written.
  for (const char* key : {"quiet_step_ms", "reporting_step_ms"})
    EXPECT_TRUE(is_figure(figures["events"][0][key])) << key;
  EXPECT_EQ(figures["character"]["updates"].get<int>(), 60);
  EXPECT_TRUE(is_figure(figures["character"]["mean_us"]));
  std::filesystem::remove(json);
}

TEST(Cli, GameplayBenchRefusesALevelThatDoesNotLoadBeforeItsLongParts) {
  const std::filesystem::path json = TempFile("gameplay-bad-level.json"), level = TempFile("two-lines.obj");
  std::ofstream(level) << "v 1 2\nf 1 2 3\n";
  for (const std::string& path : {level.string(), std::string("/no/such/level.obj")}) {
    std::string errors;
    EXPECT_EQ(RunCliErrors("bench-gameplay --level " + path + " --json " + json.string(), errors), 2) << path;
    EXPECT_NE(errors.find("--level " + path), std::string::npos) << errors;
    EXPECT_FALSE(std::filesystem::exists(json));
  }
  std::filesystem::remove(level);
}

TEST(Cli, BroadPhaseAndNavmeshBenchesWriteTheirFiguresAsJson) {
  const std::filesystem::path broad = TempFile("broadphase.json"), nav = TempFile("navmesh-bench.json");
  ASSERT_EQ(RunCli("bench-broadphase --bodies 2000 --tiles 4 --queries 200 --frames 3 --max-threads 2 "
                   "--no-bullet --json " +
                   broad.string()),
            0);
  const nlohmann::json broad_json = ReadJson(broad);
  // What was measured is the benchmarks' to print; the file must hold every figure, as a number.
  const auto is_figure = [](const nlohmann::json& value) {
    return value.is_number() && std::isfinite(value.get<double>());
  };
  EXPECT_EQ(broad_json["bodies"].get<int>(), 2000);
  for (const char* key :
       {"aabb_query_us", "ray_10m_us", "ray_100m_us", "move_us", "full_rebuild_ms", "hits_per_block"})
    EXPECT_TRUE(is_figure(broad_json["strata"][key])) << key;
  // Threads 1 and 2, 1 and 32 mutexes, without and with per-object logic.
  ASSERT_EQ(broad_json["game_object_update"].size(), 8u);
  for (const auto& row : broad_json["game_object_update"])
    for (const char* key : {"frame_ms", "lock_wait_us_mean", "lock_wait_us_median", "lock_wait_us_p99",
                            "lock_wait_us_worst", "contended", "acquisitions"})
      EXPECT_TRUE(is_figure(row[key])) << key;
  ASSERT_EQ(RunCli("bench-navmesh --crates 50 --repeats 1 --blocks 2 --steps 10 --json " + nav.string()), 0);
  const nlohmann::json nav_json = ReadJson(nav);
  EXPECT_GT(nav_json["tiles"]["count"].get<int>(), 0);
  EXPECT_GT(nav_json["request_to_ready"]["tiles"].get<int>(), 0);
  EXPECT_EQ(nav_json["step"]["steps_each"].get<int>(), 10);
  for (const char* part : {"with_jobs", "without_jobs"})
    for (const char* key : {"mean_ms", "median_ms", "max_ms", "lock_wait_ms"})
      EXPECT_TRUE(is_figure(nav_json["step"][part][key])) << part << " " << key;
  EXPECT_TRUE(is_figure(nav_json["step"]["blocked_by_navmesh_jobs_us"]));
  const std::filesystem::path open_world = TempFile("open-world.json");
  ASSERT_EQ(RunCli("bench-navmesh --open-world --world-size 300 --bodies 1000 --agents 8 --walk 30 "
                   "--tile-budget 16 --json " +
                   open_world.string()),
            0);
  const nlohmann::json open_world_json = ReadJson(open_world);
  EXPECT_EQ(open_world_json["tile_budget"].get<int>(), 16);
  EXPECT_EQ(open_world_json["failures"].get<int>(), 0);
  EXPECT_GT(open_world_json["tiles_built"].get<int>(), 0);
  EXPECT_LE(open_world_json["most_tiles_held"].get<int>(), 16);
  for (const char* key : {"step_mean_ms", "step_max_ms", "step_body_lock_wait_ms", "walk_wall_ms"})
    EXPECT_TRUE(is_figure(open_world_json[key])) << key;
  // Resident memory at the start and at each quarter of the walk.
  ASSERT_EQ(open_world_json["memory"].size(), 5u);
  for (const auto& snapshot : open_world_json["memory"]) EXPECT_TRUE(is_figure(snapshot["resident_mb"]));
  for (const char* command : {"bench-broadphase --frames 1", "bench-navmesh", "bench-navmesh --open-world"})
    EXPECT_EQ(RunCli(std::string(command) + " --json " + (TempFile("no-such-dir") / "x.json").string()), 2)
        << command;
}

TEST(Cli, BenchReportsAFailedJsonWriteAndLeavesDevicesAlone) {
  // A full device: the write fails, the exit code says so, and /dev/full is still the device.
  if (!std::filesystem::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  EXPECT_EQ(RunCli("bench --steps 2 --threads 1 --scene pyramid --no-bullet --json /dev/full"), 1);
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/full"));
  EXPECT_FALSE(std::filesystem::exists("/dev/full.tmp"));
}

TEST(Cli, BundledLevelsAreWhatTheGeneratorWrites) {
  const auto out = TempFile("levels");
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
