#include "physics/constraints/ContactConstraint.h"

#include <cmath>

#include <algorithm>
#include <new>

namespace strata {

SoftSpring MakeSoftSpring(float hertz, float damping_ratio, float h) {
  const float omega = 2.0f * kPi * hertz;
  const float a1 = 2.0f * damping_ratio + h * omega;
  return {omega / a1, h * omega * a1};
}

Softness SoftnessFor(const SoftSpring& spring, float inverse_mass_a, float inverse_mass_b) {
  // The pair's effective mass over the heavier body's: 1 against a fixed body, 1/2 for equal masses,
  // about 1/1000 for a 1:1000 pair.
  const float total = inverse_mass_a + inverse_mass_b;
  const float lighter = std::min(inverse_mass_a > 0.0f ? inverse_mass_a : kLargeFloat,
                                 inverse_mass_b > 0.0f ? inverse_mass_b : kLargeFloat);
  const float ratio = total > 0.0f && lighter < kLargeFloat ? lighter / total : 1.0f;
  const float denominator = spring.stiffness + ratio;
  return {spring.bias_rate, spring.stiffness / denominator, ratio / denominator};
}

float ApproachAtImpact(float normal_velocity, float gain_per_substep, float substep, float separation) {
  // Back to the step's start (the velocities hold the first substep's share of gravity and forces), then
  // across the gap under the pair's relative acceleration, constant over the step: a ball that began the
  // step above the floor meets it faster than it was falling then, and a bounce from the slower speed
  // loses up to 2 g dt / v of its height (10% at dt 1/30 from 2 m).
  const float start = normal_velocity - gain_per_substep;
  if (start >= 0.0f || separation <= 0.0f || substep <= 0.0f) return start;
  const float acceleration = gain_per_substep / substep;
  if (acceleration >= 0.0f) return start;
  return -std::sqrt(start * start - 2.0f * acceleration * separation);
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
  c->reports = cache->reports;
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
        ApproachAtImpact((velocity_b + spin_b.cross(p.r_b) - velocity_a - spin_a.cross(p.r_a)).dot(normal),
                         (b.velocity_gain - a.velocity_gain).dot(normal), a.substep, p.separation);
  }
  return c;
}

}  // namespace strata
