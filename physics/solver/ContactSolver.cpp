#include "physics/solver/ContactSolver.h"

namespace strata {

namespace {

float EffectiveMass(const SolverBody& a, const SolverBody& b, const Vec3& r_a, const Vec3& r_b,
                    const Vec3& axis) {
  const Vec3 ra_x = r_a.cross(axis), rb_x = r_b.cross(axis);
  const float k = a.inverse_mass + b.inverse_mass + ra_x.dot(a.inverse_inertia * ra_x) +
                  rb_x.dot(b.inverse_inertia * rb_x);
  return k > 0.0f ? 1.0f / k : 0.0f;
}

Vec3 RelativeVelocity(const SolverBody& a, const SolverBody& b, const Vec3& r_a, const Vec3& r_b) {
  return b.linear_velocity + b.angular_velocity.cross(r_b) - a.linear_velocity -
         a.angular_velocity.cross(r_a);
}

template <class AxisPart>
void SetupAxis(const SolverBody& a, const SolverBody& b, const Vec3& r_a, const Vec3& r_b, const Vec3& axis,
               AxisPart& part) {
  part.angular_a = r_a.cross(axis);
  part.angular_b = r_b.cross(axis);
  part.response_a = a.inverse_inertia * part.angular_a;
  part.response_b = b.inverse_inertia * part.angular_b;
  const float k = a.inverse_mass + b.inverse_mass + part.angular_a.dot(part.response_a) +
                  part.angular_b.dot(part.response_b);
  part.mass = k > 0.0f ? 1.0f / k : 0.0f;
  part.impulse = 0.0f;
}

template <class AxisPart>
float AxisVelocity(const SolverBody& a, const SolverBody& b, const Vec3& axis, const AxisPart& part) {
  return axis.dot(b.linear_velocity - a.linear_velocity) + part.angular_b.dot(b.angular_velocity) -
         part.angular_a.dot(a.angular_velocity);
}

template <class AxisPart>
void ApplyAxisImpulse(SolverBody& a, SolverBody& b, const Vec3& axis, const AxisPart& part, float impulse) {
  a.linear_velocity -= (a.inverse_mass * impulse) * axis;
  a.angular_velocity -= impulse * part.response_a;
  b.linear_velocity += (b.inverse_mass * impulse) * axis;
  b.angular_velocity += impulse * part.response_b;
}

}  // namespace

void ContactSolver::Setup(std::span<const ContactManifold> manifolds, std::span<const std::uint32_t> body_a,
                          std::span<const std::uint32_t> body_b, std::span<const ContactMaterial> materials,
                          std::span<const SolverBody> bodies, const ContactCache& cache, float dt,
                          const PhysicsSettings& settings) {
  constraints_.clear();
  constraints_.reserve(manifolds.size());
  for (std::size_t m = 0; m < manifolds.size(); ++m) {
    const ContactManifold& manifold = manifolds[m];
    Constraint c;
    c.a = body_a[m];
    c.b = body_b[m];
    c.normal = manifold.normal;
    c.tangent[0] = AnyPerpendicular(c.normal);
    c.tangent[1] = c.normal.cross(c.tangent[0]);
    c.friction = materials[m].friction;
    c.bounce_shift = 0.0f;
    c.count = manifold.count;
    c.key = {manifold.body_a, manifold.body_b, manifold.sub_shape_b};
    const SolverBody& a = bodies[c.a];
    const SolverBody& b = bodies[c.b];
    const CachedManifold* cached = cache.FindPrevious(c.key);
    const float restitution = materials[m].restitution;
    for (int i = 0; i < manifold.count; ++i) {
      const ContactPoint& contact = manifold.points[i];
      Point& p = c.points[i];
      const Vec3 r_a = contact.position_a - a.center_of_mass;
      const Vec3 r_b = contact.position_b - b.center_of_mass;
      p.local_a = a.rotation.conjugate() * r_a;
      p.local_b = b.rotation.conjugate() * r_b;
      SetupAxis(a, b, r_a, r_b, c.normal, p.normal);
      SetupAxis(a, b, r_a, r_b, c.tangent[0], p.tangent[0]);
      SetupAxis(a, b, r_a, r_b, c.tangent[1], p.tangent[1]);
      p.separation = contact.separation;
      if (cached) {
        for (int k = 0; k < cached->count; ++k) {
          if ((cached->local_point_a[k] - p.local_a).squaredNorm() >
              settings.contact_match_distance * settings.contact_match_distance)
            continue;
          p.normal.impulse = cached->normal_impulse[k];
          p.tangent[0].impulse = cached->friction_impulse[k].dot(c.tangent[0]);
          p.tangent[1].impulse = cached->friction_impulse[k].dot(c.tangent[1]);
          break;
        }
      }
      const float approach = RelativeVelocity(a, b, r_a, r_b).dot(c.normal);
      const bool fast = approach < -settings.min_velocity_for_restitution && restitution > 0.0f;
      if (fast && p.separation <= -approach * dt) {
        // Touching now or before the step ends: bounce. A speculative contact bounces early, so the
        // bodies are shifted by the lost travel after integration (ApplyBounceCorrection), and the
        // impact speed includes what gravity adds over the remaining gap.
        const float closing_acceleration =
            std::max(0.0f, (a.gravity_factor - b.gravity_factor) * settings.gravity.dot(c.normal));
        const float gap = std::max(0.0f, p.separation);
        const float impact = std::sqrt(approach * approach + 2.0f * closing_acceleration * gap);
        p.target_velocity = restitution * impact;
        if (p.separation > 0.0f) {
          c.bounce_shift = std::max(c.bounce_shift, (1.0f + restitution) * p.separation);
          p.normal.impulse = 0.0f;
        }
      } else {
        // Speculative: the bodies may close the gap this step but no further.
        p.target_velocity = p.separation > 0.0f ? -p.separation / dt : 0.0f;
      }
    }
    constraints_.push_back(c);
  }
}

void ContactSolver::WarmStart(std::span<SolverBody> bodies) const {
  for (const Constraint& c : constraints_) {
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b];
    for (int i = 0; i < c.count; ++i) {
      const Point& p = c.points[i];
      ApplyAxisImpulse(a, b, c.normal, p.normal, p.normal.impulse);
      ApplyAxisImpulse(a, b, c.tangent[0], p.tangent[0], p.tangent[0].impulse);
      ApplyAxisImpulse(a, b, c.tangent[1], p.tangent[1], p.tangent[1].impulse);
    }
  }
}

void ContactSolver::SolveVelocities(std::span<SolverBody> bodies, int iteration) {
  // Visiting a manifold's points in alternating order keeps the first-solved point from always getting
  // the larger share, which would otherwise tilt resting stacks a little every step.
  const bool reverse = (iteration & 1) != 0;
  for (Constraint& c : constraints_) {
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b];
    // Friction first, bounded by the current normal impulse, then the non-penetration constraint, which
    // is the one that must hold best at the end of the pass. Both friction axes are solved together with
    // one mass and clamped to the friction circle, so the friction impulse opposes the sliding velocity
    // whatever the tangent basis (a per-axis mass or a box clamp would skew it and spin sliding bodies).
    for (int k = 0; k < c.count; ++k) {
      Point& p = c.points[reverse ? c.count - 1 - k : k];
      const float limit = c.friction * p.normal.impulse;
      const float mass = std::min(p.tangent[0].mass, p.tangent[1].mass);
      const float old_first = p.tangent[0].impulse, old_second = p.tangent[1].impulse;
      float first = old_first - AxisVelocity(a, b, c.tangent[0], p.tangent[0]) * mass;
      float second = old_second - AxisVelocity(a, b, c.tangent[1], p.tangent[1]) * mass;
      const float length2 = first * first + second * second;
      if (length2 > limit * limit) {
        const float scale = length2 > 0.0f ? limit / std::sqrt(length2) : 0.0f;
        first *= scale;
        second *= scale;
      }
      p.tangent[0].impulse = first;
      p.tangent[1].impulse = second;
      ApplyAxisImpulse(a, b, c.tangent[0], p.tangent[0], first - old_first);
      ApplyAxisImpulse(a, b, c.tangent[1], p.tangent[1], second - old_second);
    }
    for (int k = 0; k < c.count; ++k) {
      Point& p = c.points[reverse ? c.count - 1 - k : k];
      const float velocity = AxisVelocity(a, b, c.normal, p.normal);
      const float old_impulse = p.normal.impulse;
      p.normal.impulse = std::max(0.0f, old_impulse - (velocity - p.target_velocity) * p.normal.mass);
      ApplyAxisImpulse(a, b, c.normal, p.normal, p.normal.impulse - old_impulse);
    }
  }
}

void ContactSolver::StoreImpulses(ContactCache& cache) const {
  for (const Constraint& c : constraints_) {
    CachedManifold cached;
    cached.count = c.count;
    for (int i = 0; i < c.count; ++i) {
      const Point& p = c.points[i];
      cached.local_point_a[i] = p.local_a;
      cached.normal_impulse[i] = p.normal.impulse;
      cached.friction_impulse[i] = p.tangent[0].impulse * c.tangent[0] + p.tangent[1].impulse * c.tangent[1];
    }
    cache.Store(c.key, cached);
  }
}

void ContactSolver::ApplyBounceCorrection(std::span<SolverBody> bodies) const {
  for (const Constraint& c : constraints_) {
    if (c.bounce_shift <= 0.0f) continue;
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b];
    const float total = a.inverse_mass + b.inverse_mass;
    if (total <= 0.0f) continue;
    a.center_of_mass += c.normal * (c.bounce_shift * a.inverse_mass / total);
    b.center_of_mass -= c.normal * (c.bounce_shift * b.inverse_mass / total);
  }
}

float ContactSolver::SolvePositions(std::span<SolverBody> bodies, const PhysicsSettings& settings) const {
  float deepest = 0.0f;
  for (const Constraint& c : constraints_) {
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b];
    for (int i = 0; i < c.count; ++i) {
      const Point& p = c.points[i];
      const Vec3 r_a = a.rotation * p.local_a;
      const Vec3 r_b = b.rotation * p.local_b;
      const float separation = (b.center_of_mass + r_b - a.center_of_mass - r_a).dot(c.normal);
      deepest = std::min(deepest, separation);
      const float correction = std::clamp(settings.baumgarte * (separation + settings.penetration_slop),
                                          -settings.max_position_correction, 0.0f);
      if (correction >= 0.0f) continue;
      const float mass = EffectiveMass(a, b, r_a, r_b, c.normal);
      const Vec3 impulse = (-correction * mass) * c.normal;
      a.center_of_mass -= a.inverse_mass * impulse;
      b.center_of_mass += b.inverse_mass * impulse;
      // Rotate by the angular "impulse" as a small rotation vector.
      const Vec3 turn_a = -(a.inverse_inertia * r_a.cross(impulse));
      const Vec3 turn_b = b.inverse_inertia * r_b.cross(impulse);
      auto rotate = [](Quat& q, const Vec3& turn) {
        if (turn.squaredNorm() == 0.0f) return;
        const Quat delta(0.0f, 0.5f * turn.x(), 0.5f * turn.y(), 0.5f * turn.z());
        q.coeffs() += (delta * q).coeffs();
        q.normalize();
      };
      rotate(a.rotation, turn_a);
      rotate(b.rotation, turn_b);
    }
  }
  return deepest;
}

}  // namespace strata
