// About 640 lines, on purpose: the service's front (requests, mirrored tile states and counters) and its back
// end (per-profile records, the queue, publishing and eviction, the scanner) work on the same records under
// the same two locks; split into files they would each reach into the other's private state.
#include "navmesh/NavMeshService.h"

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#endif

#include "navmesh/TileBuilder.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::navmesh {

namespace {

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

float SquaredPlanarDistance(const Vec3& a, const Vec3& b) {
  const float dx = a.x() - b.x();
  const float dz = a.z() - b.z();
  return dx * dx + dz * dz;
}

bool MovedBeyond(const AABB& before, const AABB& now, float threshold) {
  return (before.min - now.min).cwiseAbs().maxCoeff() > threshold ||
         (before.max - now.max).cwiseAbs().maxCoeff() > threshold;
}

/// Lowers the calling thread's priority by `niceness` (best effort: failing leaves it as it was).
void LowerThisThreadPriority(int niceness) {
#if defined(__linux__)
  if (niceness <= 0) return;
  const auto thread = static_cast<id_t>(::syscall(SYS_gettid));
  errno = 0;
  const int current = ::getpriority(PRIO_PROCESS, thread);
  if (errno == 0) (void)::setpriority(PRIO_PROCESS, thread, std::min(19, current + niceness));
#else
  (void)niceness;
#endif
}

}  // namespace

const char* ToString(TileState state) {
  switch (state) {
    case TileState::kMissing:
      return "missing";
    case TileState::kQueued:
      return "queued";
    case TileState::kBuilding:
      return "building";
    case TileState::kReady:
      return "ready";
    case TileState::kStale:
      return "stale";
  }
  return "?";
}

NavMeshServiceStats& NavMeshServiceStats::operator+=(const NavMeshServiceStats& other) {
  builds += other.builds, rebuilds += other.rebuilds, failures += other.failures;
  queued += other.queued, building += other.building, ready += other.ready, stale += other.stale;
  evictions += other.evictions, tiles_holding_data += other.tiles_holding_data;
  polygons_taken += other.polygons_taken;
  // Scans and gathers are the service's, not a profile's: every profile's copy holds the same count.
  scans = other.scans, gathers = other.gathers;
  return *this;
}

Result<int> NavMeshService::MaxTilesToCover(const AABB& box, float tile_size) {
  if (!box.IsValid()) return MakeError(ErrorCode::kInvalidArgument, "navmesh: the box to cover is not valid");
  const std::uint64_t tiles = TileGrid(tile_size).TileCount(box);
  if (tiles <= static_cast<std::uint64_t>(kMaxTiles)) return static_cast<int>(tiles);
  const Vec3 size = box.Size();
  char extent[128];
  std::snprintf(extent, sizeof(extent), "%.4g m x %.4g m, %llu tiles of %.4g m",
                static_cast<double>(size.x()), static_cast<double>(size.z()),
                static_cast<unsigned long long>(tiles), static_cast<double>(tile_size));
  return MakeError(ErrorCode::kInvalidArgument, std::string("navmesh: the level spans ") + extent +
                                                    ", more than a navmesh holds (" +
                                                    std::to_string(kMaxTiles) + ")");
}

Result<std::unique_ptr<NavMeshService>> NavMeshService::Create(const PhysicsSystem& world,
                                                               const NavMeshServiceConfig& config) {
  if (Status status = config.Validate(); !status.ok()) return status.error();
  std::vector<AgentProfile> agents = config.profiles;
  if (agents.empty()) agents.push_back(AgentProfile::FromSettings(config.settings));
  // One rasterization serves them all: the border of the widest, walkable flags merged within the lowest
  // climb (each profile's own climb still decides its ledges and steps).
  float widest = 0.0f, lowest_climb = agents.front().max_climb;
  for (const AgentProfile& agent : agents)
    widest = std::max(widest, agent.radius), lowest_climb = std::min(lowest_climb, agent.max_climb);
  std::vector<Profile> profiles;
  for (const AgentProfile& agent : agents) {
    Profile profile{agent,
                    agent.Apply(config.settings),
                    agent.max_tiles > 0 ? agent.max_tiles : config.max_tiles,
                    nullptr,
                    0,
                    {}};
    if (agents.size() > 1) {
      profile.settings.raster_border_radius = widest;
      profile.settings.raster_merge_climb = lowest_climb;
    }
    if (Status valid = profile.settings.Validate(); !valid)
      return MakeError(valid.error().code, "profile '" + agent.name + "': " + valid.message());
    Result<std::unique_ptr<NavMesh>> navmesh =
        NavMesh::Create(profile.settings.tile_size(), profile.max_tiles, profile.settings.origin_tile,
                        config.profiles.empty() ? std::string() : agent.name);
    if (!navmesh) return navmesh.error();
    profile.navmesh = std::move(*navmesh);
    profiles.push_back(std::move(profile));
  }
  return std::unique_ptr<NavMeshService>(new NavMeshService(world, config, std::move(profiles)));
}

NavMeshService::NavMeshService(const PhysicsSystem& world, const NavMeshServiceConfig& config,
                               std::vector<Profile> profiles)
    : world_(world),
      config_(config),
      grid_(config.settings.tile_size()),
      profiles_(std::move(profiles)),
      front_stats_(profiles_.size()) {
  // Here, on the creator's thread: enabling copies the bodies already in the world under their locks, the
  // only body locks the service ever takes.
  world_.body_snapshots().Enable(world_.body_manager());
  for (int i = 0; i < config_.worker_threads; ++i)
    workers_.emplace_back([this] {
      LowerThisThreadPriority(config_.thread_niceness);
      WorkerLoop();
    });
  scanner_ = std::thread([this] {
    LowerThisThreadPriority(config_.thread_niceness);
    ScannerLoop();
  });
}

NavMeshService::~NavMeshService() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  WakeWorkers();
  state_changed_.notify_all();
  for (std::thread& worker : workers_) worker.join();
  scanner_.join();
}

Result<int> NavMeshService::FindProfile(const std::string& name) const {
  std::string names;
  for (std::size_t i = 0; i < profiles_.size(); ++i) {
    if (profiles_[i].profile.name == name) return static_cast<int>(i);
    names += (i ? ", " : "") + profiles_[i].profile.name;
  }
  return MakeError(ErrorCode::kInvalidArgument,
                   "navmesh: no agent profile is named '" + name + "' (this service has " + names + ")");
}

Status NavMeshService::CheckMask(ProfileMask profiles) const {
  const ProfileMask all = profiles_.size() >= 32 ? kAllProfiles : (ProfileMask{1} << profiles_.size()) - 1;
  if ((profiles & all) != 0) return Status::Ok();
  return MakeError(ErrorCode::kInvalidArgument,
                   "navmesh request: the profile mask names none of the service's " +
                       std::to_string(profiles_.size()) + " profiles");
}

Status NavMeshService::RequestAround(const Vec3& position, float radius, ProfileMask profiles) {
  return RequestAroundPoints(std::span<const Vec3>(&position, 1), radius, profiles);
}

Status NavMeshService::RequestAroundPoints(std::span<const Vec3> points, float radius, ProfileMask profiles) {
  if (!std::isfinite(radius) || radius < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh request: radius must be a finite number >= 0");
  if (Status mask = CheckMask(profiles); !mask) return mask;
  // Only an absurd radius is refused. Tiles with nothing walkable (off the level) take no slot in the tile
  // table, so a circle wider than the level is a normal request, however small the table.
  const Vec3 reach(radius, 0.0f, radius);
  for (const Vec3& position : points) {
    if (!IsFinite(position))
      return MakeError(ErrorCode::kInvalidArgument, "navmesh request: position is not finite");
    if (Status in_reach =
            CheckReach(AABB(position, position).Expanded(radius), gather_settings(), "the request");
        !in_reach)
      return in_reach;
    const std::uint64_t tiles = grid_.TileCount(AABB(position - reach, position + reach));
    if (tiles > static_cast<std::uint64_t>(kMaxTiles))
      return MakeError(ErrorCode::kInvalidArgument, "navmesh request: a radius of " + std::to_string(radius) +
                                                        " m touches " + std::to_string(tiles) +
                                                        " tiles, more than a navmesh holds (" +
                                                        std::to_string(kMaxTiles) + ")");
  }
  // Each tile once, by its nearest requester: every (tile, distance) pair, sorted, the first of each tile
  // kept.
  const Clock::time_point now = Clock::now();
  std::vector<PendingRequest> requests;
  for (const Vec3& position : points)
    grid_.ForEachTileInCircle(position, radius, [&](TileCoord tile) {
      requests.push_back({tile, SquaredPlanarDistance(grid_.Center(tile), position), now, profiles});
    });
  std::sort(requests.begin(), requests.end(), [](const PendingRequest& a, const PendingRequest& b) {
    return a.tile != b.tile ? a.tile < b.tile : a.priority < b.priority;
  });
  requests.erase(
      std::unique(requests.begin(), requests.end(),
                  [](const PendingRequest& a, const PendingRequest& b) { return a.tile == b.tile; }),
      requests.end());
  if (!requests.empty()) Submit(std::move(requests));
  return Status::Ok();
}

Status NavMeshService::RequestBox(const AABB& box, ProfileMask profiles) {
  if (!box.IsValid()) return MakeError(ErrorCode::kInvalidArgument, "navmesh request: box is not valid");
  if (Status mask = CheckMask(profiles); !mask) return mask;
  if (Status reach = CheckReach(box, gather_settings(), "the requested box"); !reach) return reach;
  // The same count as the listing below (an estimate here once refused boxes the listing fits).
  const std::uint64_t tiles = grid_.TileCount(box);
  for (std::size_t p = 0; p < profiles_.size(); ++p) {
    if (!(profiles & (ProfileMask{1} << p)) || tiles <= static_cast<std::uint64_t>(profiles_[p].max_tiles))
      continue;
    return MakeError(ErrorCode::kInvalidArgument, "navmesh request: box covers " + std::to_string(tiles) +
                                                      " tiles, more than max_tiles (" +
                                                      std::to_string(profiles_[p].max_tiles) + ")");
  }
  const Clock::time_point now = Clock::now();
  std::vector<PendingRequest> requests;
  for (const TileCoord tile : grid_.TilesInBox(box))
    requests.push_back({tile, SquaredPlanarDistance(grid_.Center(tile), box.Center()), now, profiles});
  Submit(std::move(requests));
  return Status::Ok();
}

void NavMeshService::Submit(std::vector<PendingRequest> requests) {
  {
    const std::lock_guard lock(front_mutex_);
    for (const PendingRequest& request : requests) {
      for (std::size_t p = 0; p < profiles_.size(); ++p) {
        if (!(request.profiles & (ProfileMask{1} << p))) continue;
        const ProfileTile tile{static_cast<int>(p), request.tile};
        const auto found = front_states_.find(tile);
        if (found == front_states_.end() || found->second == TileState::kMissing)
          SetFrontState(tile, TileState::kQueued);
      }
    }
    inbox_.insert(inbox_.end(), requests.begin(), requests.end());
  }
  WakeWorkers();
}

void NavMeshService::WakeWorkers() {
  work_epoch_.fetch_add(1, std::memory_order_release);
  work_epoch_.notify_all();
}

void NavMeshService::DrainInbox() {
  std::vector<PendingRequest> requests;
  {
    const std::lock_guard lock(front_mutex_);
    requests.swap(inbox_);
  }
  for (const PendingRequest& request : requests)
    for (std::size_t p = 0; p < profiles_.size(); ++p)
      if (request.profiles & (ProfileMask{1} << p))
        Enqueue({static_cast<int>(p), request.tile}, request.priority, request.when);
}

void NavMeshService::SetState(ProfileTile tile, TileRecord& record, TileState state) {
  record.state = state;
  const std::lock_guard lock(front_mutex_);
  SetFrontState(tile, state);
}

namespace {
std::size_t* CountOf(NavMeshServiceStats& stats, TileState state) {
  switch (state) {
    case TileState::kQueued:
      return &stats.queued;
    case TileState::kBuilding:
      return &stats.building;
    case TileState::kReady:
      return &stats.ready;
    case TileState::kStale:
      return &stats.stale;
    case TileState::kMissing:
      return nullptr;
  }
  return nullptr;
}
}  // namespace

void NavMeshService::SetFrontState(ProfileTile tile, TileState state) {
  TileState& front = front_states_[tile];
  NavMeshServiceStats& stats = front_stats_[static_cast<std::size_t>(tile.profile)];
  if (std::size_t* count = CountOf(stats, front)) --*count;
  if (std::size_t* count = CountOf(stats, state)) ++*count;
  front = state;
  if (state == TileState::kReady) front_published_.insert(tile);
  if (state == TileState::kMissing) front_published_.erase(tile);
}

void NavMeshService::ForgetFrontState(ProfileTile tile) {
  const std::lock_guard lock(front_mutex_);
  const auto found = front_states_.find(tile);
  if (found == front_states_.end()) return;
  if (std::size_t* count = CountOf(front_stats_[static_cast<std::size_t>(tile.profile)], found->second))
    --*count;
  front_states_.erase(found);
  front_published_.erase(tile);
}

void NavMeshService::MirrorCounters() {
  const std::lock_guard lock(front_mutex_);
  for (std::size_t p = 0; p < profiles_.size(); ++p) {
    const Profile& profile = profiles_[p];
    NavMeshServiceStats& front = front_stats_[p];
    front.builds = profile.counters.builds;
    front.rebuilds = profile.counters.rebuilds;
    front.polygons_taken = profile.counters.polygons_taken;
    front.failures = profile.counters.failures;
    front.evictions = profile.counters.evictions;
    front.tiles_holding_data = static_cast<std::size_t>(profile.tiles_holding_data);
    front.scans = scans_;
    front.gathers = gathers_;
  }
}

Status NavMeshService::Invalidate(const AABB& box, ProfileMask profiles) {
  if (!box.IsValid()) return MakeError(ErrorCode::kInvalidArgument, "navmesh invalidate: box is not valid");
  if (Status mask = CheckMask(profiles); !mask) return mask;
  const Clock::time_point now = Clock::now();
  const std::lock_guard lock(mutex_);
  for (auto& [tile, record] : tiles_) {
    if (!(profiles & (ProfileMask{1} << tile.profile))) continue;
    if (record.state != TileState::kReady || !grid_.Bounds(tile.coord).Overlaps(box)) continue;
    SetState(tile, record, TileState::kStale);
    record.stale_since = now;
  }
  return Status::Ok();
}

void NavMeshService::QueueCoord(TileCoord coord, float priority) {
  const auto [found, inserted] = queued_.try_emplace(coord, priority);
  if (!inserted) {
    if (priority >= found->second) return;
    queue_.erase({found->second, coord});
    found->second = priority;
  }
  queue_.insert({priority, coord});
}

void NavMeshService::Enqueue(ProfileTile tile, float priority, Clock::time_point now) {
  TileRecord& record = tiles_[tile];
  record.last_requested = now;
  record.last_priority = priority;
  switch (record.state) {
    case TileState::kMissing:
      SetState(tile, record, TileState::kQueued);
      record.priority = priority;
      record.requested = now;
      QueueCoord(tile.coord, priority);
      return;
    case TileState::kQueued:
      record.priority = std::min(record.priority, priority);
      QueueCoord(tile.coord, priority);
      return;
    case TileState::kStale:  // waits out its debounce in the scanner
    case TileState::kBuilding:
    case TileState::kReady:
      record.priority = std::min(record.priority, priority);
      return;
  }
}

TileState NavMeshService::GetTileState(TileCoord tile, int profile) const {
  const std::lock_guard lock(front_mutex_);
  const auto found = front_states_.find({profile, tile});
  return found == front_states_.end() ? TileState::kMissing : found->second;
}

bool NavMeshService::IsPublished(TileCoord tile, int profile) const {
  const std::lock_guard lock(front_mutex_);
  return front_published_.count({profile, tile}) > 0;
}

bool NavMeshService::Idle() const {
  if (!queue_.empty()) return false;
  {
    const std::lock_guard lock(front_mutex_);
    if (!inbox_.empty()) return false;
  }
  // A stale tile whose rebuild failed waits for its retry with its old data published: nothing is pending.
  for (const auto& [tile, record] : tiles_)
    if (record.state == TileState::kBuilding ||
        (record.state == TileState::kStale && record.failed_in_a_row == 0))
      return false;
  return true;
}

NavMeshService::Clock::duration NavMeshService::RetryDelay(const TileRecord& record) const {
  if (record.failed_in_a_row == 0) return config_.rebuild_delay;
  // Doubling from 100 ms up to about 13 s: a tile that cannot be built costs little while it cannot.
  const Clock::duration first =
      std::max<Clock::duration>(config_.rebuild_delay, std::chrono::milliseconds(100));
  return first * (1 << std::min(record.failed_in_a_row - 1, 7));
}

bool NavMeshService::WaitUntilIdle(std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  return state_changed_.wait_for(lock, timeout, [this] { return Idle(); });
}

NavMeshServiceStats NavMeshService::stats() const {
  const std::lock_guard lock(front_mutex_);
  NavMeshServiceStats total;
  for (const NavMeshServiceStats& profile : front_stats_) total += profile;
  return total;
}

NavMeshServiceStats NavMeshService::profile_stats(int profile) const {
  const std::lock_guard lock(front_mutex_);
  return front_stats_.at(static_cast<std::size_t>(profile));
}

std::vector<TileBuildRecord> NavMeshService::build_log() const {
  const std::lock_guard lock(mutex_);
  return log_;
}

std::string NavMeshService::last_error() const {
  const std::lock_guard lock(mutex_);
  return last_error_;
}

void NavMeshService::WorkerLoop() {
  while (true) {
    // Read the epoch before looking for work: a request submitted after this changes it, so the wait
    // below returns at once instead of missing the wake-up.
    const std::uint64_t epoch = work_epoch_.load(std::memory_order_acquire);
    std::unique_lock lock(mutex_);
    if (stopping_) return;
    DrainInbox();
    if (queue_.empty()) {
      lock.unlock();
      state_changed_.notify_all();  // the inbox may just have been emptied into nothing new
      work_epoch_.wait(epoch, std::memory_order_acquire);
      continue;
    }
    const TileCoord coord = queue_.begin()->second;
    queue_.erase(queue_.begin());
    queued_.erase(coord);
    // Every profile queued at this tile is built from the one gather.
    std::vector<int> profiles;
    for (int p = 0; p < profile_count(); ++p) {
      const auto found = tiles_.find({p, coord});
      if (found == tiles_.end() || found->second.state != TileState::kQueued) continue;
      SetState({p, coord}, found->second, TileState::kBuilding);
      profiles.push_back(p);
    }
    if (profiles.empty()) continue;  // nothing left to build there (no gather for it)
    ++gathers_;
    lock.unlock();
    BuildOne(coord, profiles);
  }
}

void NavMeshService::BuildOne(TileCoord coord, const std::vector<int>& profiles) {
  const Clock::time_point gather_start = Clock::now();
  TileGeometry geometry = GatherTileGeometry(world_, TileGatherBox(gather_settings(), coord), config_.filter);
  const double gather_ms = MillisecondsSince(gather_start);
  std::vector<NavMeshSettings> settings;
  for (const int p : profiles) settings.push_back(profiles_[static_cast<std::size_t>(p)].settings);
  std::vector<Result<BuiltTile>> built = BuildTileForProfiles(settings, coord, geometry);
  for (Result<BuiltTile>& tile : built)
    if (tile && tile->polygons_from >= 0)
      tile->polygons_from = profiles[static_cast<std::size_t>(tile->polygons_from)];
  {
    // Publishing happens under the back-end lock, so making room (evicting) and taking the slot is one
    // decision however many workers finish at once. Game threads never take this lock.
    const std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < profiles.size(); ++i) {
      const TileBuildRecord record{
          coord, profiles[i], 0, geometry.bodies.size(), geometry.triangle_count(), 0, gather_ms, 0.0,
          0.0,   0.0,         -1};
      Publish({profiles[i], coord}, built[i], record, geometry.bodies);
      ForgetOldRecords(profiles[i]);
    }
    MirrorCounters();
  }
  state_changed_.notify_all();
}

void NavMeshService::Publish(ProfileTile tile, Result<BuiltTile>& built, TileBuildRecord record,
                             const std::vector<GatheredBody>& bodies) {
  Profile& profile = profiles_[static_cast<std::size_t>(tile.profile)];
  TileRecord& state = tiles_[tile];
  Status published = built.status();
  if (built) {
    record.polygons = built->polygons;
    record.recast_ms = built->recast_ms;
    record.polygons_from = built->polygons_from;
    const bool takes_slot = !built->data.empty() && !state.holds_data;
    if (takes_slot) published = MakeRoom(tile);
    if (published.ok()) {
      const bool holds_data = !built->data.empty();
      const Clock::time_point publish_start = Clock::now();
      published = profile.navmesh->ReplaceTile(tile.coord, std::move(built->data));
      record.publish_ms = MillisecondsSince(publish_start);
      if (published.ok()) {
        profile.tiles_holding_data += static_cast<int>(holds_data) - static_cast<int>(state.holds_data);
        state.holds_data = holds_data;
      }
    }
  }
  if (!published.ok()) {
    ++profile.counters.failures;
    last_error_ = published.message();
    ++state.failed_in_a_row;
    if (state.builds > 0) {
      // A rebuild failed: the last good tile is still published, so agents keep it while it is retried.
      SetState(tile, state, TileState::kStale);
      state.stale_since = Clock::now();
    } else {
      SetState(tile, state, TileState::kMissing);  // the next request tries again
    }
    return;
  }
  state.failed_in_a_row = 0;
  SetState(tile, state, TileState::kReady);
  state.bodies = std::make_shared<const std::vector<GatheredBody>>(bodies);
  record.build = ++state.builds;
  record.request_to_ready_ms = MillisecondsSince(state.requested);
  ++profile.counters.builds;
  profile.counters.polygons_taken += record.polygons_from >= 0;
  profile.counters.rebuilds += record.build > 1;
  log_.push_back(record);
}

namespace {
/// Whether `a` is a better tile to give up than `b`: requested longer ago, or as long ago but farther
/// from the agent that asked.
template <class Record>
bool EvictsBefore(const Record& a, const Record& b) {
  if (a.last_requested != b.last_requested) return a.last_requested < b.last_requested;
  return a.last_priority > b.last_priority;
}
}  // namespace

Status NavMeshService::MakeRoom(ProfileTile tile) {
  Profile& profile = profiles_[static_cast<std::size_t>(tile.profile)];
  if (profile.tiles_holding_data < profile.max_tiles) return Status::Ok();
  // Only a published tile can go: one that is building comes back to publish, and one that is queued holds
  // nothing yet.
  auto victim = tiles_.end();
  const auto first = tiles_.lower_bound(
      {tile.profile, TileCoord{std::numeric_limits<int>::min(), std::numeric_limits<int>::min()}});
  for (auto it = first; it != tiles_.end() && it->first.profile == tile.profile; ++it) {
    const TileRecord& record = it->second;
    if (it->first.coord == tile.coord || !record.holds_data) continue;
    if (record.state != TileState::kReady && record.state != TileState::kStale) continue;
    if (victim == tiles_.end() || EvictsBefore(record, victim->second)) victim = it;
  }
  if (victim == tiles_.end())
    return MakeError(ErrorCode::kCapacityExceeded, "navmesh: every one of the " +
                                                       std::to_string(profile.max_tiles) +
                                                       " tiles of profile '" + profile.profile.name +
                                                       "''s budget is being built; raise max_tiles");
  profile.navmesh->RemoveTile(victim->first.coord);
  --profile.tiles_holding_data;
  ++profile.counters.evictions;
  ForgetFrontState(victim->first);
  tiles_.erase(victim);
  return Status::Ok();
}

void NavMeshService::ForgetOldRecords(int profile_index) {
  // Tiles that hold nothing (off the level, nothing walkable) take no slot, but their records would pile up
  // as agents walk across a large world: keep as many as a few budgets' worth, dropping the oldest.
  const Profile& profile = profiles_[static_cast<std::size_t>(profile_index)];
  const std::size_t limit = 4 * static_cast<std::size_t>(profile.max_tiles) + 64;
  const auto first = [&] {
    return tiles_.lower_bound(
        {profile_index, TileCoord{std::numeric_limits<int>::min(), std::numeric_limits<int>::min()}});
  };
  const auto count = [&] {
    std::size_t n = 0;
    for (auto it = first(); it != tiles_.end() && it->first.profile == profile_index; ++it) ++n;
    return n;
  };
  for (std::size_t records = count(); records > limit; --records) {
    auto oldest = tiles_.end();
    for (auto it = first(); it != tiles_.end() && it->first.profile == profile_index; ++it) {
      const TileRecord& record = it->second;
      if (record.holds_data || (record.state != TileState::kReady && record.state != TileState::kMissing))
        continue;
      if (oldest == tiles_.end() || EvictsBefore(record, oldest->second)) oldest = it;
    }
    if (oldest == tiles_.end()) return;
    ForgetFrontState(oldest->first);
    tiles_.erase(oldest);
  }
}

bool NavMeshService::TileChanged(const std::vector<GatheredBody>& now,
                                 const std::vector<GatheredBody>& bodies) const {
  if (now.size() != bodies.size()) return true;
  for (std::size_t i = 0; i < now.size(); ++i) {
    if (now[i].id != bodies[i].id) return true;
    if (MovedBeyond(bodies[i].bounds, now[i].bounds, config_.move_threshold)) return true;
  }
  return false;
}

void NavMeshService::QueueDueRetries(Clock::time_point now) {
  bool queued = false;
  for (auto& [tile, record] : tiles_) {
    if (record.state != TileState::kStale || now - record.stale_since < RetryDelay(record)) continue;
    SetState(tile, record, TileState::kQueued);
    record.requested = record.stale_since;
    QueueCoord(tile.coord, record.priority);
    queued = true;
  }
  if (queued) WakeWorkers();
}

void NavMeshService::ScannerLoop() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    state_changed_.wait_for(lock, config_.scan_interval, [this] { return stopping_; });
    if (stopping_) return;
    QueueDueRetries(Clock::now());
    std::vector<std::pair<ProfileTile, std::shared_ptr<const std::vector<GatheredBody>>>> ready;
    for (auto& [tile, record] : tiles_)
      if (record.state == TileState::kReady) ready.emplace_back(tile, record.bodies);
    lock.unlock();
    // Each tile's bodies are found once per scan, whichever profiles hold it.
    std::map<TileCoord, std::vector<GatheredBody>> found_now;
    std::vector<std::size_t> changed;
    for (std::size_t i = 0; i < ready.size(); ++i) {
      const TileCoord coord = ready[i].first.coord;
      auto found = found_now.find(coord);
      if (found == found_now.end())
        found = found_now
                    .emplace(coord, FindCountedBodies(world_, TileGatherBox(gather_settings(), coord),
                                                      config_.filter))
                    .first;
      if (TileChanged(found->second, *ready[i].second)) changed.push_back(i);
    }
    lock.lock();
    for (const std::size_t i : changed) {
      const auto found = tiles_.find(ready[i].first);  // evicted meanwhile: nothing to mark
      if (found == tiles_.end()) continue;
      TileRecord& record = found->second;
      // Only if the tile still holds the build we compared against (no rebuild finished meanwhile).
      if (record.state != TileState::kReady || record.bodies != ready[i].second) continue;
      SetState(ready[i].first, record, TileState::kStale);
      record.stale_since = Clock::now();
    }
    ++scans_;
    MirrorCounters();
  }
}

}  // namespace strata::navmesh
