#include "physics/solver/ContactConstraint.h"

#include <new>

namespace strata {

Softness MakeSoftness(float hertz, float damping_ratio, float h) {
  if (hertz <= 0.0f) return {};
  const float omega = 2.0f * kPi * hertz;
  const float a1 = 2.0f * damping_ratio + h * omega;
  const float a2 = h * omega * a1;
  const float a3 = 1.0f / (1.0f + a2);
  return {omega / a1, a2 * a3, a3};
}

ContactConstraint* BuildContactConstraint(BlockArena& arena, const Vec3& normal,
                                          std::span<const ContactArms> points, const ContactSide& a,
                                          const ContactSide& b, float friction, float restitution,
                                          CachedManifold* cache) {
  const auto count = static_cast<int>(points.size());
  void* memory = arena.Allocate(ContactConstraint::Bytes(count), alignof(ContactConstraint));
  auto* c = new (memory) ContactConstraint;
  c->normal = normal;
  c->body_a = a.solver_index;
  c->body_b = b.solver_index;
  c->friction = friction;
  c->restitution = restitution;
  c->cache = cache;
  c->point_count = static_cast<std::uint8_t>(count);
  c->dynamic_a = a.dynamic;
  c->dynamic_b = b.dynamic;
  const Vec3 velocity_a = ToVec3(a.body->linear_velocity), spin_a = ToVec3(a.body->angular_velocity);
  const Vec3 velocity_b = ToVec3(b.body->linear_velocity), spin_b = ToVec3(b.body->angular_velocity);
  const CachedContactPoint* cached = cache->points();
  for (int i = 0; i < count; ++i) {
    const ContactArms& arms = points[i];
    ContactConstraintPoint& p = *new (&c->points()[i]) ContactConstraintPoint;
    p.r_a = arms.r_a;
    p.r_b = arms.r_b;
    p.warm_normal = cached[i].normal_impulse;
    p.warm_friction = cached[i].friction_impulse;
    p.separation = arms.separation;
    p.normal_velocity =
        (velocity_b + spin_b.cross(p.r_b) - velocity_a - spin_a.cross(p.r_a)).dot(normal);
  }
  return c;
}

}  // namespace strata
