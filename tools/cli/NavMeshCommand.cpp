// `strata navmesh bake LEVEL --out NAV.bin [--obj NAV.obj] [--report report.json]`: builds every navmesh
// tile of a level with the background service and saves them in RecastDemo's tiled set format.
// `--shard K/N` builds share K of N of the tiles; `strata navmesh merge SHARD... --out NAV.bin` joins the
// shards' files into the file one bake writes, byte for byte.
// `strata navmesh path NAV.bin --from x,y,z --to x,y,z [--json]`: a path query on a saved navmesh.
// Bad input (missing or corrupt files, bad settings, bad points) exits with code 2.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "navmesh/LevelBake.h"
#include "navmesh/NavMeshQuery.h"
#include "navmesh/NavMeshService.h"
#include "navmesh/Validation.h"
#include "physics/core/JobSystem.h"
#include "physics/core/OutputFile.h"
#include "physics/world/PhysicsSystem.h"
#include "tools/bench/Progress.h"
#include "tools/cli/Commands.h"
#include "tools/cli/NavMeshOptions.h"
#include "tools/cli/Validators.h"

namespace strata::cli {

namespace {

struct BakeOptions {
  std::string level;
  LevelLoadOptions level_options;
  navmesh::NavMeshSettings settings;
  std::string out;
  std::string obj;
  std::string report;
  int threads = 2;
  std::string shard;  // "K/N": build share K of N (a farm's job array); empty: every tile
  std::string profile;
  const CLI::App* command = nullptr;  // to tell which agent options were given
};

struct MergeOptions {
  std::vector<std::string> shards;
  std::string out;
  bool allow_partial = false;
};

struct PathOptions {
  std::string navmesh;
  std::string profile;
  std::string from;
  std::string to;
  bool json = false;
};

int Fail(const std::string& command, const std::string& message) {
  std::cerr << "strata navmesh " << command << ": " << message << "\n";
  return 2;
}

nlohmann::json Report(const BakeOptions& options, const LoadedLevel& level,
                      const navmesh::NavMeshService& service, double wall_ms) {
  std::vector<double> gather, recast, total;
  for (const navmesh::TileBuildRecord& record : service.build_log()) {
    gather.push_back(record.gather_ms);
    recast.push_back(record.recast_ms);
    total.push_back(record.gather_ms + record.recast_ms);
  }
  const auto stats = [](const std::vector<double>& values) {
    const auto [median, max] = MedianAndMax(values);
    return nlohmann::json{{"median", median}, {"max", max}};
  };
  const navmesh::NavMesh& navmesh = service.navmesh();
  const navmesh::NavMeshSettings& settings = service.profile_settings();
  return {{"level", options.level},
          {"profile", navmesh.profile().empty() ? "default" : navmesh.profile()},
          {"level_triangles", level.triangles},
          {"level_chunks", level.chunks},
          {"tiles_built", service.build_log().size()},
          {"tiles", navmesh.tile_count()},
          {"polygons", navmesh.polygon_count()},
          {"walkable_area_m2", navmesh.WalkableArea()},
          {"islands", navmesh::CountIslands(navmesh)},
          {"build_ms", {{"gather", stats(gather)}, {"recast", stats(recast)}, {"total", stats(total)}}},
          {"wall_ms", wall_ms},
          {"threads", options.threads},
          {"settings",
           {{"cell_size", settings.cell_size},
            {"cell_height", settings.cell_height},
            {"agent_height", settings.agent_height},
            {"agent_radius", settings.agent_radius},
            {"agent_max_climb", settings.agent_max_climb},
            {"agent_max_slope", settings.agent_max_slope},
            {"agent_max_drop", settings.agent_max_drop}}},
          {"drop_links", navmesh.link_count()}};
}

/// "K/N" with 0 <= K < N.
std::optional<std::pair<int, int>> ParseShard(const std::string& text) {
  int shard = 0, count = 0;
  char slash = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d %c %d %c", &shard, &slash, &count, &extra) != 3 || slash != '/')
    return std::nullopt;
  if (count < 1 || count > 100000 || shard < 0 || shard >= count) return std::nullopt;
  return std::pair{shard, count};
}

int RunBake(const BakeOptions& options) {
  navmesh::LevelBakeOptions bake_options;
  if (!options.shard.empty()) {
    const std::optional<std::pair<int, int>> shard = ParseShard(options.shard);
    if (!shard) return Fail("bake", "--shard must be K/N with 0 <= K < N, got '" + options.shard + "'");
    bake_options.shard = shard->first;
    bake_options.shard_count = shard->second;
  }
  if (Status distinct = DistinctFiles({{"the level", options.level},
                                       {"--out", options.out},
                                       {"--obj", options.obj},
                                       {"--report", options.report}});
      !distinct)
    return Fail("bake", distinct.message());
  bake_options.service.settings = options.settings;
  Result<std::optional<navmesh::AgentProfile>> profile = ChosenProfile(*options.command, options.profile);
  if (!profile) return Fail("bake", profile.error().message);
  if (*profile) bake_options.service.profiles = {**profile};
  bake_options.service.worker_threads = options.threads;
  if (Status status = bake_options.service.Validate(); !status.ok()) return Fail("bake", status.message());
  PhysicsSystemConfig world_config;
  world_config.max_bodies = 4096;
  world_config.job_system = std::make_shared<SerialJobSystem>();
  auto world = PhysicsSystem::Create(world_config);
  if (!world) return Fail("bake", world.error().message);
  Result<LoadedLevel> level = LoadLevel(**world, options.level, options.level_options);
  if (!level) return Fail("bake", level.error().message);
  for (const std::string& warning : level->warnings)
    std::fprintf(stderr, "strata navmesh bake: warning: %s\n", warning.c_str());

  bench::Progress progress("strata navmesh bake", "tiles");
  if (progress.terminal()) bake_options.progress = progress.Callback();
  Result<navmesh::LevelBake> bake = navmesh::BakeLevel(**world, level->bounds, bake_options);
  if (!bake) return Fail("bake", options.level + ": " + bake.error().message);
  progress.Finish(std::to_string(bake->service->build_log().size()) + " tiles built, " +
                  std::to_string(bake->service->navmesh().tile_count()) + " with polygons");
  const navmesh::NavMeshService& service = *bake->service;
  const double wall_ms = bake->wall_ms;

  const navmesh::NavMesh& navmesh = service.navmesh();
  if (Status status = navmesh.Save(options.out, bake->coverage); !status.ok())
    return Fail("bake", status.message());
  if (!options.obj.empty())
    if (Status status = navmesh.WriteObj(options.obj); !status.ok()) return Fail("bake", status.message());
  const nlohmann::json report = Report(options, *level, service, wall_ms);
  if (!options.report.empty())
    if (Status written = WriteOutputFile(options.report, report.dump(2) + "\n"); !written)
      return Fail("bake", written.message());
  std::printf(
      "%s (%s): %zu triangles in %zu chunks -> %d tiles, %d polygons, %.1f m^2 walkable, %d islands\n",
      options.level.c_str(), report["profile"].get<std::string>().c_str(), level->triangles, level->chunks,
      navmesh.tile_count(), navmesh.polygon_count(), navmesh.WalkableArea(), report["islands"].get<int>());
  std::printf("per tile: gather %.2f ms median (max %.2f), recast %.2f ms median (max %.2f); bake %.0f ms\n",
              report["build_ms"]["gather"]["median"].get<double>(),
              report["build_ms"]["gather"]["max"].get<double>(),
              report["build_ms"]["recast"]["median"].get<double>(),
              report["build_ms"]["recast"]["max"].get<double>(), wall_ms);
  std::printf("wrote %s\n", options.out.c_str());
  return 0;
}

int RunMerge(const MergeOptions& options) {
  const std::vector<std::filesystem::path> files(options.shards.begin(), options.shards.end());
  std::vector<std::pair<std::string, std::string>> named{{"--out", options.out}};
  for (const std::string& shard : options.shards) named.emplace_back("shard " + shard, shard);
  if (Status distinct = DistinctFiles(named); !distinct) return Fail("merge", distinct.message());
  Result<navmesh::MergedShards> merged = navmesh::MergeShards(files, options.allow_partial);
  if (!merged) {
    std::cerr << "strata " << merged.error().message << "\n";  // it names the command and the file
    return 2;
  }
  if (!merged->missing_tiles.empty())
    std::fprintf(stderr, "strata navmesh merge: warning: %zu shards missing, %zu tiles left out: %s\n",
                 merged->missing_shards.size(), merged->missing_tiles.size(),
                 navmesh::DescribeTiles(merged->missing_tiles).c_str());
  const navmesh::NavMesh& navmesh = *merged->navmesh;
  if (Status saved = navmesh.Save(options.out, merged->coverage); !saved)
    return Fail("merge", saved.message());
  std::printf("merged %zu shards: %d tiles, %d polygons; wrote %s\n", files.size(), navmesh.tile_count(),
              navmesh.polygon_count(), options.out.c_str());
  return 0;
}

int RunPath(const PathOptions& options) {
  const std::optional<Vec3> from = ParsePoint(options.from);
  const std::optional<Vec3> to = ParsePoint(options.to);
  if (!from) return Fail("path", "--from must be x,y,z with finite numbers, got '" + options.from + "'");
  if (!to) return Fail("path", "--to must be x,y,z with finite numbers, got '" + options.to + "'");
  Result<std::unique_ptr<navmesh::NavMesh>> navmesh = navmesh::NavMesh::Load(options.navmesh);
  if (!navmesh) return Fail("path", navmesh.error().message);
  const std::string& baked_for = (*navmesh)->profile();
  if (!options.profile.empty() && baked_for != options.profile)
    return Fail("path",
                options.navmesh + " was baked for " +
                    (baked_for.empty() ? std::string("no named profile") : "profile '" + baked_for + "'") +
                    ", not '" + options.profile + "' (bake one with --profile " + options.profile + ")");
  auto query = navmesh::NavMeshQuery::Create(**navmesh);
  if (!query) return Fail("path", query.error().message);
  Result<navmesh::PathResult> path = (*query)->FindPath(*from, *to);
  if (!path) return Fail("path", path.error().message);
  // Valid but likely not what was meant: say so, on standard error so --json output stays clean.
  if (!path->reached_end && !(*query)->FindNearestPoly(*to).ok())
    std::fprintf(
        stderr,
        "strata navmesh path: warning: --to %s is not on or near the navmesh; the path stops where the "
        "navmesh does\n",
        options.to.c_str());
  if (options.json) {
    nlohmann::json points = nlohmann::json::array();
    for (const Vec3& p : path->points) points.push_back({p.x(), p.y(), p.z()});
    std::cout << nlohmann::json{{"profile", baked_for.empty() ? "default" : baked_for},
                                {"found", path->found},
                                {"reached_end", path->reached_end},
                                {"length", path->length},
                                {"polygons", path->polys.size()},
                                {"points", points}}
                     .dump()
              << "\n";
    return 0;
  }
  std::printf("found: %s\nreached end: %s\nlength: %.3f m over %zu polygons\n", path->found ? "yes" : "no",
              path->reached_end ? "yes" : "no", path->length, path->polys.size());
  for (const Vec3& p : path->points) std::printf("  (%.3f, %.3f, %.3f)\n", p.x(), p.y(), p.z());
  return 0;
}

}  // namespace

std::function<int()> AddNavMeshCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("navmesh", "bake navmeshes and query paths");
  command->require_subcommand(1);

  auto bake = std::make_shared<BakeOptions>();
  CLI::App* bake_command = command->add_subcommand("bake", "build every navmesh tile of a level");
  bake_command->add_option("level", bake->level, "level mesh (OBJ, glTF/GLB, FBX, PLY, STL, DAE)")
      ->required();
  bake_command->add_option("--out", bake->out, "navmesh set file to write (RecastDemo's MSET format)")
      ->required();
  bake_command->add_option("--obj", bake->obj, "also write the navmesh as OBJ");
  bake_command->add_option("--report,--json", bake->report, "write build figures as JSON");
  bake_command->add_option("--threads", bake->threads, "background build threads")
      ->check(CountIn(1, kMaxThreads, "--threads"))
      ->capture_default_str();
  bake_command->add_option("--shard", bake->shard,
                           "K/N: build only share K of N of the tiles (coordinate order, every N-th); "
                           "`navmesh merge` joins the shards' files into what one bake writes");
  AddNavMeshSettingsOptions(*bake_command, bake->settings);
  AddProfileOption(*bake_command, bake->profile, "the kind of walker to bake for");
  bake->command = bake_command;
  AddLevelOptions(*bake_command, bake->level_options);

  auto merge = std::make_shared<MergeOptions>();
  CLI::App* merge_command =
      command->add_subcommand("merge", "join the files of a sharded bake into one navmesh set file");
  merge_command->add_option("shards", merge->shards, "the shards' navmesh set files")->required();
  merge_command->add_option("--out", merge->out, "navmesh set file to write")->required();
  merge_command->add_flag("--allow-partial", merge->allow_partial,
                          "write the tiles there are even when shards are missing (listed on stderr)");

  auto path = std::make_shared<PathOptions>();
  CLI::App* path_command = command->add_subcommand("path", "find a path on a saved navmesh");
  path_command->add_option("navmesh", path->navmesh, "navmesh set file")->required();
  path_command->add_option("--from", path->from, "start x,y,z")->required();
  path_command->add_option("--to", path->to, "target x,y,z")->required();
  path_command->add_flag("--json", path->json, "print JSON");
  AddProfileOption(*path_command, path->profile,
                   "the kind of walker the path is for (the file must be baked for it)");

  return [bake, path, merge, bake_command, path_command, merge_command] {
    if (bake_command->parsed()) return RunBake(*bake);
    if (merge_command->parsed()) return RunMerge(*merge);
    if (path_command->parsed()) return RunPath(*path);
    return 2;
  };
}

}  // namespace strata::cli
