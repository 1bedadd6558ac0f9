#include "navmesh/TileGather.h"

#include <algorithm>

#include "physics/body/BodyManager.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::navmesh {

namespace {

class IdCollector final : public BroadPhaseCollector {
 public:
  void AddHit(BodyID id, float) override { ids.push_back(id); }
  std::vector<BodyID> ids;
};

/// Body ids overlapping `box`, through a pinned generation so the tree cannot be freed under the walk.
std::vector<BodyID> QueryBox(const PhysicsSystem& world, const AABB& box, const NavMeshBodyFilter& filter) {
  const BroadPhase& broad_phase = world.broad_phase();
  const BroadPhasePin pin = broad_phase.Pin();
  IdCollector collector;
  broad_phase.CollideAABB(pin, box, QueryFilter{filter.object_layers, BodyID::kInvalidIndex}, collector);
  std::sort(collector.ids.begin(), collector.ids.end());
  collector.ids.erase(std::unique(collector.ids.begin(), collector.ids.end()), collector.ids.end());
  return std::move(collector.ids);
}

/// What a gather copies out of a body under its read lock.
struct BodyCopy {
  bool counts = false;
  ShapeRef shape;
  Pose pose;
  AABB bounds;
};

/// The broad phase's bounds may be wider than the body's (motion margins); only the body's own bounds decide,
/// so a gather and a later dirty check agree on who is in the box.
BodyCopy CopyBody(const PhysicsSystem& world, BodyID id, const AABB& box, const NavMeshBodyFilter& filter) {
  const BodyLockRead lock(world.body_manager(), id);
  if (!lock.Succeeded()) return {};
  const Body& body = lock.body();
  if (!body.in_world() || !filter.Counts(body) || !body.world_bounds().Overlaps(box)) return {};
  return {true, body.shape(), body.pose(), body.world_bounds()};
}

}  // namespace

bool NavMeshBodyFilter::Counts(const Body& body) const {
  const ObjectLayer layer = body.object_layer();
  if (layer < 64 && ((object_layers >> layer) & 1u) == 0) return false;
  if (!body.IsDynamic()) return true;
  return body.world_bounds().Size().maxCoeff() >= min_dynamic_size;
}

bool SolidVolume::Contains(const Vec3& point, float margin) const {
  for (const Plane& plane : planes)
    if (plane.normal.dot(point) > plane.offset - margin) return false;
  return true;
}

namespace {

SolidVolume MakeSolid(const BodyCopy& copy) {
  SolidVolume solid;
  solid.bounds = copy.bounds;
  std::vector<Triangle> faces;
  copy.shape->GetTrianglesInBox(copy.bounds.Expanded(0.01f), copy.pose, faces);
  for (const Triangle& face : faces) {
    const Vec3 normal = (face.vertices[1] - face.vertices[0]).cross(face.vertices[2] - face.vertices[0]);
    if (normal.squaredNorm() < 1e-12f) continue;
    const Vec3 unit = normal.normalized();
    solid.planes.push_back({unit, unit.dot(face.vertices[0])});
  }
  return solid;
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
  TileGeometry geometry;
  std::vector<Triangle> triangles;
  for (const BodyID id : QueryBox(world, box, filter)) {
    const BodyCopy copy = CopyBody(world, id, box, filter);
    if (!copy.counts) continue;
    geometry.bodies.push_back({id, copy.bounds});
    if (copy.shape->IsConvex()) geometry.solids.push_back(MakeSolid(copy));
    triangles.clear();
    copy.shape->GetTrianglesInBox(box, copy.pose, triangles);
    for (const Triangle& triangle : triangles) geometry.AddTriangle(triangle);
  }
  return geometry;
}

std::vector<GatheredBody> FindCountedBodies(const PhysicsSystem& world, const AABB& box,
                                            const NavMeshBodyFilter& filter) {
  std::vector<GatheredBody> bodies;
  for (const BodyID id : QueryBox(world, box, filter)) {
    const BodyCopy copy = CopyBody(world, id, box, filter);
    if (copy.counts) bodies.push_back({id, copy.bounds});
  }
  return bodies;
}

}  // namespace strata::navmesh
