// Agent profiles: one service builds a navmesh per kind of walker from one gather of each tile; each
// profile's tiles are the bytes a service for that profile alone builds; a passage wide enough for a person
// is closed to a machine.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

#include "NavMeshTestWorld.h"
#include "navmesh/LevelBake.h"
#include "tests/TempPath.h"

namespace strata::test {
namespace {

using navmesh::AgentProfile;

navmesh::NavMeshServiceConfig ThreeProfiles(int workers = 1) {
  navmesh::NavMeshServiceConfig config = FastServiceConfig(workers);
  config.profiles = {AgentProfile::Person(), AgentProfile::Machine(), AgentProfile::Critter()};
  return config;
}

// Two tiles by two of ground with a bit of everything a profile reads differently: walls with a 1.2 m gap,
// steps of 0.3, 0.7 and 1.2 m, a 40 degree ramp, a low shelf only a critter fits under, and a crate.
void AddVariedGround(PhysicsSystem& world) {
  AddFloor(world, 2);
  AddSlab(world, 10.0f, 10.6f, 0.0f, 11.4f, 3.0f);   // a wall along z...
  AddSlab(world, 10.0f, 10.6f, 12.6f, 25.6f, 3.0f);  // ...and its other half, 1.2 m further on
  AddSlab(world, 2.0f, 5.0f, 2.0f, 5.0f, 0.3f);
  AddSlab(world, 2.0f, 5.0f, 6.0f, 9.0f, 0.7f);
  AddSlab(world, 2.0f, 5.0f, 10.0f, 13.0f, 1.2f);
  const Quat tilt(Eigen::AngleAxisf(40.0f * kPi / 180.0f, Vec3::UnitZ()));
  Add(world, Static(Box(3.0f, 0.2f, 2.0f), Vec3(16.0f, 1.5f, 4.0f), tilt));
  AddSlab(world, 14.0f, 20.0f, 16.0f, 20.0f, 1.2f, 0.2f);  // a shelf 1 m above the floor
  Add(world, Static(Box(0.8f, 0.8f, 0.8f), Vec3(18.0f, 0.8f, 10.0f)));
}

std::string Bytes(const navmesh::NavMesh& navmesh, const std::string& name) {
  const std::filesystem::path path = TempPath("profile_" + name + ".bin");
  EXPECT_TRUE(navmesh.Save(path).ok());
  std::ifstream file(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  return bytes;
}

TEST(AgentProfiles, EachProfilesTilesAreTheBytesOfAServiceForItAlone) {
  auto world = MakeWorld();
  AddVariedGround(*world);
  const auto shared = BuildArea(*world, TileArea(2), ThreeProfiles(2));
  ASSERT_EQ(shared->profile_count(), 3);
  for (int p = 0; p < shared->profile_count(); ++p) {
    navmesh::NavMeshServiceConfig alone = FastServiceConfig();
    alone.settings = shared->profile_settings(p);
    alone.profiles = {shared->profile(p)};  // named alike: the saved set names its profile
    const auto single = BuildArea(*world, TileArea(2), alone);
    EXPECT_GT(single->navmesh().polygon_count(), 0) << shared->profile(p).name;
    EXPECT_EQ(Bytes(shared->navmesh(p), "shared"), Bytes(single->navmesh(), "alone"))
        << shared->profile(p).name;
  }
  // The profiles differ, yet every tile was gathered once for all three.
  EXPECT_NE(shared->navmesh(0).WalkableArea(), shared->navmesh(1).WalkableArea());
  EXPECT_NE(shared->navmesh(0).WalkableArea(), shared->navmesh(2).WalkableArea());
  const navmesh::NavMeshServiceStats stats = shared->stats();
  EXPECT_EQ(stats.gathers, 4u);
  EXPECT_EQ(stats.builds, 12u);
  for (const navmesh::TileBuildRecord& record : shared->build_log()) EXPECT_GT(record.triangles, 0u);
}

TEST(AgentProfiles, AProfileWhoseWalkableCellsMatchAnEarlierOnesTakesItsPolygonsAndKeepsItsOwnBytes) {
  // Open floor, where a person and a critter (both two cells of radius) have the same walkable cells, and in
  // the far tile a shelf 1 m up that a critter walks under and a person does not.
  auto world = MakeWorld();
  AddFloor(*world, 2);
  AddSlab(*world, 18.0f, 22.0f, 18.0f, 22.0f, 1.2f, 0.2f);
  const auto shared = BuildArea(*world, TileArea(2), ThreeProfiles(2));
  std::size_t records = 0;
  for (const navmesh::TileBuildRecord& record : shared->build_log()) {
    ++records;
    const bool shelf_tile = record.coord == navmesh::TileCoord{1, 1};
    // Only the critter takes, from the person, and not where the shelf makes their cells differ.
    const int expected = record.profile == 2 && !shelf_tile ? 0 : -1;
    EXPECT_EQ(record.polygons_from, expected)
        << "profile " << record.profile << " tile " << record.coord.x << ", " << record.coord.z;
  }
  EXPECT_EQ(records, 12u);
  EXPECT_EQ(shared->stats().polygons_taken, 3u);
  for (int p = 0; p < shared->profile_count(); ++p) {
    navmesh::NavMeshServiceConfig alone = FastServiceConfig();
    alone.settings = shared->profile_settings(p);
    alone.profiles = {shared->profile(p)};
    const auto single = BuildArea(*world, TileArea(2), alone);
    EXPECT_EQ(single->stats().polygons_taken, 0u);
    EXPECT_EQ(Bytes(shared->navmesh(p), "shared"), Bytes(single->navmesh(), "alone"))
        << shared->profile(p).name;
    EXPECT_EQ(shared->navmesh(p).TilesCrc(), single->navmesh().TilesCrc());
  }
  // Taken polygons, yet each profile's own tiles: the critter's bytes are not the person's.
  EXPECT_NE(shared->navmesh(0).TilesCrc(), shared->navmesh(2).TilesCrc());
}

TEST(AgentProfiles, APassageWideEnoughForAPersonIsClosedToAMachine) {
  auto world = MakeWorld();
  AddFloor(*world, 4);
  // A wall across the ground from z = 0 to z = 51.2 with one 1.2 m gap in the middle.
  AddSlab(*world, 25.0f, 26.0f, 0.0f, 25.0f, 4.0f);
  AddSlab(*world, 25.0f, 26.0f, 26.2f, 51.2f, 4.0f);
  const auto service = BuildArea(*world, TileArea(4), ThreeProfiles());
  const Vec3 from(15.0f, 0.0f, 25.6f), to(36.0f, 0.0f, 25.6f);
  const int person = *service->FindProfile("person"), machine = *service->FindProfile("machine");
  const navmesh::PathResult walker = *MakeQuery(service->navmesh(person))->FindPath(from, to);
  EXPECT_TRUE(walker.reached_end);
  EXPECT_LT(walker.length, 23.0f);  // straight through the gap
  // The machine's navmesh keeps 2.5 m from the wall: it has ground on both sides but no way between them.
  const auto machine_query = MakeQuery(service->navmesh(machine));
  ASSERT_TRUE(machine_query->FindNearestPoly(Vec3(10.0f, 0.0f, 25.6f)).ok());
  ASSERT_TRUE(machine_query->FindNearestPoly(Vec3(41.0f, 0.0f, 25.6f)).ok());
  const navmesh::PathResult big =
      *machine_query->FindPath(Vec3(10.0f, 0.0f, 25.6f), Vec3(41.0f, 0.0f, 25.6f));
  EXPECT_FALSE(big.reached_end);
}

TEST(AgentProfiles, RequestsNameTheProfilesTheyWant) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  auto service = MakeService(*world, ThreeProfiles());
  const int critter = *service->FindProfile("critter");
  ASSERT_TRUE(service->RequestBox(TileArea(1), navmesh::ProfileMask{1} << critter).ok());
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
  EXPECT_EQ(service->GetTileState({0, 0}, critter), navmesh::TileState::kReady);
  EXPECT_EQ(service->GetTileState({0, 0}, 0), navmesh::TileState::kMissing);
  EXPECT_EQ(service->navmesh(0).tile_count(), 0);
  EXPECT_EQ(service->profile_stats(critter).builds, 1u);
  EXPECT_EQ(service->stats().builds, 1u);
  // A mask naming no profile of the service, and a name it does not have, are errors.
  EXPECT_FALSE(service->RequestAround(Vec3(5, 0, 5), 5.0f, navmesh::ProfileMask{1} << 7).ok());
  const Result<int> missing = service->FindProfile("thunderjaw");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("person, machine, critter"), std::string::npos);
}

TEST(AgentProfiles, BadProfilesAreRefusedWhole) {
  auto world = MakeWorld();
  navmesh::NavMeshServiceConfig config = ThreeProfiles();
  config.profiles[1].name = "person";
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());
  config.profiles[1].name = "big machine";
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());
  config.profiles[1] = AgentProfile::Machine();
  config.profiles[1].radius = -1.0f;
  const auto bad = navmesh::NavMeshService::Create(*world, config);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("profile 'machine'"), std::string::npos) << bad.error().message;
  EXPECT_FALSE(AgentProfile::Named("thunderjaw").ok());
  EXPECT_EQ(AgentProfile::Named("critter")->radius, 0.25f);
}

TEST(AgentProfiles, ASavedSetNamesItsProfileAndShardsOfTwoProfilesDoNotMerge) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  navmesh::NavMeshServiceConfig config = FastServiceConfig();
  config.profiles = {AgentProfile::Person(), AgentProfile::Machine()};
  const auto service = BuildArea(*world, TileArea(2), config);
  const std::filesystem::path directory = TempPath("profile_sets");
  std::filesystem::create_directories(directory);
  ASSERT_TRUE(service->navmesh(0).Save(directory / "person.bin").ok());
  ASSERT_TRUE(service->navmesh(1).Save(directory / "machine.bin").ok());
  const auto machine = navmesh::NavMesh::Load(directory / "machine.bin");
  ASSERT_TRUE(machine.ok()) << machine.error().message;
  EXPECT_EQ((*machine)->profile(), "machine");
  EXPECT_EQ((*machine)->polygon_count(), service->navmesh(1).polygon_count());
  // A single-agent service names none: its file is the older format, which loads with no name.
  const auto unnamed_service = BuildArea(*world, TileArea(1));
  ASSERT_TRUE(unnamed_service->navmesh().Save(directory / "unnamed.bin").ok());
  EXPECT_EQ((*navmesh::NavMesh::Load(directory / "unnamed.bin"))->profile(), "");
  // The name is under the header's checksum: a changed letter is damage, not another profile.
  std::string bytes;
  {
    std::ifstream file(directory / "machine.bin", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  const std::size_t at = bytes.rfind("machine");
  ASSERT_NE(at, std::string::npos);
  bytes[at] = 'n';
  std::ofstream(directory / "renamed.bin", std::ios::binary) << bytes;
  const auto renamed = navmesh::NavMesh::Load(directory / "renamed.bin");
  ASSERT_FALSE(renamed.ok());
  EXPECT_NE(renamed.error().message.find("damaged"), std::string::npos) << renamed.error().message;
  // Two profiles' files are no shards of one bake.
  const auto merged = navmesh::MergeShards({directory / "person.bin", directory / "machine.bin"}, true);
  ASSERT_FALSE(merged.ok());
  EXPECT_NE(merged.error().message.find("agent profile 'machine'"), std::string::npos)
      << merged.error().message;
  std::filesystem::remove_all(directory);
}

// Three profiles on two workers while another thread adds, moves and removes crates: every profile ends with
// every tile ready and the bytes a fresh build of the final world gives it.
TEST(AgentProfilesThreads, ThreeProfilesBuildAndRebuildWhileTheWorldChanges) {
  auto world = MakeWorld({}, 512);
  AddFloor(*world, 2);
  auto service = MakeService(*world, ThreeProfiles(2));
  std::thread mutator([&] {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> across(2.0f, 23.0f);
    std::vector<BodyID> crates;
    for (int op = 0; op < 200; ++op) {
      if (crates.size() < 8 || random() % 3 == 0) {
        auto id =
            world->bodies().CreateAndAddBody(Static(Box(1, 1, 1), Vec3(across(random), 1, across(random))));
        if (id) crates.push_back(*id);
      } else if (random() % 2 == 0) {
        EXPECT_TRUE(world->bodies().RemoveAndDestroyBody(crates.back()).ok());
        crates.pop_back();
      } else {
        EXPECT_TRUE(
            world->bodies().SetPosition(crates.front(), Vec3(across(random), 1, across(random))).ok());
      }
      if (op % 10 == 0) {
        EXPECT_TRUE(service->RequestBox(TileArea(2)).ok());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  mutator.join();
  ASSERT_TRUE(service->RequestBox(TileArea(2)).ok());
  ASSERT_TRUE(WaitUntilSettled(*service, std::chrono::seconds(120)));
  EXPECT_EQ(service->stats().failures, 0u) << service->last_error();
  for (int p = 0; p < service->profile_count(); ++p) {
    for (int z = 0; z < 2; ++z) {
      for (int x = 0; x < 2; ++x) {
        EXPECT_EQ(service->GetTileState({x, z}, p), navmesh::TileState::kReady);
      }
    }
    navmesh::NavMeshServiceConfig alone = FastServiceConfig();
    alone.settings = service->profile_settings(p);
    alone.profiles = {service->profile(p)};
    const auto fresh = BuildArea(*world, TileArea(2), alone);
    EXPECT_EQ(Bytes(service->navmesh(p), "live"), Bytes(fresh->navmesh(), "fresh"))
        << service->profile(p).name;
  }
}

}  // namespace
}  // namespace strata::test
