#include "navmesh/TileGather.h"

#include <algorithm>

#include "physics/shapes/BoxShape.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::navmesh {

namespace {

/// A body the broad phase holds in the box, with the bounds it holds for it.
struct Candidate {
  BodyID id;
  AABB bounds;
  bool has_bounds = false;
};

class CandidateCollector final : public BroadPhaseCollector {
 public:
  void AddHit(BodyID id, float) override { candidates.push_back({id, AABB(), false}); }
  void AddOverlap(BodyID id, const AABB& bounds) override { candidates.push_back({id, bounds, true}); }
  std::vector<Candidate> candidates;
};

/// Bodies overlapping `box`, in id order, through a pinned generation so the tree cannot be freed under the
/// walk.
std::vector<Candidate> QueryBox(const PhysicsSystem& world, const AABB& box,
                                const NavMeshBodyFilter& filter) {
  const BroadPhase& broad_phase = world.broad_phase();
  const BroadPhasePin pin = broad_phase.Pin();
  CandidateCollector collector;
  broad_phase.CollideAABB(pin, box, QueryFilter{filter.object_layers, BodyID::kInvalidIndex}, collector);
  std::vector<Candidate>& candidates = collector.candidates;
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.id < b.id; });
  candidates.erase(std::unique(candidates.begin(), candidates.end(),
                               [](const Candidate& a, const Candidate& b) { return a.id == b.id; }),
                   candidates.end());
  return std::move(candidates);
}

/// The broad phase's bounds are six floats read while a foreground thread may be writing them: a read that
/// straddles a move can mix two boxes, so take the box spanning both corners.
AABB SpanningBox(const AABB& bounds) {
  return {bounds.min.cwiseMin(bounds.max), bounds.min.cwiseMax(bounds.max)};
}

/// What a body gives a tile: static bodies their exact shape (from the snapshot BodyInterface published),
/// moving bodies the box the broad phase holds for them (their pose is the step's, read by nobody here).
struct CountedBody {
  bool counts = false;
  bool exact = false;
  BodySnapshot snapshot;
  AABB bounds;
};

/// No body lock: the snapshot table and the broad phase are all a job reads, so the step never waits on it.
CountedBody Inspect(const PhysicsSystem& world, const Candidate& candidate, const AABB& box,
                    const NavMeshBodyFilter& filter) {
  std::optional<BodySnapshot> snapshot = world.body_snapshots().Read(candidate.id);
  if (!snapshot || snapshot->sensor) return {};  // not in the world (yet, or any more), or a trigger volume
  const bool exact = snapshot->motion_type == MotionType::kStatic;
  // A broad phase that reports no bounds (only AddHit) leaves the body's bounds as of its last teleport.
  const AABB bounds = exact || !candidate.has_bounds ? snapshot->bounds : SpanningBox(candidate.bounds);
  if (!filter.Counts(snapshot->motion_type, snapshot->object_layer, bounds) || !bounds.Overlaps(box))
    return {};
  return {true, exact, std::move(*snapshot), bounds};
}

}  // namespace

bool NavMeshBodyFilter::Counts(MotionType motion_type, ObjectLayer layer, const AABB& bounds) const {
  if (layer < 64 && ((object_layers >> layer) & 1u) == 0) return false;
  if (motion_type != MotionType::kDynamic) return true;
  return bounds.Size().maxCoeff() >= min_dynamic_size;
}

bool SolidVolume::Contains(const Vec3& point, float margin) const {
  for (const Plane& plane : planes)
    if (plane.normal.dot(point) > plane.offset - margin) return false;
  return true;
}

namespace {

SolidVolume MakeSolid(const Shape& shape, const Pose& pose, const AABB& bounds) {
  SolidVolume solid;
  solid.bounds = bounds;
  std::vector<Triangle> faces;
  shape.GetTrianglesInBox(bounds.Expanded(0.01f), pose, faces);
  for (const Triangle& face : faces) {
    const Vec3 normal = (face.vertices[1] - face.vertices[0]).cross(face.vertices[2] - face.vertices[0]);
    if (normal.squaredNorm() < 1e-12f) continue;
    const Vec3 unit = normal.normalized();
    solid.planes.push_back({unit, unit.dot(face.vertices[0])});
  }
  return solid;
}

/// A moving body's box is never flat, so its faces stay triangles Recast can rasterize.
constexpr float kMinHalfExtent = 1e-3f;

/// Adds `body`'s triangles inside `box` and, for a convex body, its volume.
void AddBody(const CountedBody& body, const AABB& box, TileGeometry& geometry,
             std::vector<Triangle>& triangles) {
  geometry.bodies.push_back({body.snapshot.id, body.bounds});
  triangles.clear();
  if (body.exact) {
    const Shape& shape = *body.snapshot.shape;
    if (shape.IsConvex()) geometry.solids.push_back(MakeSolid(shape, body.snapshot.pose, body.bounds));
    shape.GetTrianglesInBox(box, body.snapshot.pose, triangles);
  } else {
    const BoxShape obstacle(body.bounds.HalfExtents().cwiseMax(kMinHalfExtent), 0.0f);
    const Pose at_center{body.bounds.Center(), Quat::Identity()};
    geometry.solids.push_back(MakeSolid(obstacle, at_center, body.bounds));
    obstacle.GetTrianglesInBox(box, at_center, triangles);
  }
  for (const Triangle& triangle : triangles) geometry.AddTriangle(triangle);
}

}  // namespace

void TileGeometry::AddTriangle(const Triangle& triangle) {
  const int base = static_cast<int>(vertices.size() / 3);
  for (const Vec3& vertex : triangle.vertices) {
    vertices.insert(vertices.end(), {vertex.x(), vertex.y(), vertex.z()});
    bounds.Encapsulate(vertex);
  }
  triangles.insert(triangles.end(), {base, base + 1, base + 2});
}

TileGeometry GatherTileGeometry(const PhysicsSystem& world, const AABB& box,
                                const NavMeshBodyFilter& filter) {
  world.body_snapshots().Enable(world.body_manager());
  TileGeometry geometry;
  std::vector<Triangle> triangles;
  for (const Candidate& candidate : QueryBox(world, box, filter)) {
    const CountedBody body = Inspect(world, candidate, box, filter);
    if (body.counts) AddBody(body, box, geometry, triangles);
  }
  return geometry;
}

std::vector<GatheredBody> FindCountedBodies(const PhysicsSystem& world, const AABB& box,
                                            const NavMeshBodyFilter& filter) {
  world.body_snapshots().Enable(world.body_manager());
  std::vector<GatheredBody> bodies;
  for (const Candidate& candidate : QueryBox(world, box, filter)) {
    const CountedBody body = Inspect(world, candidate, box, filter);
    if (body.counts) bodies.push_back({candidate.id, body.bounds});
  }
  return bodies;
}

}  // namespace strata::navmesh
