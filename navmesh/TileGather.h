// TileGather: collects the world-space triangles a navmesh tile is built from, without taking a body lock
// (so a physics step never waits on it). It pins a broad-phase generation and queries the tile's box; static
// bodies give their exact shape from the world's published snapshots, moving bodies the box the broad phase
// holds for them. Safe from any thread, at any time (also while the world steps and other threads add,
// remove and move bodies).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "physics/body/Body.h"
#include "physics/math/AABB.h"

namespace strata {
class PhysicsSystem;
}

namespace strata::navmesh {

/// Which bodies shape the navmesh. By default: static and kinematic geometry, and dynamic bodies large
/// enough to block an agent; small debris is left out. Sensors and other layers are excluded by mask.
/// Static bodies count with their exact shape; kinematic and dynamic ones as the box of their broad-phase
/// bounds (which include the step's motion margin), the only thing known of them without locking them.
struct NavMeshBodyFilter {
  std::uint64_t object_layers = ~0ull;  ///< bit per object layer that may count (layers >= 64 always may)
  float min_dynamic_size = 1.5f;  ///< a dynamic body counts when its largest bounds side reaches this (m)

  bool Counts(MotionType motion_type, ObjectLayer layer, const AABB& bounds) const;
};

/// What a tile's geometry was made of: enough to tell later whether it changed.
struct GatheredBody {
  BodyID id;
  AABB bounds;  ///< world bounds when gathered
};

/// A convex body's volume as the planes of its faces (outward normals), so the builder can tell floor
/// *inside* a solid (under a crate) from floor beside it: Recast itself only sees surfaces.
struct SolidVolume {
  struct Plane {
    Vec3 normal;
    float offset;  ///< normal . point for points on the plane
  };
  AABB bounds;
  std::vector<Plane> planes;

  /// True when `point` is deeper than `margin` inside every face.
  bool Contains(const Vec3& point, float margin) const;
};

/// Triangles in Recast's layout (x, y, z floats; 3 vertex indices per triangle), plus the bodies they came
/// from, sorted by id.
struct TileGeometry {
  std::vector<float> vertices;
  std::vector<int> triangles;
  std::vector<GatheredBody> bodies;
  std::vector<SolidVolume> solids;  ///< of the convex bodies among them
  AABB bounds;                      ///< of the triangles (empty when there are none)

  std::size_t triangle_count() const { return triangles.size() / 3; }
  void AddTriangle(const Triangle& triangle);
};

/// Gathers the triangles of every counted body whose bounds overlap `box`, in body-index order (so the
/// same world gives the same triangles). Bodies removed or destroyed while gathering are skipped. The first
/// call on a world enables its body snapshots (NavMeshService does that up front, on its creator's thread).
TileGeometry GatherTileGeometry(const PhysicsSystem& world, const AABB& box, const NavMeshBodyFilter& filter);

/// Ids of the counted bodies overlapping `box` now, sorted (for dirty tracking).
std::vector<GatheredBody> FindCountedBodies(const PhysicsSystem& world, const AABB& box,
                                            const NavMeshBodyFilter& filter);

}  // namespace strata::navmesh
