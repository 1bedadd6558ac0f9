// Drop links: a ledge gets one-way links down to the ground below for an agent that may drop that far and
// none for one that may not; they are saved and loaded with their tile; a link whose landing lies in the
// next tile works once both tiles are ready.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "NavMeshTestWorld.h"
#include "tests/TempPath.h"

namespace strata::test {
namespace {

navmesh::NavMeshServiceConfig DropConfig(float max_drop) {
  navmesh::NavMeshServiceConfig config = FastServiceConfig();
  config.settings.agent_radius = 0.4f;
  config.settings.agent_height = 1.8f;
  config.settings.agent_max_climb = 0.5f;
  config.settings.agent_max_drop = max_drop;
  return config;
}

// Ground at y = 0 over two tiles along x, and on it a 1.5 m high platform from x = 4 to x = 10 (ramps,
// stairs and anything else that leads up are left out: the only way down is to drop).
void AddLedge(PhysicsSystem& world, float ledge_from_x = 4.0f, float ledge_to_x = 10.0f) {
  AddSlab(world, 0.0f, 25.6f, 0.0f, 12.8f, 0.0f);
  AddSlab(world, ledge_from_x, ledge_to_x, 3.0f, 9.0f, 1.5f, 1.5f);
}

navmesh::PathResult PathDown(const navmesh::NavMesh& navmesh, const Vec3& top, const Vec3& bottom) {
  return *MakeQuery(navmesh)->FindPath(top, bottom);
}

TEST(DropLinks, ALedgeOfOneAndAHalfMetresIsADropForTwoMetresAndNotForOne) {
  auto world = MakeWorld();
  AddLedge(*world);
  const Vec3 top(7.0f, 1.5f, 6.0f), bottom(7.0f, 0.0f, 11.5f);
  const auto dropper = BuildArea(*world, TileArea(1), DropConfig(2.0f));
  const auto walker = BuildArea(*world, TileArea(1), DropConfig(1.0f));
  EXPECT_GT(dropper->navmesh().link_count(), 4);  // along all four sides of the platform
  EXPECT_EQ(walker->navmesh().link_count(), 0);
  const navmesh::PathResult down = PathDown(dropper->navmesh(), top, bottom);
  EXPECT_TRUE(down.reached_end);
  EXPECT_LT(down.length, 9.0f);  // off the nearest edge, not round anything
  EXPECT_FALSE(PathDown(walker->navmesh(), top, bottom).reached_end);
  // One way: nothing climbs back up.
  EXPECT_FALSE(PathDown(dropper->navmesh(), bottom, top).reached_end);
  // The same navmesh as the walker's otherwise: the links add no ground.
  EXPECT_EQ(dropper->navmesh().polygon_count(), walker->navmesh().polygon_count());
}

TEST(DropLinks, AQueryThatAllowsNoLinksFindsWhatAWalkerReaches) {
  auto world = MakeWorld();
  AddLedge(*world);
  const auto service = BuildArea(*world, TileArea(1), DropConfig(2.0f));
  const Vec3 top(7.0f, 1.5f, 6.0f), bottom(7.0f, 0.0f, 11.5f);
  auto query = MakeQuery(service->navmesh());
  EXPECT_TRUE(query->FindPath(top, bottom)->reached_end);
  query->set_links_allowed(false);
  EXPECT_FALSE(query->FindPath(top, bottom)->reached_end);
  query->set_links_allowed(true);
  EXPECT_TRUE(query->FindPath(top, bottom)->reached_end);
}

TEST(DropLinks, RandomPointsAreOnGroundTheStartReachesAndRepeatWithTheSeed) {
  auto world = MakeWorld();
  AddLedge(*world);
  const auto dropper = BuildArea(*world, TileArea(1), DropConfig(2.0f));
  const auto walker = BuildArea(*world, TileArea(1), DropConfig(1.0f));
  const Vec3 top(7.0f, 1.5f, 6.0f);
  std::mt19937 first(5), again(5), walker_random(5);
  auto dropper_query = MakeQuery(dropper->navmesh()), walker_query = MakeQuery(walker->navmesh());
  int below = 0;
  for (int i = 0; i < 40; ++i) {
    const Result<Vec3> point = dropper_query->RandomPointAround(top, 30.0f, first);
    ASSERT_TRUE(point.ok()) << point.error().message;
    EXPECT_EQ(*point, *dropper_query->RandomPointAround(top, 30.0f, again));
    EXPECT_TRUE(dropper_query->FindPath(top, *point)->reached_end);
    below += point->y() < 0.5f;
    // Without a link down, the walker's points all lie on the platform.
    EXPECT_GT(walker_query->RandomPointAround(top, 30.0f, walker_random)->y(), 1.0f);
  }
  EXPECT_GT(below, 20) << "the ground below is most of what a dropper reaches";
  EXPECT_FALSE(dropper_query->RandomPointAround(top, -1.0f, first).ok());
  EXPECT_FALSE(dropper_query->RandomPointAround(Vec3(500, 0, 500), 10.0f, first).ok());
}

TEST(DropLinks, LinksAreSavedAndLoadedWithTheirTile) {
  auto world = MakeWorld();
  AddLedge(*world);
  const auto service = BuildArea(*world, TileArea(1), DropConfig(2.0f));
  const std::filesystem::path file = TempPath("drop_links.bin");
  ASSERT_TRUE(service->navmesh().Save(file).ok());
  const auto loaded = navmesh::NavMesh::Load(file);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ((*loaded)->link_count(), service->navmesh().link_count());
  const navmesh::PathResult down = PathDown(**loaded, Vec3(7.0f, 1.5f, 6.0f), Vec3(7.0f, 0.0f, 11.5f));
  EXPECT_TRUE(down.reached_end);
  std::filesystem::remove(file);
}

// A file without Strata's checksums (as RecastDemo writes them) is checked link by link: a link with a side
// Detour does not know, or no radius, is refused with its reason.
TEST(DropLinks, ACorruptLinkInAFileIsRefused) {
  auto world = MakeWorld();
  AddLedge(*world);
  const auto service = BuildArea(*world, TileArea(1), DropConfig(2.0f));
  ASSERT_EQ(service->navmesh().tile_count(), 1);
  const std::filesystem::path file = TempPath("drop_corrupt.bin");
  ASSERT_TRUE(service->navmesh().Save(file).ok());
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::size_t trailer = bytes.rfind("KCTS");  // the checksum trailer's magic, little-endian
  ASSERT_NE(trailer, std::string::npos);
  bytes.resize(trailer);  // the tile's last link now ends the file
  const auto load_with = [&](std::size_t from_end, const std::string& value) {
    std::string corrupt = bytes;
    corrupt.replace(corrupt.size() - from_end, value.size(), value);
    std::ofstream(file, std::ios::binary) << corrupt;
    return navmesh::NavMesh::Load(file);
  };
  ASSERT_TRUE(load_with(0, "").ok());
  // The last dtOffMeshConnection: pos[6], rad, poly, flags, side, userId (36 bytes).
  const auto bad_side = load_with(36 - 31, std::string(1, '\x09'));
  ASSERT_FALSE(bad_side.ok());
  EXPECT_NE(bad_side.error().message.find("has a bad side"), std::string::npos) << bad_side.error().message;
  const auto no_radius = load_with(36 - 24, std::string(4, '\0'));
  ASSERT_FALSE(no_radius.ok());
  EXPECT_NE(no_radius.error().message.find("has a bad radius"), std::string::npos)
      << no_radius.error().message;
  std::filesystem::remove(file);
}

TEST(DropLinks, ALinkIntoTheNextTileWorksOnceBothAreReady) {
  auto world = MakeWorld();
  // The platform ends 0.3 m before the tiles' shared edge at x = 12.8: its drops off that end land in tile 1.
  AddLedge(*world, 6.0f, 12.5f);
  const Vec3 top(10.0f, 1.5f, 6.0f), bottom(14.5f, 0.0f, 6.0f);
  auto service = MakeService(*world, DropConfig(2.0f));
  ASSERT_TRUE(service->RequestBox(TileArea(1)).ok());
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
  EXPECT_FALSE(PathDown(service->navmesh(), top, bottom).reached_end);  // nothing to land on yet
  ASSERT_TRUE(service->RequestBox(AABB(Vec3(12.9f, -1.0f, 0.1f), Vec3(25.5f, 1.0f, 12.7f))).ok());
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
  ASSERT_EQ(service->navmesh().tile_count(), 2);
  const navmesh::PathResult down = PathDown(service->navmesh(), top, bottom);
  EXPECT_TRUE(down.reached_end);
  EXPECT_LT(down.length, 6.0f);  // straight off the end into the next tile
}

}  // namespace
}  // namespace strata::test
