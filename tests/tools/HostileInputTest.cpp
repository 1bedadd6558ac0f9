// What a hostile or unlucky user did to `strata` (issue: "nothing crashes, hangs or lies"), one reproducer
// per class: damaged PLY files, files a level refers to that are pipes, sizes and thread counts past any
// machine, 10,000 bodies spawned at one point, kills during every writing command, outputs that cannot be
// written, two outputs given the same file, a level far from the origin exported as OBJ. Each runs the CLI
// as a user would and checks the exit code, the message and what is left on disk.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/TempPath.h"

extern char** environ;

namespace strata::test {
namespace {

const std::filesystem::path kScenes = STRATA_SCENES_DIR;
const std::filesystem::path kLevels = STRATA_LEVELS_DIR;

std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

struct CliRun {
  int status = -1;  ///< exit code; 124 when `timeout` stopped it
  std::string out;
  std::string err;
};

/// Runs `strata arguments` under a 60 s timeout (a hang is a failure, never a stuck test).
CliRun Strata(const std::string& arguments) {
  const std::filesystem::path out = TempPath("stdout"), err = TempPath("stderr");
  const int status = std::system(("timeout 60 " + std::string(STRATA_CLI) + " " + arguments + " > " +
                                  out.string() + " 2> " + err.string())
                                     .c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadBytes(out), ReadBytes(err)};
}

// A 20 m x 20 m floor facing up, as ASCII PLY; `last_newline` false cuts the file's last byte.
std::string AsciiPlyFloor(bool last_newline) {
  std::string ply =
      "ply\nformat ascii 1.0\ncomment a floor\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "-10 0 -10\n-10 0 10\n10 0 10\n10 0 -10\n3 0 1 2\n3 0 2 3\n";
  if (!last_newline) ply.pop_back();
  return ply;
}

std::string BinaryPlyFloor() {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const float vertices[4][3] = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
  ply.append(reinterpret_cast<const char*>(vertices), sizeof(vertices));
  const std::int32_t faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& face : faces) {
    ply.push_back(3);
    ply.append(reinterpret_cast<const char*>(face), sizeof(face));
  }
  return ply;
}

TEST(HostileInput, APlyWithoutItsLastNewlineBakesThroughEveryRoute) {
  const auto ply = TempPath("floor.ply"), navmesh = TempPath("floor.bin"),
             scene = TempPath("floor_scene.json");
  WriteBytes(ply, AsciiPlyFloor(false));
  const CliRun bake = Strata("navmesh bake " + ply.string() + " --out " + navmesh.string());
  ASSERT_EQ(bake.status, 0) << bake.err;
  EXPECT_NE(bake.out.find("2 triangles"), std::string::npos) << bake.out;
  EXPECT_NE(bake.out.find("-> 4 tiles"), std::string::npos) << bake.out;
  WriteBytes(scene,
             R"({"bodies": [{"name": "floor", "motion": "static", "shape": {"type": "mesh", "file": ")" +
                 ply.filename().string() + R"("}}]})");
  const CliRun simulate = Strata("simulate " + scene.string() + " --steps 2 --out /dev/null");
  EXPECT_EQ(simulate.status, 0) << simulate.err;
  const CliRun demo = Strata("demo " + ply.string() +
                             " --steps 30 --crates 2 --boulders 0 --agents 2 --no-player --out-dir " +
                             TempPath("ply_demo").string());
  EXPECT_EQ(demo.status, 0) << demo.err;
}

TEST(HostileInput, DamagedPlyFilesAreErrorsNotCrashesOrSpins) {
  const auto ply = TempPath("damaged.ply");
  const std::string binary = BinaryPlyFloor();
  struct Case {
    std::string name;
    std::string bytes;
    std::string message;
  };
  const std::string header_only = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n";
  const std::vector<Case> cases = {
      {"binary one byte short", binary.substr(0, binary.size() - 1), "face 1"},
      {"header without end_header", header_only + std::string(100000, 'x'), "no end_header line"},
      {"a billion vertices declared",
       "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\nproperty float "
       "z\n"
       "end_header\n0 0 0\n",
       "declares 1000000000 entries"},
      {"a face past the vertices",
       AsciiPlyFloor(true).replace(AsciiPlyFloor(true).find("3 0 2 3"), 7, "3 0 2 9"), "vertex index 9"},
      {"not a number", AsciiPlyFloor(true).replace(AsciiPlyFloor(true).find("-10 0 10"), 3, "abc"),
       "not a number"},
  };
  for (const Case& c : cases) {
    WriteBytes(ply, c.bytes);
    const CliRun bake = Strata("navmesh bake " + ply.string() + " --out " + TempPath("damaged.bin").string());
    EXPECT_EQ(bake.status, 2) << c.name << ": " << bake.err;
    EXPECT_NE(bake.err.find(c.message), std::string::npos) << c.name << ": " << bake.err;
  }
  WriteBytes(ply, binary);
  EXPECT_EQ(Strata("navmesh bake " + ply.string() + " --out " + TempPath("damaged.bin").string()).status, 0)
      << "the undamaged binary file bakes";
}

TEST(HostileInput, APipeALevelRefersToIsRefusedNotWaitedOn) {
  const auto folder = TempPath("referenced");
  std::filesystem::remove_all(folder);  // an earlier run under a reused process id left its pipes
  std::filesystem::create_directories(folder);
  ASSERT_EQ(::mkfifo((folder / "materials.mtl").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((folder / "buffer.bin").c_str(), 0600), 0);
  WriteBytes(folder / "level.obj", "mtllib materials.mtl\nv -10 0 -10\nv -10 0 10\nv 10 0 10\nf 1 2 3\n");
  const CliRun obj =
      Strata("navmesh bake " + (folder / "level.obj").string() + " --out " + TempPath("ref.bin").string());
  // OBJ geometry is read by ObjReader, which never opens a material file: the pipe is not touched.
  EXPECT_EQ(obj.status, 0) << obj.err;
  WriteBytes(folder / "level.gltf",
             R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "buffer.bin", "byteLength": 36}],
                 "bufferViews": [{"buffer": 0, "byteLength": 36}],
                 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
                 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}],
                 "scenes": [{"nodes": [0]}], "scene": 0})");
  const CliRun gltf =
      Strata("navmesh bake " + (folder / "level.gltf").string() + " --out " + TempPath("ref.bin").string());
  EXPECT_EQ(gltf.status, 2) << gltf.err;
  EXPECT_NE(gltf.err.find("buffer.bin"), std::string::npos) << gltf.err;
  EXPECT_NE(gltf.status, 124) << "the bake waited on the pipe";
}

TEST(HostileInput, SizeAndThreadOptionsNameTheirLimits) {
  struct Case {
    std::string arguments;
    std::string message;
  };
  const std::string scene = (kScenes / "stack.json").string();
  const std::vector<Case> cases = {
      {"simulate " + scene + " --threads 100000", "--threads must be from 0 to 256"},
      {"demo --threads 20000", "--threads must be from 1 to 256"},
      {"demo --navmesh-threads 1000", "--navmesh-threads must be from 1 to 64"},
      {"demo --crates 1000000", "--crates"},
      {"demo --profiles elephant", "--profiles"},
      {"demo --profiles person,person", "'person' is named twice"},
      {"demo --profiles person --agent-radius 1", "give --profiles or --agent-radius, not both"},
      {"demo --time-scale -1", "--time-scale"},
      {"demo --target-radius nan", "--target-radius"},
      {"bench --threads 100000", "--threads must be from 1 to 256"},
      {"bench-broadphase --max-threads 100000", "--max-threads must be from 0 to 256"},
      {"bench-navmesh --blocks -1 --steps -5", "--blocks must be from 2 to 1000"},
      {"navmesh bake x.obj --out y.bin --threads 100000", "--threads must be from 1 to 256"},
      {"demo --steps 10000000 --record-every 1 --record " + TempPath("huge_recording.json").string(),
       "record fewer frames"},
  };
  for (const Case& c : cases) {
    const CliRun run = Strata(c.arguments);
    EXPECT_EQ(run.status, 2) << c.arguments << "\n" << run.err;
    EXPECT_NE((run.err + run.out).find(c.message), std::string::npos) << c.arguments << "\n"
                                                                      << run.err << run.out;
  }
}

TEST(HostileInput, TenThousandBodiesAtOnePointStepWithinBudgetWithAWarning) {
  const auto scene = TempPath("pile.json");
  std::string bodies =
      R"({"name": "ground", "motion": "static", "shape": {"type": "box", "half_extents": [50, 0.5, 50]},
                           "position": [0, -0.5, 0]})";
  for (int i = 0; i < 10000; ++i)
    bodies += R"(, {"name": "s)" + std::to_string(i) +
              R"(", "shape": {"type": "sphere", "radius": 0.5}, "position": [0, 5, 0]})";
  WriteBytes(scene, R"({"bodies": [)" + bodies + "]}");
  const CliRun run = Strata("simulate " + scene.string() + " --steps 5 --out /dev/null");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.err.find("past the budget of"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("PhysicsSystemConfig::max_body_pairs"), std::string::npos) << run.err;
  const std::size_t peak = run.err.find("peak memory ");
  ASSERT_NE(peak, std::string::npos) << run.err;
  std::printf("10,000 spheres at one point, 5 steps: peak memory %ld MB\n",
              std::atol(run.err.c_str() + peak + 12));
  EXPECT_LT(std::atol(run.err.c_str() + peak + 12), 2048) << "bounded by the budget, not by the machine";
}

TEST(HostileInput, OutputsThatCannotBeWrittenAreErrors) {
  const auto full = TempPath("full_link");
  std::filesystem::remove(full);
  std::filesystem::create_symlink("/dev/full", full);
  const std::string navmesh = TempPath("path.bin").string();
  ASSERT_EQ(Strata("navmesh bake " + (kLevels / "arena.glb").string() + " --out " + navmesh).status, 0);
  const CliRun to_link =
      Strata("navmesh bake " + (kLevels / "arena.glb").string() + " --out " + full.string());
  EXPECT_NE(to_link.status, 0);
  EXPECT_NE(to_link.err.find("No space left on device"), std::string::npos) << to_link.err;
  // Standard output to a full device.
  const int status = std::system(("timeout 60 " + std::string(STRATA_CLI) + " navmesh path " + navmesh +
                                  " --from 0,0,0 --to 5,0,5 --json > /dev/full 2> /dev/null")
                                     .c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << "a report that reached nobody is a failure";
}

TEST(HostileInput, OneFileGivenForTwoOutputsIsRefused) {
  const auto out = TempPath("same.bin"), level = TempPath("level_copy.obj");
  std::filesystem::copy_file(kLevels / "courtyard.obj", level,
                             std::filesystem::copy_options::overwrite_existing);
  const std::string before = ReadBytes(level);
  CliRun run = Strata("navmesh bake " + level.string() + " --out " + out.string() + " --obj " + out.string());
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("--out and --obj name the same file"), std::string::npos) << run.err;
  run = Strata("navmesh bake " + level.string() + " --out " + level.string());
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(ReadBytes(level), before) << "the level was overwritten by its own navmesh";
  const auto link = TempPath("same_link.bin");
  std::filesystem::remove(link);
  std::filesystem::create_symlink(out, link);
  WriteBytes(out, "x");
  EXPECT_EQ(Strata("navmesh bake " + level.string() + " --out " + out.string() + " --report " + link.string())
                .status,
            2)
      << "the same file through a link";
}

TEST(HostileInput, ALinkWhereTheOldTemporaryWentIsNotFollowed) {
  const auto out = TempPath("field.obj"), victim = TempPath("victim.txt");
  WriteBytes(victim, "keep me");
  std::filesystem::remove(out.string() + ".tmp");
  std::filesystem::create_symlink(victim, out.string() + ".tmp");
  ASSERT_EQ(Strata("level field --size 100 --out " + out.string()).status, 0);
  EXPECT_EQ(ReadBytes(victim), "keep me");
  EXPECT_NE(ReadBytes(out).find("\nv "), std::string::npos);
}

TEST(HostileInput, ALevelFarFromTheOriginKeepsItsShapeInTheObjExport) {
  // A 10,000 km offset: every exported vertex used to print as 1e+07.
  const auto level = TempPath("far.obj"), navmesh = TempPath("far.bin"), obj = TempPath("far_navmesh.obj");
  const double far = 1.0e7;
  std::string text;
  for (const auto& [x, z] : {std::pair{-20.0, -20.0}, {-20.0, 20.0}, {20.0, 20.0}, {20.0, -20.0}}) {
    char line[96];
    std::snprintf(line, sizeof(line), "v %.3f 0 %.3f\n", far + x, far + z);
    text += line;
  }
  WriteBytes(level, text + "f 1 2 3\nf 1 3 4\n");
  const CliRun run =
      Strata("navmesh bake " + level.string() + " --out " + navmesh.string() + " --obj " + obj.string());
  ASSERT_EQ(run.status, 0) << run.err;
  std::ifstream exported(obj);
  double min_x = 1e300, max_x = -1e300;
  std::string word;
  while (exported >> word) {
    if (word != "v") continue;
    double x = 0, y = 0, z = 0;
    exported >> x >> y >> z;
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
  }
  EXPECT_GT(max_x - min_x, 30.0) << "the navmesh spans most of the 40 m level";
  EXPECT_GT(min_x, far - 21.0);
}

TEST(HostileInput, DuplicateKeysInASceneAreRefused) {
  const auto scene = TempPath("duplicate.json");
  WriteBytes(scene, R"({"bodies": [{"name": "a", "name": "b", "shape": {"type": "sphere", "radius": 1}}]})");
  const CliRun run = Strata("simulate " + scene.string() + " --steps 1");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("the key \"name\" appears twice"), std::string::npos) << run.err;
}

TEST(HostileInput, MergingTwoOfThreeShardsFailsAndListsWhatIsMissing) {
  const auto level = TempPath("merge_field.obj");
  ASSERT_EQ(Strata("level field --size 100 --seed 3 --out " + level.string()).status, 0);
  std::vector<std::string> shards;
  for (int shard = 0; shard < 2; ++shard) {
    shards.push_back(TempPath("merge_shard" + std::to_string(shard) + ".bin").string());
    ASSERT_EQ(Strata("navmesh bake " + level.string() + " --shard " + std::to_string(shard) + "/3 --out " +
                     shards.back())
                  .status,
              0);
  }
  const auto merged = TempPath("merged.bin");
  std::filesystem::remove(merged);
  CliRun run = Strata("navmesh merge " + shards[0] + " " + shards[1] + " --out " + merged.string());
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("1 of 3 shards are missing (shard 2)"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(merged));
  run = Strata("navmesh merge " + shards[0] + " " + shards[1] + " --out " + merged.string() +
               " --allow-partial");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.err.find("tiles left out"), std::string::npos) << run.err;
}

// kill -9 at fixed-seed moments during each command that writes a file: the file is then the old one or the
// complete new one (byte for byte what a whole run writes), never empty or cut, and the next run leaves no
// temporary behind.
struct Writer {
  std::string name;
  std::string arguments;  ///< "{out}" is the output
  std::string extension;
  /// Whether every whole run writes the same bytes; otherwise (timings, background threads' timing) the file
  /// must be one whole JSON document.
  bool same_bytes = true;
};

pid_t Spawn(const std::string& command) {
  const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  pid_t pid = 0;
  return ::posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) == 0 ? pid : -1;
}

std::string Expand(std::string text, const std::filesystem::path& out) {
  for (std::size_t at; (at = text.find("{out}")) != std::string::npos;) text.replace(at, 5, out.string());
  return text;
}

void KillDuringEveryWriter(int tries) {
  const std::vector<Writer> writers = {
      {"level field", "level field --size 400 --seed 5 --out {out}", ".obj"},
      {"level field glb", "level field --size 400 --seed 5 --out {out}", ".glb"},
      {"navmesh bake", "navmesh bake " + (kLevels / "courtyard.obj").string() + " --out {out}", ".bin"},
      {"navmesh bake --obj",
       "navmesh bake " + (kLevels / "arena.glb").string() + " --out " + TempPath("k.bin").string() +
           " --obj {out}",
       ".obj"},
      {"simulate --out", "simulate " + (kScenes / "stack.json").string() + " --steps 200 --out {out}",
       ".jsonl"},
      {"demo --record",
       "demo --steps 60 --crates 10 --no-player --out-dir " + TempPath("kill_demo").string() +
           " --record {out}",
       ".json", false},
      {"bench --json", "bench --scene pyramid --steps 20 --threads 1 --no-bullet --json {out}", ".json",
       false},
  };
  std::mt19937 random(20261127);
  for (const Writer& writer : writers) {
    const auto out = TempPath("killed" + writer.extension);
    const std::string command =
        "exec " + std::string(STRATA_CLI) + " " + Expand(writer.arguments, out) + " > /dev/null 2>&1";
    const auto start = std::chrono::steady_clock::now();
    ASSERT_EQ(std::system(command.c_str()), 0) << writer.name;
    const double whole_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const std::string complete = ReadBytes(out);
    ASSERT_FALSE(complete.empty()) << writer.name;
    for (int attempt = 0; attempt < tries; ++attempt) {
      const pid_t pid = Spawn(command);
      ASSERT_GT(pid, 0);
      const auto delay = std::chrono::microseconds(
          static_cast<long>(std::uniform_real_distribution<double>(0.0, 1.1)(random) * whole_ms * 1000.0));
      std::this_thread::sleep_for(delay);
      ::kill(pid, SIGKILL);
      int status = 0;
      ::waitpid(pid, &status, 0);
      const std::string left = ReadBytes(out);
      if (!writer.same_bytes) {
        EXPECT_TRUE(nlohmann::json::accept(left)) << writer.name << " attempt " << attempt << ": "
                                                  << left.size() << " bytes left, not one whole document";
      } else {
        EXPECT_EQ(left.size(), complete.size())
            << writer.name << " attempt " << attempt << " killed after " << delay.count() << " us";
        EXPECT_TRUE(left == complete) << writer.name << " attempt " << attempt;
      }
    }
    // The next whole run removes what the killed ones left beside the file.
    ASSERT_EQ(std::system(command.c_str()), 0) << writer.name;
    for (const auto& entry : std::filesystem::directory_iterator(out.parent_path()))
      EXPECT_EQ(entry.path().filename().string().find("." + out.filename().string() + "."), std::string::npos)
          << writer.name << " left " << entry.path();
  }
}

TEST(HostileInput, KilledWritersLeaveTheOldFileWhole) {
  KillDuringEveryWriter(3);
}

TEST(HostileInputStress, KilledWritersLeaveTheOldFileWholeTwentyTimesEach) {
  KillDuringEveryWriter(20);
}

}  // namespace
}  // namespace strata::test
