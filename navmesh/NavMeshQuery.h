// NavMeshQuery: path queries on a NavMesh (nearest polygon, path corridor + straight path, raycast).
// One per thread: it owns Detour's search nodes. Each call holds the NavMesh's read lock for its duration,
// so tiles published meanwhile wait for it and the query never sees half a tile.
#pragma once

#include <DetourNavMeshQuery.h>

#include <memory>
#include <random>
#include <vector>

#include "navmesh/NavMesh.h"
#include "physics/math/Math.h"

namespace strata::navmesh {

/// The polygon nearest a point and the closest point on it.
struct NearestPoly {
  dtPolyRef poly = 0;
  Vec3 point = Vec3::Zero();
};

/// A path between two points.
struct PathResult {
  bool found = false;        ///< a corridor from the start polygon was found
  bool reached_end = false;  ///< its last point is within 0.5 m (x-z) of the target
  std::vector<dtPolyRef> polys;
  std::vector<Vec3> points;  ///< straight path (string-pulled corners), start to end
  float length = 0.0f;       ///< of the straight path (m)
};

/// A walkability ray along the navmesh surface.
struct NavRaycastResult {
  bool hit_wall = false;  ///< the ray left the navmesh before reaching its end
  float fraction = 1.0f;  ///< how far along it got (1 when it reached the end)
  Vec3 hit_normal = Vec3::Zero();
};

/// A thread's query object over a NavMesh (which must outlive it).
class NavMeshQuery {
 public:
  /// `max_nodes`: Detour's search node budget; larger finds longer paths.
  static Result<std::unique_ptr<NavMeshQuery>> Create(const NavMesh& navmesh, int max_nodes = 8192);
  ~NavMeshQuery();
  NavMeshQuery(const NavMeshQuery&) = delete;
  NavMeshQuery& operator=(const NavMeshQuery&) = delete;

  /// Search box half extents around a query point (m).
  void set_search_extents(const Vec3& half_extents) { extents_ = half_extents; }

  /// Fails for a non-finite point or when no polygon is within the search box.
  Result<NearestPoly> FindNearestPoly(const Vec3& position) const;
  /// Fails for non-finite points or when there is no polygon near the start; a path that cannot reach the
  /// target is not an error (found with reached_end false, or found false when the end has no polygon).
  Result<PathResult> FindPath(const Vec3& from, const Vec3& to) const;
  Result<NavRaycastResult> Raycast(const Vec3& from, const Vec3& to) const;
  /// A point drawn from `random` on the navmesh connected to the polygon nearest `center`, among the
  /// polygons within about `radius` of it (by area): where a wandering agent may go. The same navmesh and
  /// generator state give the same point. Fails off the navmesh or for bad numbers.
  Result<Vec3> RandomPointAround(const Vec3& center, float radius, std::mt19937& random) const;

  /// Whether paths may take off-mesh links (drop-downs; on by default): off, a query answers what a walker
  /// that never drops can reach.
  void set_links_allowed(bool allowed);

 private:
  NavMeshQuery(const NavMesh& navmesh, dtNavMeshQuery* query) : navmesh_(navmesh), query_(query) {}

  const NavMesh& navmesh_;
  dtNavMeshQuery* query_;
  dtQueryFilter filter_;
  Vec3 extents_ = Vec3(2.0f, 4.0f, 2.0f);
};

}  // namespace strata::navmesh
