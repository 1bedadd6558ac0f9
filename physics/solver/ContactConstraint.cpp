#include "physics/solver/ContactConstraint.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace strata {

ContactConstraint* BuildContactConstraint(BlockArena& arena, const Vec3& normal,
                                          std::span<const ContactArms> points, const ContactSide& a,
                                          const ContactSide& b, float friction, float restitution,
                                          CachedManifold* cache, float dt, const PhysicsSettings& settings) {
  const auto count = static_cast<int>(points.size());
  void* memory = arena.Allocate(ContactConstraint::Bytes(count), alignof(ContactConstraint));
  auto* c = new (memory) ContactConstraint;
  c->normal = normal;
  c->body_a = a.solver_index;
  c->body_b = b.solver_index;
  c->friction = friction;
  c->bounce_shift = 0.0f;
  c->cache = cache;
  c->point_count = static_cast<std::uint8_t>(count);
  c->dynamic_a = a.dynamic;
  c->dynamic_b = b.dynamic;

  const float closing_acceleration =
      std::max(0.0f, (a.gravity_factor - b.gravity_factor) * settings.gravity.dot(normal));
  const Vec3 velocity_a = ToVec3(a.body->linear_velocity), spin_a = ToVec3(a.body->angular_velocity);
  const Vec3 velocity_b = ToVec3(b.body->linear_velocity), spin_b = ToVec3(b.body->angular_velocity);
  const CachedContactPoint* cached = cache->points();
  for (int i = 0; i < count; ++i) {
    const ContactArms& arms = points[i];
    ContactConstraintPoint& p = *new (&c->points()[i]) ContactConstraintPoint;
    p.r_a = arms.r_a;
    p.r_b = arms.r_b;
    // The fixed body sits at the origin with no rotation, so its "local" point is the world point.
    p.local_a = a.solver_index == 0 ? Vec3(a.center_of_mass + arms.r_a) : cached[i].local_a;
    p.local_b = b.solver_index == 0 ? Vec3(b.center_of_mass + arms.r_b) : cached[i].local_b;
    p.warm_normal = cached[i].normal_impulse;
    p.warm_friction = cached[i].friction_impulse;

    const float approach = (velocity_b + spin_b.cross(p.r_b) - velocity_a - spin_a.cross(p.r_a)).dot(normal);
    const bool fast = approach < -settings.min_velocity_for_restitution && restitution > 0.0f;
    const float separation = arms.separation;
    if (fast && separation <= -approach * dt) {
      // Touching now or before the step ends: bounce. A speculative contact bounces early, so the bodies are
      // shifted by the lost travel after integration, and the impact speed includes what gravity adds over
      // the remaining gap.
      const float gap = std::max(0.0f, separation);
      const float impact = std::sqrt(approach * approach + 2.0f * closing_acceleration * gap);
      p.target_velocity = restitution * impact;
      if (separation > 0.0f) {
        c->bounce_shift = std::max(c->bounce_shift, (1.0f + restitution) * separation);
        p.warm_normal = 0.0f;
      }
    } else {
      // Speculative: the bodies may close the gap this step but no further.
      p.target_velocity = separation > 0.0f ? -separation / dt : 0.0f;
    }
  }
  return c;
}

void ApplyContactBounceShift(const ContactConstraint& c, const SolverBody* bodies, SolverPose* poses) {
  if (c.bounce_shift <= 0.0f) return;
  const float inverse_mass_a = bodies[c.body_a].inverse_mass, inverse_mass_b = bodies[c.body_b].inverse_mass;
  const float total = inverse_mass_a + inverse_mass_b;
  if (total <= 0.0f) return;
  const Vec4 normal = ToVec4(c.normal);
  if (c.dynamic_a) poses[c.body_a].center_of_mass += normal * (c.bounce_shift * inverse_mass_a / total);
  if (c.dynamic_b) poses[c.body_b].center_of_mass -= normal * (c.bounce_shift * inverse_mass_b / total);
}

}  // namespace strata
