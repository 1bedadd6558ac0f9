// The `strata` CLI's long commands as a user runs them: the demo (its navmesh, pictures, player and exit
// codes) and the benchmarks (figures written as JSON, failed writes reported).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <assimp/scene.h>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include "CliRunner.h"

namespace strata::test {
namespace {

TEST(Cli, DemoRefusesBadOptionsBeforeRunningAndAddsEveryCrate) {
  const auto out_dir = TempPath("demo_out");
  for (const char* bad :
       {"--steps -1", "--steps 0", "--crates -1", "--request-radius nan", "--request-radius -3",
        "--agents 100000", "--threads 0", "--player-route 1,2,3", "--player-route 33,45",
        "--player-route 1,nan,3,4", "--player-speed 0", "--player-speed 51"})
    EXPECT_EQ(RunCli("demo --out-dir " + out_dir.string() + " " + std::string(bad)), 2) << bad;
  const auto file = TempPath("a_file");
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
  const auto out = TempPath("demo");
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

/// The demo's table of agents: per row its profile, whether it reached its target and the note.
struct AgentRow {
  std::string profile;
  bool reached = false;
  std::string note;
};

std::vector<AgentRow> AgentRows(const std::string& output) {
  std::vector<AgentRow> rows;
  std::istringstream lines(output.substr(output.find("\nagent profile")));
  std::string line;
  std::getline(lines, line);
  std::getline(lines, line);  // the header
  // "index profile (from) (to) set-off arrived walked-m reached  note": the reached column is right-aligned
  // in seven characters and followed by two spaces.
  while (std::getline(lines, line) && !line.empty() && std::isdigit(static_cast<unsigned char>(line[0]))) {
    std::istringstream fields(line);
    std::string index;
    AgentRow row;
    fields >> index >> row.profile;
    const std::size_t yes = line.find("    yes  "), no = line.find("     no  ");
    if (yes == std::string::npos && no == std::string::npos) {
      ADD_FAILURE() << "not an agent row: " << line;
      continue;
    }
    row.reached = yes != std::string::npos && (no == std::string::npos || yes < no);
    row.note = line.substr((row.reached ? yes : no) + 9);
    rows.push_back(row);
  }
  return rows;
}

TEST(Cli, DemoAgentsWalkToTheirTargetsAndThePlayerWalksTheCourtyardTour) {
  // At a game's pace: the background has a frame's wall time per frame, also in the sanitizer build beside
  // other tests. At twice the pace the agents there once set off only at 9.5 s of the 25 (their tiles took
  // 4.75 s of wall time), and a machine did not arrive in time.
  const auto out = TempPath("demo_player");
  std::string output;
  ASSERT_EQ(RunCliCapture("demo --time-scale 1 --out-dir " + out.string(), output), 0) << output;
  // Every agent, people and machines, walked to its target through its crowd; the two on the crate stack
  // could only get down by a drop link.
  const std::vector<AgentRow> rows = AgentRows(output);
  ASSERT_EQ(rows.size(), 10u) << output;
  std::size_t machines = 0, drop_downs = 0;
  for (const AgentRow& row : rows) {
    EXPECT_TRUE(row.reached) << output;
    machines += row.profile == "machine";
    drop_downs += row.note == "drop-down agent: no way without a drop link";
  }
  EXPECT_EQ(machines, 2u);
  EXPECT_EQ(drop_downs, 2u) << output;
  EXPECT_NE(output.find("agents: 10 of 10 reached their targets walking"), std::string::npos) << output;

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

TEST(Cli, DemoAgentsOnTheCrateStackStayThereWithoutDropLinks) {
  // Only the two drop-down agents, for ten seconds (they need under ten with links).
  const auto out = TempPath("demo_no_links");
  const std::string quiet =
      " --steps 600 --time-scale 4 --agents 0 --crates 0 --boulders 0 --no-player --out-dir ";
  std::string with_links, without_links;
  ASSERT_EQ(RunCliCapture("demo" + quiet + out.string(), with_links), 0) << with_links;
  ASSERT_EQ(RunCliCapture("demo --no-drop-links" + quiet + out.string(), without_links), 0) << without_links;
  const std::vector<AgentRow> walked = AgentRows(with_links), stayed = AgentRows(without_links);
  ASSERT_EQ(walked.size(), 2u) << with_links;
  ASSERT_EQ(stayed.size(), 2u) << without_links;
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(walked[i].reached) << with_links;
    EXPECT_FALSE(stayed[i].reached) << without_links;
    EXPECT_EQ(stayed[i].note, "drop-down agent: no way without a drop link");
  }
  EXPECT_NE(without_links.find("drops 0 m"), std::string::npos) << without_links;
  std::filesystem::remove_all(out);
}

TEST(Cli, DemoOnTheSmallArenaGivesEveryAgentANavmesh) {
  // The arena is four tiles; each agent asks for the tiles 16 m around it, which reach off the level. That
  // request was once refused as "more tiles than max_tiles", silently: no tile, every agent "no navmesh",
  // exit code 0.
  const auto out = TempPath("demo_arena");
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
  const auto level = TempPath("walls.obj");
  std::ofstream(level) << "v 0 0 0\nv 20 0 0\nv 20 10 0\nv 0 10 0\nv 0 0 20\nv 0 10 20\n"
                          "f 1 2 3\nf 1 3 4\nf 1 4 6\nf 1 6 5\n";
  const auto out = TempPath("demo_walls");
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
  const auto level = TempPath("far_triangle.obj");
  std::ofstream(level) << "v 0 0 0\nv 30 0 0\nv 30 0 30\nv 0 0 30\nv 3000 0 3000\nv 3001 0 3000\n"
                          "v 3001 0 3001\nf 1 3 2\nf 1 4 3\nf 5 7 6\n";
  const auto out = TempPath("demo_far");
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
  const std::filesystem::path json = TempPath("bench.json");
  std::string output;
  ASSERT_EQ(RunCliCapture("bench --steps 12 --threads 1,2 --no-bullet --json " + json.string(), output), 0);
  EXPECT_NE(output.find("where a step goes"), std::string::npos);
  EXPECT_NE(output.find("serial stages"), std::string::npos);
  const nlohmann::json document = ReadJson(json);
  ASSERT_TRUE(document["instruction_set"].is_string());  // "x86-64 SSE2" for the portable build
  EXPECT_FALSE(document["instruction_set"].get<std::string>().empty());
  // pyramid, convex_vs_mesh, ragdolls, chains, each at Strata's default passes and at Jolt's.
  ASSERT_EQ(document["scenes"].size(), 8u);
  for (std::size_t i = 0; i < document["scenes"].size(); ++i) {
    const std::string solver = document["scenes"][i]["solver"];
    EXPECT_EQ(
        solver.rfind(i % 2 == 0 ? "strata: 4 substeps x (1 velocity + 1 relax" : "jolt: 1 substep x (", 0),
        0u)
        << solver;
  }
  EXPECT_NE(document["scenes"][1]["solver"].get<std::string>().find("(10 velocity + 2 relax passes)"),
            std::string::npos);  // the pyramid at Jolt's 10 velocity and 2 position steps
  EXPECT_NE(document["scenes"][3]["solver"].get<std::string>().find("(4 velocity + 1 relax passes)"),
            std::string::npos);  // convex_vs_mesh at Jolt's 4 and 1
  for (const auto& scene : document["scenes"]) {
    const auto& runs = scene["strata"];
    ASSERT_EQ(runs.size(), 2u);
    EXPECT_EQ(runs[0]["threads"], 1);
    EXPECT_EQ(runs[1]["threads"], 2);
    // The same inputs give the same result whatever the thread count.
    EXPECT_EQ(runs[0]["state_hash"], runs[1]["state_hash"]) << scene["name"];
    EXPECT_DOUBLE_EQ(runs[0]["speedup"].get<double>(), 1.0);
    // Joints hold their anchors together: a chain's links stay within a millimetre of each other.
    const double gap = runs[0]["max_joint_gap_mm"].get<double>();
    const double bound = scene["name"] == "chains" ? 1.0 : scene["name"] == "pyramid" ? 0.0 : 1e9;
    EXPECT_LE(gap, bound) << scene["name"] << ", " << scene["solver"];  // the pyramid has no joints
    // The widest over the run includes the last step's reading.
    EXPECT_GE(runs[0]["widest_joint_gap_mm"].get<double>(), gap) << scene["name"];
    if (scene["name"] == "pyramid") {
      EXPECT_EQ(runs[0]["widest_joint_gap_mm"].get<double>(), 0.0);
    }
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
  EXPECT_EQ(RunCli("bench --steps 2 --runs 0"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --threads 0"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --threads 1,x"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --job-system fibers"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --solver bullet"), 2);
  EXPECT_EQ(RunCli("bench --steps 2 --json " + (TempPath("no-such-dir") / "bench.json").string()), 2);
}

TEST(Cli, BenchTakesTurnsAndReportsTheMedianRunAndRatio) {
  const std::filesystem::path json = TempPath("bench-runs.json");
  std::string output;
  ASSERT_EQ(RunCliCapture(
                "bench --scene chains --solver strata --steps 6 --threads 1 --runs 3 --json " + json.string(),
                output),
            0);
  EXPECT_NE(output.find("each row the median of 3 runs"), std::string::npos) << output;
  const nlohmann::json document = ReadJson(json);
  ASSERT_EQ(document["scenes"].size(), 1u);
  const nlohmann::json& scene = document["scenes"][0];
  EXPECT_EQ(scene["runs"], 3);
  ASSERT_EQ(scene["strata"].size(), 1u);  // the median run of each thread count, not every run
  EXPECT_GT(scene["strata"][0]["steps_per_second"].get<double>(), 0.0);
  if (scene.contains("bullet")) {  // built with the Bullet peer
    ASSERT_EQ(scene["strata_over_bullet"].size(), 1u);
    EXPECT_EQ(scene["strata_over_bullet"][0]["threads"], 1);
    EXPECT_GT(scene["strata_over_bullet"][0]["steps_per_second"].get<double>(), 0.0);
    EXPECT_NE(output.find("median of the turns' ratios"), std::string::npos);
  }
  std::filesystem::remove(json);
}

TEST(Cli, BenchInProcessRunsTheSameSimulationAsInAChild) {
  // For profilers that do not follow a fork: the same steps, the same end state, without a child process.
  const std::filesystem::path child = TempPath("bench-child.json"), here = TempPath("bench-here.json");
  const std::string run =
      "bench --scene convex_vs_mesh --solver jolt --steps 20 --threads 1 --no-bullet --json ";
  ASSERT_EQ(RunCli(run + child.string()), 0);
  ASSERT_EQ(RunCli(run + here.string() + " --in-process"), 0);
  const nlohmann::json forked = ReadJson(child)["scenes"][0]["strata"][0];
  const nlohmann::json in_process = ReadJson(here)["scenes"][0]["strata"][0];
  EXPECT_GT(in_process["steps_per_second"].get<double>(), 0.0);
  EXPECT_EQ(in_process["state_hash"], forked["state_hash"]);
  std::filesystem::remove(child);
  std::filesystem::remove(here);
}

TEST(Cli, ShardedBakeMergesIntoTheFileOfOneBake) {
  const std::string level = (kLevels / "courtyard.obj").string();
  const auto whole = TempPath("whole.bin"), merged = TempPath("merged.bin");
  ASSERT_EQ(RunCli("navmesh bake " + level + " --out " + whole.string()), 0);
  std::string shards;
  for (int k = 0; k < 3; ++k) {
    const auto shard = TempPath("courtyard-" + std::to_string(k) + ".bin");
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
    EXPECT_EQ(RunCli("navmesh bake " + level + " --shard " + bad + " --out " + TempPath("bad.bin").string()),
              2)
        << bad;
  EXPECT_EQ(RunCli("navmesh merge" + shards + shards + " --out " + merged.string()), 2) << "a tile twice";
}

TEST(Cli, LongCommandsShowABarOnATerminalAndOneSummaryLineOtherwise) {
  const std::string level = (kLevels / "courtyard.obj").string();
  const std::string bake = "navmesh bake " + level + " --out " + TempPath("progress.bin").string();
  std::string errors;
  ASSERT_EQ(RunCliErrors(bake, errors), 0) << errors;
  EXPECT_EQ(errors.rfind("strata navmesh bake: ", 0), 0u) << errors;
  EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 1) << errors;
  EXPECT_EQ(errors.find('\r'), std::string::npos) << errors;
  ASSERT_EQ(RunCliErrors("simulate " + (kScenes / "bounce.json").string() + " --steps 30 --out " +
                             TempPath("progress.jsonl").string(),
                         errors),
            0);
  EXPECT_EQ(errors.rfind("strata simulate: 30 steps", 0), 0u) << errors;

  // On a terminal (util-linux `script` gives the command one) the bar is drawn, then the summary.
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` here";
  const std::filesystem::path typescript = TempPath("progress-terminal.txt");
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
  const std::filesystem::path json = TempPath("gameplay.json");
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
  const std::filesystem::path json = TempPath("gameplay-bad-level.json"), level = TempPath("two-lines.obj");
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
  const std::filesystem::path broad = TempPath("broadphase.json"), nav = TempPath("navmesh-bench.json");
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
  const std::filesystem::path open_world = TempPath("open-world.json");
  ASSERT_EQ(RunCli("bench-navmesh --open-world --world-size 300 --bodies 1000 --agents 8 --walk 30 "
                   "--tile-budget 16 --profile-cost-tiles 2 --profile-cost-runs 1 --crowd-agents 8 --json " +
                   open_world.string()),
            0);
  const nlohmann::json open_world_json = ReadJson(open_world);
  EXPECT_EQ(open_world_json["tile_budget"].get<int>(), 16);
  EXPECT_EQ(open_world_json["failures"].get<int>(), 0);
  EXPECT_GT(open_world_json["tiles_built"].get<int>(), 0);
  EXPECT_LE(open_world_json["most_tiles_held"].get<int>(), 16);
  for (const char* key : {"step_mean_ms", "step_max_ms", "step_body_lock_wait_ms", "walk_wall_ms",
                          "crowd_update_mean_ms", "crowd_update_max_ms", "waiting_agent_seconds"})
    EXPECT_TRUE(is_figure(open_world_json[key])) << key;
  // The crowd walked on the navmesh; the profiles were built the same both ways.
  EXPECT_EQ(open_world_json["on_mesh_share"].get<double>(), 1.0);
  EXPECT_EQ(open_world_json["stuck_agents"].get<int>(), 0);
  EXPECT_TRUE(open_world_json["profile_cost"]["same_tiles"].get<bool>());
  EXPECT_EQ(open_world_json["profile_cost"]["tiles"].get<int>(), 4);
  ASSERT_EQ(open_world_json["crowd_updates"].size(), 1u);
  EXPECT_EQ(open_world_json["crowd_updates"][0]["off_mesh"].get<int>(), 0);
  // Resident memory at the start and at each quarter of the walk.
  ASSERT_EQ(open_world_json["memory"].size(), 5u);
  for (const auto& snapshot : open_world_json["memory"]) EXPECT_TRUE(is_figure(snapshot["resident_mb"]));
  for (const char* command : {"bench-broadphase --frames 1", "bench-navmesh", "bench-navmesh --open-world"})
    EXPECT_EQ(RunCli(std::string(command) + " --json " + (TempPath("no-such-dir") / "x.json").string()), 2)
        << command;
}

TEST(Cli, BenchReportsAFailedJsonWriteAndLeavesDevicesAlone) {
  // A full device: the write fails, the exit code says so, and /dev/full is still the device.
  if (!std::filesystem::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  EXPECT_EQ(RunCli("bench --steps 2 --threads 1 --scene pyramid --no-bullet --json /dev/full"), 1);
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/full"));
  EXPECT_FALSE(std::filesystem::exists("/dev/full.tmp"));
}

}  // namespace
}  // namespace strata::test
