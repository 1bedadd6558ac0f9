// Shape: the immutable geometry of a body, shared by reference (std::shared_ptr<const Shape>) so a query
// can copy the reference under a body's read lock and keep using the shape after unlocking.
// All methods are const and safe to call from any number of threads at once.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "physics/math/AABB.h"
#include "physics/shapes/MassProperties.h"

namespace strata {

enum class ShapeType : std::uint8_t { kSphere, kBox, kCapsule, kConvexHull, kTriangleMesh, kHeightField };

/// Human-readable name of a shape type ("sphere", "box", ...).
const char* ToString(ShapeType type);

/// A ray hit in the shape's local space.
struct ShapeRayHit {
  float fraction = 1.0f;        ///< hit point = origin + fraction * direction
  Vec3 normal = Vec3::UnitY();  ///< surface normal at the hit, local space
  std::uint32_t sub_shape = 0;  ///< triangle index for meshes, 0 otherwise
};

/// One triangle in world space (counter-clockwise seen from its front side).
struct Triangle {
  Vec3 vertices[3];
};

class Shape;
using ShapeRef = std::shared_ptr<const Shape>;

/// Base of all shapes. Local space has the shape's reference point at the origin.
class Shape {
 public:
  virtual ~Shape() = default;
  Shape(const Shape&) = delete;
  Shape& operator=(const Shape&) = delete;

  ShapeType type() const { return type_; }
  /// Whether the shape is a ConvexShape (what the narrow phase sweeps and what dynamic bodies are made of).
  bool IsConvex() const { return convex_; }

  /// Bounds in local space.
  virtual AABB LocalBounds() const = 0;
  /// Whether the world bounds turn with the body (a box's do); a shape that looks the same from every side
  /// (a sphere) says no, and its world bounds are its local bounds moved, which is tighter.
  virtual bool BoundsTurnWithBody() const { return true; }
  /// How far the shape's edges and corners are rounded (its convex radius; 0 for sharp shapes): a rounded
  /// shape's world bounds are its local bounds shrunk by this, turned, and grown by it again, which fits a
  /// turned rounded box exactly where the turned local box would stick out at the corners.
  virtual float BoundsRounding() const { return 0.0f; }
  /// Bounds in world space for a body at `pose`.
  AABB WorldBounds(const Pose& pose) const {
    return WorldBoundsOf(LocalBounds(), BoundsTurnWithBody(), BoundsRounding(), pose);
  }
  /// The same from the three facts alone: bodies keep them, so that moving a body reads no shape.
  static AABB WorldBoundsOf(const AABB& local, bool turns_with_body, float rounding, const Pose& pose) {
    if (!turns_with_body) return {pose.position + local.min, pose.position + local.max};
    if (rounding == 0.0f) return local.Transformed(pose);
    const AABB core{local.min.array() + rounding, local.max.array() - rounding};
    return core.Transformed(pose).Expanded(rounding);
  }

  /// Mass, inertia about the centre of mass and centre of mass for uniform `density` (kg/m^3).
  virtual MassProperties ComputeMassProperties(float density) const = 0;

  /// Ray origin + t * direction, t in [0, max_fraction], in local space. Returns true and fills `hit` on
  /// the first hit from outside; rays starting inside a solid shape hit at fraction 0.
  virtual bool CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                       ShapeRayHit& hit) const = 0;

  /// Appends the world-space triangles of this shape at `pose` whose bounds overlap `world_box`
  /// (used to gather navmesh input). Convex shapes are triangulated, meshes go through their BVH.
  void GetTrianglesInBox(const AABB& world_box, const Pose& pose, std::vector<Triangle>& out) const;

 protected:
  Shape(ShapeType type, bool convex) : type_(type), convex_(convex) {}

  /// Local-space triangles that may overlap `local_box` (a superset is fine; the caller filters).
  virtual void CollectLocalTriangles(const AABB& local_box, std::vector<Triangle>& out) const = 0;

 private:
  ShapeType type_;
  bool convex_;
};

}  // namespace strata
