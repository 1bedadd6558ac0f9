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

/// The rounding a box or hull gets unless it asks for another (m), Jolt's default convex radius. A small
/// shape gets at most a quarter of its thinnest half-size (ConvexShape::kMaxDefaultRadiusShare).
inline constexpr float kDefaultConvexRadius = 0.05f;

/// A convex shape = a core (point, segment, shrunk box, shrunk hull) swept by a sphere of core radius.
/// GJK runs on the cheap core and only falls back to EPA on the exact shape for deep penetration.
/// Spheres, capsules and rounded boxes and hulls are exactly their core plus the radius (CoreIsExact); a
/// sharp box or hull (convex radius 0) keeps a small core radius inside for GJK's sake, and its corners are
/// sharp.
class ConvexShape : public Shape {
 public:
  /// Farthest point of the exact shape along `direction` (local space; direction need not be unit).
  virtual Vec3 Support(const Vec3& direction) const = 0;
  /// Farthest point of the core along `direction`; core + CoreRadius() lies inside the exact shape.
  virtual Vec3 CoreSupport(const Vec3& direction) const = 0;
  float core_radius() const { return core_radius_; }
  /// Whether the core swept by the core radius is the exact shape (spheres, capsules, rounded boxes and
  /// hulls): distance queries then measure on the core, which GJK meets exactly, instead of on a curved
  /// surface it only approaches.
  bool CoreIsExact() const { return core_is_exact_; }
  /// How far the shape's edges and corners are rounded (m): the core radius where the core is exact, else 0.
  float convex_radius() const { return core_is_exact_ ? core_radius_ : 0.0f; }
  float BoundsRounding() const override { return convex_radius(); }
  /// The share of a shape's thinnest half-size that the default convex radius may take.
  static constexpr float kMaxDefaultRadiusShare = 0.25f;

  /// The face of the exact shape whose outward normal is most aligned with `direction`
  /// (one point for spheres, a segment for capsules lying flat).
  virtual void GetSupportingFace(const Vec3& direction, SupportingFace& face) const = 0;

 protected:
  ConvexShape(ShapeType type, float core_radius, bool core_is_exact)
      : Shape(type, true), core_radius_(core_radius), core_is_exact_(core_is_exact) {}

  /// A ray against the rounded shape (core plus convex radius), given `sharp`, the ray's hit on the sharp
  /// shape the rounding cuts from: the rounded shape lies inside it, so the ray cannot meet it sooner. From
  /// there it steps by the gap to the rounded surface (sphere tracing), which never passes the first touch.
  /// `closest_on_core(p)` is the core's point nearest to p.
  template <class ClosestOnCore>
  bool CastRayRounded(const Vec3& origin, const Vec3& direction, float max_fraction, const ShapeRayHit& sharp,
                      const ClosestOnCore& closest_on_core, ShapeRayHit& hit) const;

 private:
  float core_radius_;
  bool core_is_exact_;
};

template <class ClosestOnCore>
bool ConvexShape::CastRayRounded(const Vec3& origin, const Vec3& direction, float max_fraction,
                                 const ShapeRayHit& sharp, const ClosestOnCore& closest_on_core,
                                 ShapeRayHit& hit) const {
  // Gaps below a hundredth of a millimetre are a touch; a grazing ray that has not closed its gap in this
  // many steps passes within that of the surface.
  constexpr float kTouch = 1e-5f;
  constexpr int kMaxSteps = 64;
  const float length = direction.norm();
  float fraction = sharp.fraction;
  float previous_gap = kLargeFloat;
  for (int step = 0; step < kMaxSteps; ++step) {
    const Vec3 point = origin + fraction * direction;
    const Vec3 outward = point - closest_on_core(point);
    const float from_core = outward.norm();
    const float gap = from_core - core_radius_;
    if (gap <= kTouch) {
      hit.fraction = fraction;
      hit.sub_shape = 0;
      // Where the sharp face is met on the rounded shape's flat part, the face's normal is exact.
      if (step == 0 || from_core < 1e-6f)
        hit.normal = sharp.normal;
      else
        hit.normal = outward / from_core;
      return true;
    }
    // The gap along a line to a convex set falls, then rises: once it rises the ray has passed the shape.
    if (gap >= previous_gap || length == 0.0f) return false;
    previous_gap = gap;
    fraction += gap / length;
    if (fraction > max_fraction) return false;
  }
  return false;
}

}  // namespace strata
