#include "navmesh/NavMeshQuery.h"

#include <string>

#include <cmath>

namespace strata::navmesh {

namespace {

constexpr int kMaxPathPolys = 2048;
constexpr float kReachedDistance = 0.5f;

Error NotFinite(const char* what) {
  return MakeError(ErrorCode::kInvalidArgument, std::string("navmesh query: ") + what + " is not finite");
}

Vec3 ToVec3(const float* v) {
  return {v[0], v[1], v[2]};
}

// Detour draws its random numbers through a plain function pointer: the caller's generator is reached
// through this thread's slot for the length of one call.
thread_local std::mt19937* t_random = nullptr;

float DrawUnit() {
  return std::uniform_real_distribution<float>(0.0f, 1.0f)(*t_random);
}

}  // namespace

Result<std::unique_ptr<NavMeshQuery>> NavMeshQuery::Create(const NavMesh& navmesh, int max_nodes) {
  if (max_nodes < 16 || max_nodes > 65535)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh query: max_nodes must be in [16, 65535]");
  dtNavMeshQuery* query = dtAllocNavMeshQuery();
  std::unique_ptr<NavMeshQuery> wrapper(new NavMeshQuery(navmesh, query));
  const bool ok = query && navmesh.Read([&](const dtNavMesh& mesh) {
    return dtStatusSucceed(query->init(&mesh, max_nodes));
  });
  if (!ok)
    return MakeError(ErrorCode::kCapacityExceeded, "navmesh query: Detour could not allocate its nodes");
  return wrapper;
}

NavMeshQuery::~NavMeshQuery() {
  dtFreeNavMeshQuery(query_);
}

Result<NearestPoly> NavMeshQuery::FindNearestPoly(const Vec3& position) const {
  if (!IsFinite(position)) return NotFinite("position");
  const Vec3 local = navmesh_.ToLocal(position);
  return navmesh_.Read([&](const dtNavMesh&) -> Result<NearestPoly> {
    NearestPoly nearest;
    const dtStatus status =
        query_->findNearestPoly(local.data(), extents_.data(), &filter_, &nearest.poly, nearest.point.data());
    if (dtStatusFailed(status) || nearest.poly == 0)
      return MakeError(ErrorCode::kInvalidArgument, "navmesh query: no navmesh polygon near the point");
    nearest.point = navmesh_.ToWorld(nearest.point);
    return nearest;
  });
}

Result<PathResult> NavMeshQuery::FindPath(const Vec3& from, const Vec3& to) const {
  if (!IsFinite(from)) return NotFinite("path start");
  if (!IsFinite(to)) return NotFinite("path end");
  // Detour works relative to the navmesh origin; the path comes back in world coordinates.
  const Vec3 local_from = navmesh_.ToLocal(from), local_to = navmesh_.ToLocal(to);
  return navmesh_.Read([&](const dtNavMesh&) -> Result<PathResult> {
    NearestPoly start, end;
    query_->findNearestPoly(local_from.data(), extents_.data(), &filter_, &start.poly, start.point.data());
    if (start.poly == 0)
      return MakeError(ErrorCode::kInvalidArgument, "navmesh query: no polygon near the start");
    PathResult path;
    query_->findNearestPoly(local_to.data(), extents_.data(), &filter_, &end.poly, end.point.data());
    if (end.poly == 0) return path;
    path.polys.resize(kMaxPathPolys);
    int poly_count = 0;
    query_->findPath(start.poly, end.poly, start.point.data(), end.point.data(), &filter_, path.polys.data(),
                     &poly_count, kMaxPathPolys);
    path.polys.resize(static_cast<std::size_t>(poly_count));
    if (poly_count == 0) return path;
    path.found = true;

    // A partial corridor ends at the polygon nearest the target; aim the straight path at that polygon.
    Vec3 target = end.point;
    if (path.polys.back() != end.poly)
      query_->closestPointOnPoly(path.polys.back(), end.point.data(), target.data(), nullptr);
    std::vector<float> corners(static_cast<std::size_t>(kMaxPathPolys) * 3);
    int corner_count = 0;
    query_->findStraightPath(start.point.data(), target.data(), path.polys.data(), poly_count, corners.data(),
                             nullptr, nullptr, &corner_count, kMaxPathPolys);
    for (int i = 0; i < corner_count; ++i)
      path.points.push_back(navmesh_.ToWorld(ToVec3(&corners[static_cast<std::size_t>(i) * 3])));
    for (std::size_t i = 1; i < path.points.size(); ++i)
      path.length += (path.points[i] - path.points[i - 1]).norm();
    if (!path.points.empty()) {
      const Vec3 gap = path.points.back() - to;
      path.reached_end = std::hypot(gap.x(), gap.z()) <= kReachedDistance;
    }
    return path;
  });
}

Result<NavRaycastResult> NavMeshQuery::Raycast(const Vec3& from, const Vec3& to) const {
  if (!IsFinite(from)) return NotFinite("ray start");
  if (!IsFinite(to)) return NotFinite("ray end");
  const Vec3 local_from = navmesh_.ToLocal(from), local_to = navmesh_.ToLocal(to);
  return navmesh_.Read([&](const dtNavMesh&) -> Result<NavRaycastResult> {
    NearestPoly start;
    query_->findNearestPoly(local_from.data(), extents_.data(), &filter_, &start.poly, start.point.data());
    if (start.poly == 0)
      return MakeError(ErrorCode::kInvalidArgument, "navmesh query: no polygon near the ray start");
    float t = 0.0f;
    NavRaycastResult result;
    std::vector<dtPolyRef> visited(kMaxPathPolys);
    int visited_count = 0;
    query_->raycast(start.poly, start.point.data(), local_to.data(), &filter_, &t, result.hit_normal.data(),
                    visited.data(), &visited_count, kMaxPathPolys);
    result.hit_wall = t < 1.0f;  // Detour reports FLT_MAX when the ray reaches its end
    result.fraction = result.hit_wall ? t : 1.0f;
    return result;
  });
}

Result<Vec3> NavMeshQuery::RandomPointAround(const Vec3& center, float radius, std::mt19937& random) const {
  if (!IsFinite(center)) return NotFinite("circle centre");
  if (!std::isfinite(radius) || radius <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh query: the radius must be a finite number > 0");
  const Vec3 local = navmesh_.ToLocal(center);
  return navmesh_.Read([&](const dtNavMesh&) -> Result<Vec3> {
    NearestPoly start;
    query_->findNearestPoly(local.data(), extents_.data(), &filter_, &start.poly, start.point.data());
    if (start.poly == 0)
      return MakeError(ErrorCode::kInvalidArgument, "navmesh query: no polygon near the circle's centre");
    t_random = &random;
    dtPolyRef poly = 0;
    Vec3 point;
    const dtStatus status = query_->findRandomPointAroundCircle(start.poly, start.point.data(), radius,
                                                                &filter_, DrawUnit, &poly, point.data());
    t_random = nullptr;
    if (dtStatusFailed(status) || poly == 0)
      return MakeError(ErrorCode::kInvalidArgument, "navmesh query: no random point found");
    return navmesh_.ToWorld(point);
  });
}

void NavMeshQuery::set_links_allowed(bool allowed) {
  filter_.setExcludeFlags(allowed ? 0 : kDropLinkFlag);
}

}  // namespace strata::navmesh
