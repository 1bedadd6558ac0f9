// ConvexShape: the interface the narrow phase needs from a convex solid: support mappings for GJK/EPA
// and the supporting face used to build contact manifolds by clipping. Immutable; thread-safe.
#pragma once

#include <array>

#include "physics/shapes/Shape.h"

namespace strata {

/// Up to 32 vertices of a face, counter-clockwise seen from outside, in local space.
struct SupportingFace {
  static constexpr int kMaxVertices = 32;
  std::array<Vec3, kMaxVertices> vertices;
  int count = 0;
  Vec3 normal = Vec3::Zero();  ///< outward unit normal where the shape knows it; zero = work it out
  void Add(const Vec3& v) {
    if (count < kMaxVertices) vertices[count++] = v;
  }
};

/// A convex shape = a core (point, segment, shrunk box, shrunk hull) swept by a sphere of core radius.
/// GJK runs on the cheap core and only falls back to EPA on the exact shape for deep penetration.
class ConvexShape : public Shape {
 public:
  /// Farthest point of the exact shape along `direction` (local space; direction need not be unit).
  virtual Vec3 Support(const Vec3& direction) const = 0;
  /// Farthest point of the core along `direction`; core + CoreRadius() lies inside the exact shape.
  virtual Vec3 CoreSupport(const Vec3& direction) const = 0;
  float core_radius() const { return core_radius_; }
  /// Whether the core swept by the core radius is the exact shape (spheres, capsules): distance queries then
  /// measure on the core, which GJK meets exactly, instead of on a curved surface it only approaches.
  virtual bool CoreIsExact() const { return false; }

  /// The face of the exact shape whose outward normal is most aligned with `direction`
  /// (one point for spheres, a segment for capsules lying flat).
  virtual void GetSupportingFace(const Vec3& direction, SupportingFace& face) const = 0;

 protected:
  ConvexShape(ShapeType type, float core_radius) : Shape(type, true), core_radius_(core_radius) {}

 private:
  float core_radius_;
};

}  // namespace strata
