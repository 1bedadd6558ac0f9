// ConvexSupport: world-space support mappings that GJK and EPA run on (a posed ConvexShape, its core, or
// a single mesh triangle). Light, stack-allocated views; safe from any thread.
#pragma once

#include "physics/shapes/ConvexShape.h"

namespace strata {

/// Farthest point along a direction, in world space.
class ConvexSupport {
 public:
  virtual ~ConvexSupport() = default;
  virtual Vec3 Support(const Vec3& direction) const = 0;
  /// Any point inside, used to seed the search direction.
  virtual Vec3 Center() const = 0;
};

/// A ConvexShape at a pose; `use_core` selects the shrunk core instead of the exact shape. The rotation is
/// kept as a matrix: GJK asks for a support a dozen times a pair (and per triangle on a mesh), and two
/// matrix products cost less than two quaternion rotations.
class PosedConvex final : public ConvexSupport {
 public:
  PosedConvex(const ConvexShape& shape, const Pose& pose, bool use_core)
      : PosedConvex(shape, pose.position, pose.rotation.toRotationMatrix(), use_core) {}
  /// With the pose's rotation already a matrix (a pair's core and exact shape share one).
  PosedConvex(const ConvexShape& shape, const Vec3& position, const Mat3& rotation, bool use_core)
      : shape_(shape), position_(position), rotation_(rotation), use_core_(use_core) {}
  Vec3 Support(const Vec3& direction) const override {
    const Vec3 local = rotation_.transpose() * direction;
    return position_ + rotation_ * (use_core_ ? shape_.CoreSupport(local) : shape_.Support(local));
  }
  Vec3 Center() const override { return position_ + rotation_ * shape_.LocalBounds().Center(); }

 private:
  const ConvexShape& shape_;
  Vec3 position_;
  Mat3 rotation_;
  bool use_core_;
};

/// A convex shape at a pose as distance queries measure it: its core and the core radius around it where
/// that is the shape exactly (spheres, capsules: ConvexShape::CoreIsExact), else the exact shape, radius 0.
struct MeasuredConvex {
  MeasuredConvex(const ConvexShape& shape, const Pose& pose)
      : support(shape, pose, shape.CoreIsExact()), radius(shape.CoreIsExact() ? shape.core_radius() : 0.0f) {}
  PosedConvex support;
  float radius;
};

/// A single point as a support mapping.
class PointSupport final : public ConvexSupport {
 public:
  explicit PointSupport(const Vec3& point) : point_(point) {}
  Vec3 Support(const Vec3&) const override { return point_; }
  Vec3 Center() const override { return point_; }

 private:
  Vec3 point_;
};

/// One triangle in world space.
class TriangleSupport final : public ConvexSupport {
 public:
  TriangleSupport(const Vec3& a, const Vec3& b, const Vec3& c) : vertices_{a, b, c} {}
  Vec3 Support(const Vec3& direction) const override {
    const float da = vertices_[0].dot(direction), db = vertices_[1].dot(direction),
                dc = vertices_[2].dot(direction);
    if (da >= db && da >= dc) return vertices_[0];
    return db >= dc ? vertices_[1] : vertices_[2];
  }
  Vec3 Center() const override { return (vertices_[0] + vertices_[1] + vertices_[2]) / 3.0f; }
  const Vec3& vertex(int i) const { return vertices_[i]; }

 private:
  Vec3 vertices_[3];
};

}  // namespace strata
