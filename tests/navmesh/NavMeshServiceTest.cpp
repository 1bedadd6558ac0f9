// The background service: request order and dedupe, dirty tracking (an obstacle added in a ready tile makes
// it stale, it rebuilds and the path changes; removing it brings the path back), bad input, and the
// RecastDemo "MSET" file format with corrupt files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "NavMeshTestWorld.h"
#include "navmesh/Validation.h"
#include "tests/TempPath.h"

namespace strata::test {
namespace {

using navmesh::TileCoord;
using navmesh::TileState;

constexpr float kTile = 12.8f;

TEST(NavMeshService, BuildsNearestTilesFirstAndOnlyOnce) {
  auto world = MakeWorld();
  AddFloor(*world, 5);
  const auto service = MakeService(*world, FastServiceConfig(1));
  const Vec3 agent(2.5f * kTile, 0.0f, 2.5f * kTile);
  ASSERT_TRUE(service->RequestAround(agent, 2.0f * kTile).ok());
  ASSERT_TRUE(service->RequestAround(agent, 2.0f * kTile).ok());  // duplicate: no extra work
  ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
  const auto log = service->build_log();
  ASSERT_EQ(log.size(), 21u);  // the 5 x 5 block minus its 4 corners
  float previous = 0.0f;
  for (const auto& record : log) {
    const Vec3 center = service->grid().Center(record.coord);
    const float distance = std::hypot(center.x() - agent.x(), center.z() - agent.z());
    EXPECT_GE(distance, previous - 1e-3f) << "tile (" << record.coord.x << ", " << record.coord.z << ")";
    previous = distance;
    EXPECT_EQ(service->GetTileState(record.coord), TileState::kReady);
  }
  EXPECT_EQ(service->GetTileState({0, 0}), TileState::kMissing);
  EXPECT_EQ(service->stats().ready, 21u);
}

TEST(NavMeshService, ObstacleMakesTileStaleRebuildsAndPathComesBackWhenRemoved) {
  auto world = MakeWorld();
  AddFloor(*world, 2);
  const auto service = BuildArea(*world, TileArea(2));
  const auto query = MakeQuery(service->navmesh());
  const Vec3 from(3.0f, 0.0f, kTile), to(2.0f * kTile - 3.0f, 0.0f, kTile);
  const auto before = query->FindPath(from, to);
  ASSERT_TRUE(before.ok() && before->reached_end);

  // A wall across the middle, with room to walk around it at both ends.
  const AABB wall(Vec3(kTile - 0.5f, 0.0f, 5.0f), Vec3(kTile + 0.5f, 2.0f, 2.0f * kTile - 5.0f));
  const auto wall_id =
      world->bodies().CreateAndAddBody(Static(Box(0.5f, 1.0f, 0.5f * wall.Size().z()), wall.Center()));
  ASSERT_TRUE(wall_id.ok());
  const std::size_t rebuilds = service->stats().rebuilds;
  ASSERT_TRUE(WaitForRebuilds(*service, rebuilds + 1));
  EXPECT_EQ(service->stats().rebuilds, rebuilds + 4);  // the wall's box touches all four tiles' borders
  const auto around = query->FindPath(from, to);
  ASSERT_TRUE(around.ok() && around->reached_end);
  EXPECT_FALSE(navmesh::PathCrossesBox(*around, wall));
  EXPECT_GT(around->length, before->length + 2.0f);

  ASSERT_TRUE(world->bodies().RemoveAndDestroyBody(*wall_id).ok());
  ASSERT_TRUE(WaitForRebuilds(*service, rebuilds + 5));
  const auto after = query->FindPath(from, to);
  ASSERT_TRUE(after.ok() && after->reached_end);
  EXPECT_FLOAT_EQ(after->length, before->length);
  EXPECT_EQ(after->points.size(), before->points.size());
}

TEST(NavMeshService, ARebuildThatFailsKeepsTheOldTilePublishedAndStale) {
  // In a table of 65,536 tiles Detour's references leave room for 64 polygons a tile. A floor needs a few;
  // a floor with a grid of pillars needs more than 64, so its rebuild cannot be published.
  auto world = MakeWorld();
  AddFloor(*world, 1);
  navmesh::NavMeshServiceConfig config = FastServiceConfig();
  config.max_tiles = navmesh::NavMeshService::kMaxTiles;
  const auto service = BuildArea(*world, TileArea(1), config);
  const int polygons = service->navmesh().polygon_count();
  ASSERT_GT(polygons, 0);
  ASSERT_LE(polygons, 64);
  const auto query = MakeQuery(service->navmesh());
  const Vec3 from(1.0f, 0.0f, 1.0f), to(11.8f, 0.0f, 11.8f);
  const auto before = query->FindPath(from, to);
  ASSERT_TRUE(before.ok() && before->reached_end);

  std::vector<BodyID> pillars;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      pillars.push_back(
          Add(*world, Static(Box(0.2f, 1.0f, 0.2f), Vec3(1.6f + 2.4f * i, 1.0f, 1.6f + 2.4f * j))));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (service->stats().failures == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_GE(service->stats().failures, 1u);
  EXPECT_NE(service->last_error().find("polygons, more than the 64 a tile holds"), std::string::npos)
      << service->last_error();
  EXPECT_EQ(service->GetTileState({0, 0}), TileState::kStale);
  EXPECT_TRUE(service->IsPublished({0, 0}));
  EXPECT_EQ(service->navmesh().polygon_count(), polygons);  // the old tile, still there for agents
  const auto during = query->FindPath(from, to);
  ASSERT_TRUE(during.ok() && during->reached_end);
  EXPECT_EQ(during->points, before->points);
  EXPECT_TRUE(service->WaitUntilIdle(std::chrono::seconds(5)));  // waiting to retry is not pending work

  // Without the pillars the retry succeeds.
  for (const BodyID pillar : pillars) ASSERT_TRUE(world->bodies().RemoveAndDestroyBody(pillar).ok());
  while (service->GetTileState({0, 0}) != TileState::kReady && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_EQ(service->GetTileState({0, 0}), TileState::kReady);
  EXPECT_EQ(service->navmesh().polygon_count(), polygons);
}

TEST(NavMeshService, AnAgentWalksAcrossAWorldLargerThanTheTileBudget) {
  // A floor of 20 x 3 tiles and a budget of 9: the agent asks for the tiles around it every 6.4 m; the
  // tiles behind it (requested longest ago) make room for the ones ahead, and it always has a navmesh.
  auto world = MakeWorld();
  AddSlab(*world, 0.0f, 20 * kTile, 0.0f, 3 * kTile, 0.0f);
  navmesh::NavMeshServiceConfig config = FastServiceConfig();
  config.max_tiles = 9;
  const auto service = MakeService(*world, config);
  const auto query = MakeQuery(service->navmesh());
  std::size_t most_records = 0;
  for (float x = kTile + 0.2f; x + kTile < 20 * kTile; x += 6.4f) {  // the circle stays on the floor
    const Vec3 agent(x, 0.0f, 1.5f * kTile);
    ASSERT_TRUE(service->RequestAround(agent, kTile).ok());
    ASSERT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
    const navmesh::NavMeshServiceStats stats = service->stats();
    ASSERT_EQ(stats.failures, 0u) << service->last_error();
    EXPECT_LE(stats.tiles_holding_data, 9u);
    EXPECT_LE(service->navmesh().tile_count(), 9);
    EXPECT_EQ(service->GetTileState(service->grid().TileAt(agent)), TileState::kReady) << x;
    EXPECT_TRUE(service->IsPublished(service->grid().TileAt(agent))) << x;
    const auto ahead = query->FindPath(agent, agent + Vec3(10.0f, 0.0f, 0.0f));
    ASSERT_TRUE(ahead.ok()) << x << ": " << ahead.error().message;
    EXPECT_TRUE(ahead->reached_end) << x;
    most_records = std::max(most_records, static_cast<std::size_t>(stats.queued + stats.ready + stats.stale));
    // The counts stats() keeps as states change agree with the states themselves, evictions included.
    std::size_t ready = 0;
    for (int z = -1; z <= 3; ++z)
      for (int tx = -1; tx <= 20; ++tx) ready += service->GetTileState({tx, z}) == TileState::kReady;
    EXPECT_EQ(stats.ready, ready) << x;
  }
  const navmesh::NavMeshServiceStats stats = service->stats();
  EXPECT_GE(stats.evictions, 40u);  // 60 tiles built with room for 9 at a time
  EXPECT_EQ(stats.builds, stats.evictions + stats.tiles_holding_data);  // each tile built once, none twice
  EXPECT_LE(most_records, 4u * 9u + 64u);
  // The start of the walk has been given up; a new request there builds it again.
  EXPECT_EQ(service->GetTileState({0, 1}), TileState::kMissing);
  EXPECT_FALSE(service->IsPublished({0, 1}));
  EXPECT_FALSE(service->IsPublished({0, 1}, 5));  // no such profile: nothing published
}

TEST(NavMeshService, SmallMovesAndDebrisLeaveTilesReady) {
  auto world = MakeWorld();
  AddFloor(*world, 1);
  const BodyID crate = Add(*world, Static(Box(1.0f, 1.0f, 1.0f), Vec3(6, 1, 6)));
  const auto service = BuildArea(*world, TileArea(1));
  ASSERT_TRUE(world->bodies().SetPosition(crate, Vec3(6.1f, 1.0f, 6.0f)).ok());  // below the 0.25 m threshold
  Add(*world, Dynamic(Box(0.2f, 0.2f, 0.2f), Vec3(3, 0.2f, 3)));                 // debris does not count
  // Two whole scans after the changes compared the tile with the world and left it alone.
  const std::size_t scans = service->stats().scans;
  ASSERT_TRUE(WaitForScans(*service, scans + 2, std::chrono::steady_clock::now() + std::chrono::seconds(30)));
  EXPECT_EQ(service->GetTileState({0, 0}), TileState::kReady);
  EXPECT_EQ(service->stats().builds, 1u);
  ASSERT_TRUE(world->bodies().SetPosition(crate, Vec3(8.0f, 1.0f, 6.0f)).ok());
  ASSERT_TRUE(WaitForRebuilds(*service, 1));
  EXPECT_EQ(service->GetTileState({0, 0}), TileState::kReady);
}

TEST(NavMeshService, RejectsBadConfigAndRequests) {
  auto world = MakeWorld();
  navmesh::NavMeshServiceConfig config;
  config.settings.agent_max_slope = 95.0f;
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());
  config = {};
  config.settings.cell_size = std::nanf("");
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());
  config = {};
  config.settings.verts_per_poly = 7;
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());
  config = {};
  config.thread_niceness = -1;
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());
  config = {};
  config.worker_threads = 0;
  EXPECT_FALSE(navmesh::NavMeshService::Create(*world, config).ok());

  const auto service = MakeService(*world, FastServiceConfig());
  EXPECT_FALSE(service->RequestAround(Vec3(std::nanf(""), 0, 0), 10.0f).ok());
  EXPECT_FALSE(service->RequestAround(Vec3::Zero(), -1.0f).ok());
  EXPECT_FALSE(service->RequestAround(Vec3::Zero(), 1.0e6f).ok());
  EXPECT_FALSE(service->RequestBox(AABB()).ok());
  EXPECT_EQ(service->stats().queued, 0u);
  const auto query = MakeQuery(service->navmesh());
  EXPECT_FALSE(query->FindPath(Vec3(0, std::nanf(""), 0), Vec3::Zero()).ok());
  EXPECT_FALSE(query->FindNearestPoly(Vec3(1, 0, 1)).ok());  // nothing built yet
}

TEST(TileGrid, TileCountMatchesTheListingForOddAndFarBoxes) {
  const navmesh::TileGrid grid(kTile);
  // A 20 m floor, a 6 m floor at x 3..9, an 80 x 90 m level off the grid, a box far from the origin.
  const AABB boxes[] = {{Vec3(-10, 0, -10), Vec3(10, 1, 10)},
                        {Vec3(3, 0, 3), Vec3(9, 1, 9)},
                        {Vec3(-41.3f, -2, 7.7f), Vec3(38.9f, 5, 97.9f)},
                        {Vec3(1.0e5f, 0, -2.0e5f), Vec3(1.0e5f + 50.0f, 1, -2.0e5f + 30.0f)}};
  for (const AABB& box : boxes) EXPECT_EQ(grid.TileCount(box), grid.TilesInBox(box).size());
  EXPECT_EQ(grid.TileCount(AABB()), 0u);
  // A level one corrupt vertex made 3e16 m long: counted without listing, then refused with its extent.
  const AABB corrupt(Vec3(-12.8f, 0, -3.4e16f), Vec3(12.8f, 1, 12.8f));
  EXPECT_GT(grid.TileCount(corrupt), std::uint64_t{1} << 40);
  EXPECT_TRUE(grid.TilesInBox(corrupt).empty());
  const Result<int> refused = navmesh::NavMeshService::MaxTilesToCover(corrupt, kTile);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("more than a navmesh holds"), std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find("3.4e+16 m"), std::string::npos) << refused.error().message;
}

TEST(NavMeshService, ABoxOfExactlyMaxTilesIsAccepted) {
  // The table sized from a box's tile count takes a request for that box (an estimate once refused it).
  auto world = MakeWorld();
  for (const AABB& box : {AABB(Vec3(-10, 0, -10), Vec3(10, 1, 10)), AABB(Vec3(3, 0, 3), Vec3(9, 1, 9)),
                          AABB(Vec3(-41.3f, -2, 7.7f), Vec3(38.9f, 5, 97.9f))}) {
    navmesh::NavMeshServiceConfig config = FastServiceConfig();
    const Result<int> tiles = navmesh::NavMeshService::MaxTilesToCover(box, config.settings.tile_size());
    ASSERT_TRUE(tiles.ok()) << tiles.error().message;
    config.max_tiles = *tiles;
    const auto service = MakeService(*world, config);
    EXPECT_TRUE(service->RequestBox(box).ok());
    config.max_tiles = *tiles - 1;
    if (config.max_tiles > 0) {
      const Status refused = MakeService(*world, config)->RequestBox(box);
      ASSERT_FALSE(refused.ok());
      EXPECT_NE(refused.message().find("more than max_tiles"), std::string::npos) << refused.message();
    }
  }
}

class NavMeshFile : public ::testing::Test {
 protected:
  void SetUp() override {
    world_ = MakeWorld();
    AddFloor(*world_, 2);
    AddSlab(*world_, 10.0f, 16.0f, 10.0f, 16.0f, 2.0f, 2.0f);
    service_ = BuildArea(*world_, TileArea(2));
    path_ = TempPath(std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".bin");
    ASSERT_TRUE(service_->navmesh().Save(path_).ok());
    std::ifstream file(path_, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  /// The saved file as RecastDemo writes it: the same tiles without Strata's checksum trailer.
  std::vector<char> RecastDemoBytes() const {
    std::int32_t tiles = 0;
    std::memcpy(&tiles, bytes_.data() + 8, sizeof(tiles));
    std::size_t end = 40;
    for (std::int32_t i = 0; i < tiles; ++i) {
      std::int32_t size = 0;
      std::memcpy(&size, bytes_.data() + end + 4, sizeof(size));
      end += 8 + static_cast<std::size_t>(size);
    }
    return {bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(end)};
  }
  void Write(const std::vector<char>& bytes) const {
    std::ofstream file(path_, std::ios::binary | std::ios::trunc);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }

  std::unique_ptr<PhysicsSystem> world_;
  std::unique_ptr<navmesh::NavMeshService> service_;
  std::filesystem::path path_;
  std::vector<char> bytes_;
};

TEST_F(NavMeshFile, SaveAndLoadGiveTheSamePaths) {
  ASSERT_GE(bytes_.size(), 40u);
  EXPECT_EQ(std::string(bytes_.begin(), bytes_.begin() + 4), "TESM");  // 'MSET' as a little-endian int
  const auto loaded = navmesh::NavMesh::Load(path_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ((*loaded)->Tiles(), service_->navmesh().Tiles());
  EXPECT_EQ((*loaded)->polygon_count(), service_->navmesh().polygon_count());
  const Vec3 from(2, 0, 2), to(23, 0, 23);
  const auto original = MakeQuery(service_->navmesh())->FindPath(from, to);
  const auto reloaded = MakeQuery(**loaded)->FindPath(from, to);
  ASSERT_TRUE(original.ok() && reloaded.ok());
  EXPECT_TRUE(reloaded->reached_end);
  EXPECT_EQ(reloaded->points, original->points);
}

TEST_F(NavMeshFile, BadFilesGiveClearErrors) {
  const auto expect_error = [&](const char* why, const std::string& fragment) {
    const auto loaded = navmesh::NavMesh::Load(path_);
    ASSERT_FALSE(loaded.ok()) << why;
    EXPECT_NE(loaded.error().message.find(path_.filename().string()), std::string::npos) << why;
    EXPECT_NE(loaded.error().message.find(fragment), std::string::npos) << loaded.error().message;
  };
  std::filesystem::remove(path_);
  expect_error("missing", "file not found");
  Write({'M', 'S'});
  expect_error("tiny", "too short");
  std::vector<char> bytes = bytes_;
  bytes[0] = 'X';
  Write(bytes);
  expect_error("magic", "bad magic");
  ASSERT_GT(bytes_.size(), 100u);
  const std::vector<char> recast_demo = RecastDemoBytes();
  Write(std::vector<char>(recast_demo.begin(), recast_demo.end() - 10));
  expect_error("truncated", "truncated");
  Write(std::vector<char>(bytes_.begin(), bytes_.end() - 10));
  expect_error("trailer cut short", "unexpected bytes after the last tile");
  bytes = bytes_;
  bytes.push_back(0);
  Write(bytes);
  expect_error("trailing", "unexpected bytes");
}

// A tile whose sizes all agree but whose geometry is wrong used to load and quietly change paths: NaN
// vertices, NaN bounds, a tile that names another grid cell than its bounds lie in.
TEST_F(NavMeshFile, TilesWithBadGeometryAreRefused) {
  // The first tile follows the set header (40 bytes) and its tile header (8); in Detour's tile header x is
  // the third int, bmin starts at byte 72, and the vertices follow the 100-byte header.
  constexpr std::size_t kFirstTile = 48, kCellX = kFirstTile + 8, kBoundsMin = kFirstTile + 72,
                        kFirstVertex = kFirstTile + 100;
  // Without checksums (RecastDemo's form), so that what is checked is the tile's geometry.
  const std::vector<char> recast_demo = RecastDemoBytes();
  const auto with = [&](std::size_t offset, auto value) {
    std::vector<char> bytes = recast_demo;
    std::memcpy(bytes.data() + offset, &value, sizeof(value));
    Write(bytes);
    const auto loaded = navmesh::NavMesh::Load(path_);
    return loaded.ok() ? std::string("loaded") : loaded.error().message;
  };
  const float nan = std::nanf("");
  EXPECT_NE(with(kFirstVertex, nan).find("corrupt tile 0: vertex 0 is not finite or lies outside the tile"),
            std::string::npos);
  EXPECT_NE(with(kFirstVertex + 4, 1.0e6f).find("vertex 0 is not finite or lies outside"), std::string::npos);
  EXPECT_NE(with(kBoundsMin, nan).find("bounds are not finite"), std::string::npos);
  std::int32_t cell_x = 0;
  std::memcpy(&cell_x, bytes_.data() + kCellX, sizeof(cell_x));
  EXPECT_NE(with(kCellX, cell_x - 1).find("but its bounds lie elsewhere"), std::string::npos);
  EXPECT_EQ(with(kCellX, cell_x), "loaded");  // the offsets are right: the unchanged file loads
}

TEST_F(NavMeshFile, AFlippedBitInATileIsAnError) {
  // A flip that keeps the tile's structure valid (a detail height, an area byte) loaded before checksums and
  // changed paths silently; every byte of the first tile and the set header is tried.
  const auto loaded_after_flip = [&](std::size_t byte, int bit) {
    std::vector<char> bytes = bytes_;
    bytes[byte] = static_cast<char>(bytes[byte] ^ (1 << bit));
    Write(bytes);
    return navmesh::NavMesh::Load(path_);
  };
  std::int32_t first_tile_size = 0;
  std::memcpy(&first_tile_size, bytes_.data() + 44, sizeof(first_tile_size));
  const std::size_t checked = 48 + static_cast<std::size_t>(first_tile_size);
  for (std::size_t byte = 0; byte < checked; ++byte) {
    const auto loaded = loaded_after_flip(byte, static_cast<int>(byte % 8));
    ASSERT_FALSE(loaded.ok()) << "byte " << byte << " flipped, and the file loaded";
  }
  const auto in_tile = loaded_after_flip(48 + 200, 3);
  ASSERT_FALSE(in_tile.ok());
  EXPECT_NE(in_tile.error().message.find("tile 0 does not match its checksum"), std::string::npos)
      << in_tile.error().message;
}

TEST_F(NavMeshFile, ARecastDemoFileWithoutChecksumsStillLoads) {
  Write(RecastDemoBytes());
  const auto loaded = navmesh::NavMesh::Load(path_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_FALSE((*loaded)->coverage().known());
  const Vec3 from(2, 0, 2), to(23, 0, 23);
  const auto original = MakeQuery(service_->navmesh())->FindPath(from, to);
  const auto reloaded = MakeQuery(**loaded)->FindPath(from, to);
  ASSERT_TRUE(original.ok() && reloaded.ok());
  EXPECT_EQ(reloaded->points, original->points);
}

// What fuzz_navmesh found, each as the one change to the baked arena (tests/fuzz/seeds) that matters; the
// files it wrote are kept in tests/fuzz/found and must all be refused.
class NavMeshFuzzFindings : public ::testing::Test {
 protected:
  static constexpr std::size_t kFirstTile = 48;  // after the set header (40) and the tile header (8)
  void SetUp() override {
    std::ifstream file(std::filesystem::path(STRATA_FUZZ_FOUND_DIR) / "../seeds/navmesh/arena.bin",
                       std::ios::binary);
    seed_.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    ASSERT_EQ(seed_.size(), 8280u);
  }
  // The load error for the seed with `bytes` written at `offset`.
  std::string LoadWith(std::size_t offset, const std::vector<unsigned char>& bytes) {
    std::vector<char> edited = seed_;
    std::copy(bytes.begin(), bytes.end(), edited.begin() + static_cast<std::ptrdiff_t>(offset));
    // A name of this test's own: ctest runs the fixture's tests in parallel processes.
    const auto path = TempPath(std::string("fuzz_finding_") +
                               ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".bin");
    std::ofstream(path, std::ios::binary).write(edited.data(), static_cast<std::streamsize>(edited.size()));
    const auto loaded = navmesh::NavMesh::Load(path);
    std::filesystem::remove(path);
    return loaded.ok() ? "loaded" : loaded.error().message;
  }
  std::int32_t IntAt(std::size_t offset) const {
    std::int32_t value = 0;
    std::memcpy(&value, seed_.data() + offset, sizeof(value));
    return value;
  }
  std::vector<char> seed_;
};

TEST_F(NavMeshFuzzFindings, EveryFileFoundIsRefused) {
  EXPECT_EQ(LoadWith(0, {}), "loaded");
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(STRATA_FUZZ_FOUND_DIR)) {
    if (entry.path().filename().string().rfind("navmesh_", 0) != 0) continue;
    ++files;
    EXPECT_FALSE(navmesh::NavMesh::Load(entry.path()).ok()) << entry.path();
  }
  EXPECT_GE(files, 3);
}

TEST_F(NavMeshFuzzFindings, ADetailTriangleWithARepeatedCornerIsRefused) {
  // Tile 3's first detail triangle (after 100 header bytes, 18 vertices, 12 polygons, 46 links, 12 detail
  // meshes and 15 detail vertices) made (0, 0, 0): Detour's nearest-point search then finds no edge of the
  // polygon and reads through a null pointer.
  const std::size_t tile3 = 6188,
                    first_triangle = tile3 + 100 + 18 * 12 + 12 * 32 + 46 * 12 + 12 * 12 + 15 * 12;
  EXPECT_NE(LoadWith(first_triangle, {0, 0, 0})
                .find("corrupt tile 3: polygon 0 has a detail triangle with a repeated corner"),
            std::string::npos);
}

TEST_F(NavMeshFuzzFindings, DetailTrianglesWithoutOutlineEdgesAreRefused) {
  // The same triangle's edge flags (its fourth byte) turned from "all three on the outline" (21) to 234:
  // no outline edge is left for Detour's nearest-point fallback, which then reads through a null pointer.
  const std::size_t tile3 = 6188,
                    first_triangle = tile3 + 100 + 18 * 12 + 12 * 32 + 46 * 12 + 12 * 12 + 15 * 12;
  EXPECT_NE(LoadWith(first_triangle + 3, {234})
                .find("corrupt tile 3: polygon 0 has a detail triangle with bad edge flags"),
            std::string::npos);
  EXPECT_NE(LoadWith(first_triangle + 3, {0})
                .find("polygon 0 has fewer outline edges in its detail mesh than sides"),
            std::string::npos);
}

TEST_F(NavMeshFuzzFindings, ATileTableTooLargeForAReferenceIsRefused) {
  // maxTiles (bytes 32-35 of the set header) 4 made 22,532: 15 tile bits and the seed's 18 polygon bits leave
  // no room for the salt, which Detour computes unsigned and wraps; its references then decode wrong.
  EXPECT_NE(LoadWith(33, {88}).find("leave no room for the salt"), std::string::npos);
}

TEST_F(NavMeshFuzzFindings, AnExternalLinkThroughNoSideIsRefused) {
  // A border edge of tile 0 (neighbour 0) made 0xffff, a link out of the tile through no side: Detour links
  // the tile to itself and a path query reads through a null pointer.
  const std::size_t polygons = kFirstTile + 100 + 12 * static_cast<std::size_t>(IntAt(kFirstTile + 28));
  for (int p = 0; p < IntAt(kFirstTile + 24); ++p) {
    const std::size_t poly = polygons + 32 * static_cast<std::size_t>(p);
    const int corners = static_cast<unsigned char>(seed_[poly + 30]);
    for (int v = 0; v < corners; ++v) {
      const std::size_t neighbour = poly + 16 + 2 * static_cast<std::size_t>(v);
      if (seed_[neighbour] != 0 || seed_[neighbour + 1] != 0) continue;
      EXPECT_NE(LoadWith(neighbour, {0xff, 0xff})
                    .find("corrupt tile 0: polygon " + std::to_string(p) +
                          " has a neighbour that is neither in the tile nor a side"),
                std::string::npos);
      return;
    }
  }
  FAIL() << "no border edge in tile 0";
}

TEST_F(NavMeshFuzzFindings, ANeighbourThatDoesNotNameThePolygonBackIsRefused) {
  // The file that sent a raycast round in circles: one polygon names another that does not share the edge.
  const auto loaded =
      navmesh::NavMesh::Load(std::filesystem::path(STRATA_FUZZ_FOUND_DIR) / "navmesh_raycast_cycle.bin");
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().message.find("as a neighbour it does not share an edge with"), std::string::npos)
      << loaded.error().message;
}

TEST_F(NavMeshFile, RandomCorruptionNeverCrashesLoadOrQueries) {
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> position(0, bytes_.size() - 1);
  std::uniform_int_distribution<int> value(0, 255);
  int rejected = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<char> bytes = bytes_;
    for (int flips = 0; flips < 4; ++flips) bytes[position(random)] = static_cast<char>(value(random));
    Write(bytes);
    const auto loaded = navmesh::NavMesh::Load(path_);
    if (!loaded.ok()) {
      ++rejected;
      continue;
    }
    // Whatever was accepted must be safe to query (ASan would catch reads outside a tile).
    const auto query = MakeQuery(**loaded);
    (void)query->FindPath(Vec3(2, 0, 2), Vec3(23, 0, 23));
    (void)query->Raycast(Vec3(2, 0, 2), Vec3(23, 0, 2));
    (void)navmesh::CountIslands(**loaded);
  }
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace strata::test
