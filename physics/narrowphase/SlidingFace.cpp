#include "physics/narrowphase/SlidingFace.h"

#include <algorithm>
#include <cmath>

namespace strata {

SlidingFace MakeSlidingFace(const ContactManifold& manifold, const PosedBody& face_body, const Quat& turn) {
  const ContactFace& face = manifold.face;
  const auto to_body = face_body.rotation.transpose();
  // The points are the other body's face corners in order round that face.
  float shortest = kLargeFloat;
  for (int i = 0; i < manifold.count; ++i) {
    const ContactPoint& from = manifold.points[i];
    const ContactPoint& to = manifold.points[(i + 1) % manifold.count];
    shortest = std::min(shortest, face.on_a ? (to.position_b - from.position_b).squaredNorm()
                                            : (to.position_a - from.position_a).squaredNorm());
  }
  SlidingFace sliding;
  sliding.centre = to_body * (face.centre - face_body.center_of_mass);
  sliding.u = to_body * face.u;
  sliding.v = to_body * face.v;
  sliding.normal = to_body * face.normal;
  sliding.half_u = face.half_u;
  sliding.half_v = face.half_v;
  sliding.corner_face_half = 0.5f * std::sqrt(shortest);
  sliding.on_a = face.on_a;
  sliding.found_turn = turn;
  return sliding;
}

bool SlideCorners(const SlidingFace& face, const PosedBody& face_body, const PosedBody& corner_body,
                  std::span<const Vec3> corners, float max_separation, ContactManifold& out) {
  if (corners.size() > static_cast<std::size_t>(ContactManifold::kMaxPoints)) return false;
  const Mat3& turn = face_body.rotation;
  const Vec3 normal = turn * face.normal, u = turn * face.u, v = turn * face.v;
  const Vec3 centre = face_body.center_of_mass + turn * face.centre;
  // The points are written only once every corner passed; until then only the corners and their heights
  // are kept (copying whole points from a scratch array re-read fresh piecewise stores in wider loads, which
  // stalls).
  Vec3 placed[ContactManifold::kMaxPoints];
  float heights[ContactManifold::kMaxPoints];
  float clearance = kLargeFloat, deepest = 0.0f;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    placed[i] = corner_body.center_of_mass + corner_body.rotation * corners[i];
    const Vec3 offset = placed[i] - centre;
    heights[i] = normal.dot(offset);
    // The shape test would drop this corner: let it decide what is left.
    if (heights[i] > max_separation) return false;
    clearance =
        std::min({clearance, face.half_u - std::abs(u.dot(offset)), face.half_v - std::abs(v.dot(offset))});
    deepest = std::max(deepest, -heights[i]);
  }
  // Off the face, or deeper in than a side of either body is away: that side could be the shallower way out.
  if (!(deepest < clearance && deepest < face.corner_face_half)) return false;
  out.normal = face.on_a ? normal : Vec3(-normal);
  out.count = static_cast<int>(corners.size());
  for (std::size_t i = 0; i < corners.size(); ++i) {
    ContactPoint& point = out.points[i];
    const Vec3 on_face = placed[i] - heights[i] * normal;
    point.position_a = face.on_a ? on_face : placed[i];
    point.position_b = face.on_a ? placed[i] : on_face;
    point.separation = heights[i];
  }
  return true;
}

}  // namespace strata
