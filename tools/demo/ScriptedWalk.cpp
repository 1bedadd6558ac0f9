#include "tools/demo/ScriptedWalk.h"

#include <chrono>

#include "physics/world/PhysicsSystem.h"
#include "physics/world/WorldQuery.h"

namespace strata::demo {

namespace {

const Vec3 kGravity(0.0f, -9.81f, 0.0f);
// A waypoint counts as reached within this (m, on the ground plane): a walker turns for the next one there.
constexpr float kReach = 0.5f;
// Blocked (a crate too heavy to push in the way, or two crates it is wedged between): less than this share of
// the way it should have gone in the last half second. It then jumps (onto a crate, over a low one), and if
// that does not do it turns off its way for a while: to one side, the other, and back out to each side.
constexpr float kBlocked = 0.25f;
constexpr float kCheckEvery = 0.5f;
constexpr float kSidestepFor = 0.8f;
constexpr float kJumpSpeed = 5.5f;  // m/s up: about 1.5 m high
constexpr float kSidestepDegrees[] = {0.0f, 70.0f, -70.0f, 150.0f, -150.0f};
// The path to the next waypoint is found again this often (s): it may have left it, or tiles may have come.
constexpr float kReplanEvery = 0.5f;
constexpr float kCornerReach = 0.3f;     // a path corner counts as passed within this (m)
constexpr float kCloseEnough = 2.0f;     // a waypoint it is blocked this near to counts as reached (m)
constexpr float kRequestRadius = 16.0f;  // navmesh tiles it asks for around itself and its waypoint (m)

float Flat(const Vec3& v) {
  return Vec3(v.x(), 0.0f, v.z()).norm();
}

}  // namespace

std::vector<Vec3> CourtyardRoute() {
  // The stairs climb west from x 27.4 onto the platform (x 12-22, 3 m up) at z 42-46: up them, across the
  // platform and back down; then across the yard to the bridge over the trench (x 40-48) at z 30-34.
  return {{33.0f, 0.0f, 45.0f}, {17.0f, 0.0f, 45.0f}, {17.0f, 0.0f, 43.0f},
          {33.0f, 0.0f, 43.0f}, {38.0f, 0.0f, 32.0f}, {56.0f, 0.0f, 32.0f}};
}

Result<std::unique_ptr<ScriptedWalk>> ScriptedWalk::Create(PhysicsSystem& world,
                                                           navmesh::NavMeshService& service,
                                                           const std::vector<Vec3>& route, float top,
                                                           float bottom, float speed) {
  if (route.size() < 2) return MakeError(ErrorCode::kInvalidArgument, "a route needs two points or more");
  std::vector<Vec3> grounded;
  for (const Vec3& point : route) {
    const auto hit = world.query().CastRay(Vec3(point.x(), top, point.z()), Vec3(0.0f, bottom - top, 0.0f));
    if (!hit || !hit->has_value())
      return MakeError(ErrorCode::kInvalidArgument, "no ground under the route point (" +
                                                        std::to_string(point.x()) + ", " +
                                                        std::to_string(point.z()) + ")");
    grounded.push_back((*hit)->position);
  }
  Result<std::unique_ptr<Character>> character =
      Character::Create(world, CharacterSettings{}, grounded.front() + Vec3(0.0f, 0.05f, 0.0f));
  if (!character) return character.error();
  Result<std::unique_ptr<navmesh::NavMeshQuery>> query = navmesh::NavMeshQuery::Create(service.navmesh());
  if (!query) return query.error();
  return std::unique_ptr<ScriptedWalk>(
      new ScriptedWalk(std::move(*character), service, std::move(*query), std::move(grounded), speed));
}

ScriptedWalk::ScriptedWalk(std::unique_ptr<Character> character, navmesh::NavMeshService& service,
                           std::unique_ptr<navmesh::NavMeshQuery> query, std::vector<Vec3> route, float speed)
    : character_(std::move(character)),
      service_(service),
      query_(std::move(query)),
      route_(std::move(route)),
      speed_(speed),
      start_height_(character_->feet().y()),
      last_check_feet_(character_->feet()) {}

Status ScriptedWalk::Update(float dt, float time) {
  const Vec3& feet = character_->feet();
  while (next_ < route_.size() && Flat(route_[next_] - feet) < kReach) {
    ++next_;
    path_time_ = -1.0f;  // a new leg: a new path
  }
  if (next_ == route_.size() && finished_at_ < 0.0f) finished_at_ = time;
  Vec3 velocity = Vec3::Zero();
  if (next_ < route_.size()) {
    const Vec3 to = Aim(time, feet) - feet;
    Vec3 heading = Vec3(to.x(), 0.0f, to.z()).normalized();
    Steer(time, feet);
    const std::size_t way = static_cast<std::size_t>(sidesteps_ + 4) % std::size(kSidestepDegrees);
    if (sidestep_until_ > time) {
      heading = Eigen::AngleAxisf(kSidestepDegrees[way] * kPi / 180.0f, Vec3::UnitY()) * heading;
    }
    velocity = heading * speed_;
    // The first way out is up: a jump (taken on the ground only, in the first frame of it).
    if (sidestep_until_ > time && way == 0 && jump_) velocity.y() = kJumpSpeed;
    jump_ = false;
  }
  const auto start = std::chrono::steady_clock::now();
  const Status updated = character_->Update(dt, velocity, kGravity);
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  if (!updated) return updated;
  total_update_us_ += us;
  max_update_us_ = std::max(max_update_us_, us);
  grounded_updates_ += character_->ground_state() == GroundState::kOnGround ? 1 : 0;
  trail_.push_back(character_->feet());
  return Status::Ok();
}

Vec3 ScriptedWalk::Aim(float time, const Vec3& feet) {
  const Vec3& waypoint = route_[next_];
  // The tiles around it and its waypoint, every second (a request for ready tiles costs next to nothing).
  if (time >= request_time_ + 1.0f) {
    request_time_ = time;
    (void)service_.RequestAround(feet, kRequestRadius);
    (void)service_.RequestAround(waypoint, kRequestRadius);
  }
  if (time >= path_time_ + kReplanEvery) {
    path_time_ = time;
    path_.clear();
    corner_ = 0;
    const Result<navmesh::PathResult> path = query_->FindPath(feet, waypoint);
    if (path && path->found && path->reached_end) path_ = path->points;
  }
  while (corner_ < path_.size() && Flat(path_[corner_] - feet) < kCornerReach) ++corner_;
  return corner_ < path_.size() ? path_[corner_] : waypoint;
}

void ScriptedWalk::Steer(float time, const Vec3& feet) {
  if (time < last_check_time_ + kCheckEvery) return;
  const float expected = speed_ * (time - last_check_time_);
  if (Flat(feet - last_check_feet_) < kBlocked * expected && sidestep_until_ <= time) {
    ++sidesteps_;
    sidestep_until_ = time + kSidestepFor;
    jump_ = true;
    // Something sits on the waypoint (a crate fell there): close enough, on to the next.
    if (next_ < route_.size() && Flat(route_[next_] - feet) < kCloseEnough) {
      ++next_;
      path_time_ = -1.0f;
    }
  }
  last_check_time_ = time;
  last_check_feet_ = feet;
}

WalkReport ScriptedWalk::report() const {
  WalkReport report;
  report.waypoints = route_.size();
  report.reached = std::min(next_, route_.size());
  report.finished_at = finished_at_;
  for (std::size_t i = 1; i < trail_.size(); ++i) report.distance += (trail_[i] - trail_[i - 1]).norm();
  for (const Vec3& feet : trail_) report.highest = std::max(report.highest, feet.y() - start_height_);
  const auto updates = static_cast<double>(std::max<std::size_t>(trail_.size(), 1));
  report.grounded = static_cast<float>(static_cast<double>(grounded_updates_) / updates);
  report.mean_update_us = total_update_us_ / updates;
  report.max_update_us = max_update_us_;
  report.sidesteps = sidesteps_;
  return report;
}

}  // namespace strata::demo
