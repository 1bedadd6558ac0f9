// NavMeshService: builds navmesh tiles in the background from a physics world that keeps changing, one
// navmesh per agent profile (kind of walker). Agents call RequestAround for their profiles; the service's own
// worker threads (never the physics step's) gather each tile once from a pinned broad-phase generation, build
// it with Recast for every profile that asked and publish each into its profile's NavMesh. A scanner
// thread marks ready tiles stale when counted bodies in them are added, removed or moved, and queues
// them again after a debounce delay. Every public method is thread-safe. RequestAround, RequestBox,
// GetTileState and stats touch only a small front lock that the service's low-priority threads hold for a few
// instructions, so a game thread never waits behind a job or a scan.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <thread>
#include <vector>

#include "navmesh/NavMesh.h"
#include "navmesh/NavMeshServiceConfig.h"
#include "navmesh/NavMeshSettings.h"
#include "navmesh/TileBuilder.h"
#include "navmesh/TileGather.h"
#include "navmesh/TileGrid.h"

namespace strata {
class PhysicsSystem;
}

namespace strata::navmesh {

/// Where a tile is in its life.
enum class TileState { kMissing, kQueued, kBuilding, kReady, kStale };
const char* ToString(TileState state);

/// One finished build of one tile for one profile.
struct TileBuildRecord {
  TileCoord coord;
  int profile = 0;
  int build = 0;  ///< 1 for the first build of the tile, 2 for its first rebuild, ...
  std::size_t bodies = 0;
  std::size_t triangles = 0;
  int polygons = 0;
  double gather_ms = 0.0;            ///< the tile's one gather, shared by the profiles built with it
  double recast_ms = 0.0;            ///< this profile's Recast work, with its share of a shared rasterization
  double publish_ms = 0.0;           ///< time the NavMesh was held exclusively
  double request_to_ready_ms = 0.0;  ///< from the request (or going stale) to published
  int polygons_from = -1;  ///< the profile whose polygons it took (their walkable cells were the same), or -1
};

/// Counters over the service's life (of one profile, or summed over them).
struct NavMeshServiceStats {
  std::size_t builds = 0;
  std::size_t rebuilds = 0;  ///< builds of tiles that had gone stale
  std::size_t failures = 0;
  std::size_t queued = 0;
  std::size_t building = 0;
  std::size_t ready = 0;
  std::size_t stale = 0;
  std::size_t scans = 0;      ///< finished scans, each of which compared every ready tile with the world
  std::size_t evictions = 0;  ///< published tiles dropped to make room within max_tiles
  std::size_t tiles_holding_data = 0;  ///< published tiles with polygons (at most max_tiles a profile)
  std::size_t gathers = 0;             ///< tile gathers (one per job, for all the profiles it builds)
  std::size_t polygons_taken = 0;  ///< builds that took another profile's polygons (the same walkable cells)

  NavMeshServiceStats& operator+=(const NavMeshServiceStats& other);
};

/// The background navmesh builder for one physics world (which must outlive it).
class NavMeshService {
 public:
  static Result<std::unique_ptr<NavMeshService>> Create(const PhysicsSystem& world,
                                                        const NavMeshServiceConfig& config);
  /// The most tiles a navmesh holds (Detour's reference bits).
  static constexpr int kMaxTiles = 1 << 16;
  /// The `max_tiles` that lets RequestBox(box) cover `box` with tiles of `tile_size`: its tile count, or an
  /// error naming the box's extent when that is more than a navmesh holds (a corrupt level, a unit mix-up).
  static Result<int> MaxTilesToCover(const AABB& box, float tile_size);
  /// Stops the threads; a job in progress finishes its current tile first.
  ~NavMeshService();
  NavMeshService(const NavMeshService&) = delete;
  NavMeshService& operator=(const NavMeshService&) = delete;

  /// Queues, for each profile in `profiles`, the tiles the x-z circle touches that are missing or stale,
  /// nearest to a requester first. Tiles already queued move up if this requester is nearer. Fails for a
  /// non-finite or negative input, or a mask naming no profile of the service.
  Status RequestAround(const Vec3& position, float radius, ProfileMask profiles = kAllProfiles);
  /// RequestAround for many requesters at once (a crowd's agents): each tile is queued once, by its nearest
  /// point, under one lock. Fails, queueing nothing, if any point or the radius would fail RequestAround.
  Status RequestAroundPoints(std::span<const Vec3> points, float radius, ProfileMask profiles = kAllProfiles);
  /// Queues the tiles overlapping `box` (x-z), e.g. a whole level for a bake.
  Status RequestBox(const AABB& box, ProfileMask profiles = kAllProfiles);

  /// Marks the ready tiles overlapping `box` (x-z) stale, for changes the service cannot see (geometry
  /// outside the physics world, a new filter); they rebuild after the debounce delay.
  Status Invalidate(const AABB& box, ProfileMask profiles = kAllProfiles);

  TileState GetTileState(TileCoord tile, int profile = 0) const;
  /// Whether the tile's navmesh (perhaps empty) is published for the profile: true from its first build until
  /// it is evicted, also while it is stale and a rebuild is queued or running (its old polygons stay walkable
  /// until the new ones replace them).
  bool IsPublished(TileCoord tile, int profile = 0) const;
  /// Blocks until no tile is queued, building or stale, or the timeout passes; true when idle. For tools
  /// and tests; a game polls GetTileState instead.
  bool WaitUntilIdle(std::chrono::milliseconds timeout) const;

  int profile_count() const { return static_cast<int>(profiles_.size()); }
  const AgentProfile& profile(int index) const { return profiles_[static_cast<std::size_t>(index)].profile; }
  /// The index of the profile called `name`, or an error listing the service's profiles.
  Result<int> FindProfile(const std::string& name) const;
  /// What profile `index` is built with: the shared settings, its agent, the shared border and merge climb.
  /// A single-profile service created with these builds the same tile bytes.
  const NavMeshSettings& profile_settings(int index = 0) const {
    return profiles_[static_cast<std::size_t>(index)].settings;
  }
  const NavMesh& navmesh(int profile = 0) const {
    return *profiles_[static_cast<std::size_t>(profile)].navmesh;
  }
  NavMesh& navmesh(int profile = 0) { return *profiles_[static_cast<std::size_t>(profile)].navmesh; }
  const TileGrid& grid() const { return grid_; }
  const NavMeshServiceConfig& config() const { return config_; }
  /// Summed over the profiles; touches only the front lock, so a game thread may poll it every frame.
  NavMeshServiceStats stats() const;
  NavMeshServiceStats profile_stats(int profile) const;
  /// Every finished build so far, in the order they finished.
  std::vector<TileBuildRecord> build_log() const;
  /// The most recent error from a build, empty when none failed.
  std::string last_error() const;

 private:
  using Clock = std::chrono::steady_clock;
  /// One profile's tile.
  struct ProfileTile {
    int profile = 0;
    TileCoord coord;
    friend bool operator<(const ProfileTile& a, const ProfileTile& b) {
      return a.profile != b.profile ? a.profile < b.profile : a.coord < b.coord;
    }
  };
  struct TileRecord {
    TileState state = TileState::kMissing;
    float priority = 0.0f;  ///< squared distance to the nearest requester
    int builds = 0;
    int failed_in_a_row = 0;           ///< builds that failed since the last that was published
    bool holds_data = false;           ///< its published tile has polygons (takes a slot of the budget)
    Clock::time_point last_requested;  ///< the most recent request that touched it (eviction order)
    float last_priority = 0.0f;        ///< that request's squared distance to the tile
    Clock::time_point requested;       ///< when it was requested or went stale
    Clock::time_point stale_since;
    std::shared_ptr<const std::vector<GatheredBody>> bodies;  ///< what the published tile was built from
  };
  /// A profile's navmesh and the back end's accounts of it.
  struct Profile {
    AgentProfile profile;
    NavMeshSettings settings;  ///< resolved
    int max_tiles = 0;
    std::unique_ptr<NavMesh> navmesh;
    int tiles_holding_data = 0;    // mutex_
    NavMeshServiceStats counters;  // mutex_: builds, failures, evictions
  };

  /// A request waiting in the front inbox until a worker moves it into the queue.
  struct PendingRequest {
    TileCoord tile;
    float priority;
    Clock::time_point when;
    ProfileMask profiles;
  };

  NavMeshService(const PhysicsSystem& world, const NavMeshServiceConfig& config,
                 std::vector<Profile> profiles);
  Status CheckMask(ProfileMask profiles) const;
  void Submit(std::vector<PendingRequest> requests);
  void WakeWorkers();
  void DrainInbox();                                                      // mutex_ held
  void Enqueue(ProfileTile tile, float priority, Clock::time_point now);  // mutex_ held
  void QueueCoord(TileCoord coord, float priority);                       // mutex_ held
  void SetState(ProfileTile tile, TileRecord& record, TileState state);   // mutex_ held
  void SetFrontState(ProfileTile tile, TileState state);                  // front_mutex_ held
  void ForgetFrontState(ProfileTile tile);                                // takes front_mutex_
  void MirrorCounters();                                                  // mutex_ held; takes front_mutex_
  Status MakeRoom(ProfileTile tile);   // mutex_ held: evicts a published tile if the profile's budget is full
  void ForgetOldRecords(int profile);  // mutex_ held: bounds the records of tiles that hold nothing
  void WorkerLoop();
  void BuildOne(TileCoord coord, const std::vector<int>& profiles);
  void Publish(ProfileTile tile, Result<BuiltTile>& built, TileBuildRecord record,
               const std::vector<GatheredBody>& bodies);  // mutex_ held
  void ScannerLoop();
  void QueueDueRetries(Clock::time_point now);  // mutex_ held
  bool TileChanged(const std::vector<GatheredBody>& now, const std::vector<GatheredBody>& bodies) const;
  bool Idle() const;  // mutex_ held
  /// How long a stale tile waits before it is queued: the debounce, longer after each failed rebuild.
  Clock::duration RetryDelay(const TileRecord& record) const;

  const PhysicsSystem& world_;
  const NavMeshServiceConfig config_;
  const TileGrid grid_;
  /// The gather box is the same for every profile: the shared settings' border is the widest agent's.
  const NavMeshSettings& gather_settings() const { return profiles_.front().settings; }
  std::vector<Profile> profiles_;

  // Back end: everything below mutex_ is the workers' and the scanner's.
  mutable std::mutex mutex_;
  mutable std::condition_variable state_changed_;
  std::map<ProfileTile, TileRecord> tiles_;
  std::set<std::pair<float, TileCoord>> queue_;  // (priority, tile): nearest first, ties in tile order
  std::map<TileCoord, float> queued_;            // the priority each queued tile has in queue_
  std::vector<TileBuildRecord> log_;
  std::size_t gathers_ = 0;
  std::size_t scans_ = 0;
  std::string last_error_;
  bool stopping_ = false;

  // Front: what game threads touch. Requests wait here, and every state change is mirrored here, so the
  // front lock is only ever held for a vector append or a map write.
  mutable std::mutex front_mutex_;
  std::vector<PendingRequest> inbox_;
  std::map<ProfileTile, TileState> front_states_;
  std::set<ProfileTile> front_published_;  // tiles that went ready and were not evicted since
  // Per profile: state counts kept with front_states_, counters mirrored from the back.
  std::vector<NavMeshServiceStats> front_stats_;
  std::atomic<std::uint64_t> work_epoch_{0};  // bumped (and waited on) whenever workers may have work

  std::vector<std::thread> workers_;
  std::thread scanner_;
};

}  // namespace strata::navmesh
