// Helpers shared by the navmesh tests: static level pieces as physics bodies, and a service that is built
// and waited for.
#pragma once

#include <thread>

#include "../physics/TestWorld.h"
#include "navmesh/NavMeshQuery.h"
#include "navmesh/NavMeshService.h"
#include "navmesh/TileBuilder.h"

namespace strata::test {

/// A static box with its top face at `top` (m), spanning [min_x, max_x] x [min_z, max_z].
inline BodyID AddSlab(PhysicsSystem& world, float min_x, float max_x, float min_z, float max_z, float top,
                      float thickness = 1.0f) {
  const Vec3 half(0.5f * (max_x - min_x), 0.5f * thickness, 0.5f * (max_z - min_z));
  return Add(world, Static(Box(half.x(), half.y(), half.z()),
                           Vec3(0.5f * (min_x + max_x), top - half.y(), 0.5f * (min_z + max_z))));
}

/// The floor of tiles (0, 0) to (tiles - 1, tiles - 1) at y = 0.
inline BodyID AddFloor(PhysicsSystem& world, int tiles, float tile_size = 12.8f) {
  return AddSlab(world, 0.0f, tiles * tile_size, 0.0f, tiles * tile_size, 0.0f);
}

inline navmesh::NavMeshServiceConfig FastServiceConfig(int workers = 1) {
  navmesh::NavMeshServiceConfig config;
  config.worker_threads = workers;
  config.rebuild_delay = std::chrono::milliseconds(10);
  config.scan_interval = std::chrono::milliseconds(5);
  return config;
}

inline std::unique_ptr<navmesh::NavMeshService> MakeService(const PhysicsSystem& world,
                                                            const navmesh::NavMeshServiceConfig& config) {
  auto service = navmesh::NavMeshService::Create(world, config);
  EXPECT_TRUE(service.ok()) << (service.ok() ? "" : service.error().message);
  return std::move(*service);
}

/// Builds the tiles overlapping `box` and waits for them.
inline std::unique_ptr<navmesh::NavMeshService> BuildArea(
    const PhysicsSystem& world, const AABB& box,
    const navmesh::NavMeshServiceConfig& config = FastServiceConfig()) {
  auto service = MakeService(world, config);
  EXPECT_TRUE(service->RequestBox(box).ok());
  EXPECT_TRUE(service->WaitUntilIdle(std::chrono::seconds(60)));
  EXPECT_EQ(service->stats().failures, 0u) << service->last_error();
  return service;
}

inline AABB TileArea(int tiles, float tile_size = 12.8f) {
  const float inset = 0.01f;  // stay inside the last tile instead of touching the next one
  return {Vec3(inset, -1.0f, inset), Vec3(tiles * tile_size - inset, 1.0f, tiles * tile_size - inset)};
}

inline std::unique_ptr<navmesh::NavMeshQuery> MakeQuery(const navmesh::NavMesh& navmesh) {
  auto query = navmesh::NavMeshQuery::Create(navmesh);
  EXPECT_TRUE(query.ok());
  return std::move(*query);
}

/// Waits until the scanner has finished `scans` scans in all.
inline bool WaitForScans(const navmesh::NavMeshService& service, std::size_t scans,
                         std::chrono::steady_clock::time_point deadline) {
  while (service.stats().scans < scans) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

/// Waits until the service is idle and stays so over two whole scans that began after it was idle (the
/// first may have started earlier): then every change made before this call has been seen and rebuilt,
/// however slow the machine (sanitizer builds), with no sleep tuned to it.
inline bool WaitUntilSettled(const navmesh::NavMeshService& service,
                             std::chrono::seconds timeout = std::chrono::seconds(60)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!service.WaitUntilIdle(std::chrono::milliseconds(100))) continue;
    const navmesh::NavMeshServiceStats before = service.stats();
    if (!WaitForScans(service, before.scans + 2, deadline)) return false;
    const navmesh::NavMeshServiceStats after = service.stats();
    if (after.builds == before.builds && after.queued + after.building + after.stale == 0) return true;
  }
  return false;
}

/// Waits until the service has finished at least `rebuilds` rebuilds, then until it has settled.
inline bool WaitForRebuilds(const navmesh::NavMeshService& service, std::size_t rebuilds,
                            std::chrono::seconds timeout = std::chrono::seconds(60)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (service.stats().rebuilds < rebuilds) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WaitUntilSettled(service, timeout);
}

}  // namespace strata::test
