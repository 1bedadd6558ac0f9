#include "physics/shapes/Shape.h"

namespace strata {

const char* ToString(ShapeType type) {
  switch (type) {
    case ShapeType::kSphere:
      return "sphere";
    case ShapeType::kBox:
      return "box";
    case ShapeType::kCapsule:
      return "capsule";
    case ShapeType::kConvexHull:
      return "convex_hull";
    case ShapeType::kTriangleMesh:
      return "mesh";
    case ShapeType::kHeightField:
      return "heightfield";
  }
  return "unknown";
}

void Shape::GetTrianglesInBox(const AABB& world_box, const Pose& pose, std::vector<Triangle>& out) const {
  const Pose inverse{pose.rotation.conjugate() * -pose.position, pose.rotation.conjugate()};
  const AABB local_box = world_box.Transformed(inverse);
  std::vector<Triangle> local;
  CollectLocalTriangles(local_box, local);
  for (const Triangle& triangle : local) {
    Triangle world;
    AABB bounds;
    for (int i = 0; i < 3; ++i) {
      world.vertices[i] = pose.ToWorld(triangle.vertices[i]);
      bounds.Encapsulate(world.vertices[i]);
    }
    if (bounds.Overlaps(world_box)) out.push_back(world);
  }
}

}  // namespace strata
