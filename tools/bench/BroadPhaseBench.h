// BroadPhaseBench: the streamed open-world broad-phase benchmark (20,000 bodies in 28 tiles of 256 m):
// add, remove, move, rebuild and query costs, queries under concurrent change, the parallel game-object
// update with 1 vs 32 body mutexes, and Bullet's btDbvtBroadphase on the same work. Prints figures only.
// Call from the main thread.
#pragma once

#include <cstdint>
#include <vector>

#include "physics/broadphase/Layers.h"
#include "physics/math/AABB.h"

namespace strata::bench {

/// A streamed world: bodies grouped by 256 m tile, each tile a batch.
struct OpenWorld {
  std::vector<AABB> bounds;
  std::vector<ObjectLayer> layers;
  std::vector<std::uint32_t> tile_of;             ///< tile index per body
  std::vector<std::vector<std::uint32_t>> tiles;  ///< body indices per tile
  AABB extent;
};

/// `body_count` bodies over `tile_count` tiles of 256 m laid out 7 wide; about 70% static level geometry
/// (0.5-8 m) on the ground and 30% dynamic props (0.3-2 m) up to 30 m high. Fixed seed.
OpenWorld MakeOpenWorld(int body_count, int tile_count, unsigned seed);

/// The query work every engine runs: 12.8 x 12.8 x 20 m blocks, 10 m and 100 m rays.
struct QuerySet {
  std::vector<AABB> blocks;
  std::vector<Vec3> ray_origins;
  std::vector<Vec3> ray_directions_10m;
  std::vector<Vec3> ray_directions_100m;
};
QuerySet MakeQuerySet(const OpenWorld& world, int count, unsigned seed);

/// Figures one engine produced (microseconds unless named otherwise); negative = not measured.
struct BroadPhaseFigures {
  double prepare_per_body_us = -1;
  std::vector<double> finalize_us;  ///< per batch size in kBatchSizes
  double remove_us = -1;
  double move_us = -1;
  double full_rebuild_ms = -1;
  double incremental_rebuild_ms = -1;  ///< after 600 dynamic bodies moved (a step's worth of active bodies)
  double aabb_query_us = -1;
  double ray_10m_us = -1;
  double ray_100m_us = -1;
  double aabb_query_busy_us = -1;  ///< while two other threads add, remove and move
  double ray_10m_busy_us = -1;
  double ray_100m_busy_us = -1;
  double hits_per_block = 0;  ///< average bodies per 12.8 m block (a check that both engines agree)
  double hits_per_100m_ray = 0;
};

inline constexpr int kBatchSizes[] = {1, 100, 1000, 10000};

BroadPhaseFigures MeasureStrata(const OpenWorld& world, const QuerySet& queries);
#ifdef STRATA_HAVE_BULLET
/// btDbvtBroadphase: add = createProxy per body, remove = destroyProxy, move = setAabb, queries =
/// aabbTest / rayTest. Not thread-safe, so no figures under concurrent change.
BroadPhaseFigures MeasureBullet(const OpenWorld& world, const QuerySet& queries);
#endif

/// One row of the game-object update: T threads each move their own bodies and ray cast every frame.
struct GameObjectFigures {
  int threads = 0;
  std::uint32_t mutexes = 0;
  double work_us = 0;
  double frame_ms = 0;                       ///< median wall time of a frame
  double lock_wait_us_per_thread_frame = 0;  ///< mean over threads and frames
  double median_lock_wait_us = 0;            ///< median thread-frame (robust to a preempted lock holder)
  double p99_lock_wait_us = 0;               ///< 99th percentile thread-frame
  double max_lock_wait_us = 0;               ///< worst thread-frame
  double acquisitions_per_thread_frame = 0;  ///< body mutexes taken, mean over threads and frames
  double contended_per_thread_frame = 0;     ///< of those, found taken by another thread
};
/// `work_us` of busy work per object stands in for its game logic (outside any lock).
GameObjectFigures MeasureGameObjectUpdate(const OpenWorld& world, int threads, std::uint32_t mutexes,
                                          int frames, double work_us);

}  // namespace strata::bench
