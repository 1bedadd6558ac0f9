#include "physics/solver/ContactSolver.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace strata {

namespace {

constexpr int kNormal = 0;
constexpr int kFirstTangent = 1;
constexpr int kSecondTangent = 2;

// Velocity along a constraint row: axis . (v_b - v_a) + angular_b . w_b - angular_a . w_a, summed in one
// horizontal add.
inline float RowVelocity(const Vec4& axis, const Vec4& angular_a, const Vec4& angular_b, const Vec4& va,
                         const Vec4& wa, const Vec4& vb, const Vec4& wb) {
  return (axis.cwiseProduct(vb - va) + angular_b.cwiseProduct(wb) - angular_a.cwiseProduct(wa)).sum();
}

// Turns `rotation` by the small rotation vector `turn` (first order, renormalised).
inline void Turn(Quat& rotation, const Vec4& turn) {
  const Quat delta(0.0f, 0.5f * turn.x(), 0.5f * turn.y(), 0.5f * turn.z());
  rotation.coeffs() += (delta * rotation).coeffs();
  rotation.normalize();
}

inline float InverseEffectiveMass(const SolverBody& a, const SolverBody& b, const Vec4& angular_a,
                                  const Vec4& angular_b, Vec4& response_a, Vec4& response_b) {
  response_a = a.InverseInertiaTimes(angular_a);
  response_b = b.InverseInertiaTimes(angular_b);
  return a.inverse_mass + b.inverse_mass + angular_a.dot(response_a) + angular_b.dot(response_b);
}

template <bool kDynamicA, bool kDynamicB>
void SolveVelocity(SolverContact& c, SolverBody* bodies, bool reverse) {
  SolverBody& a = bodies[c.constraint->body_a];
  SolverBody& b = bodies[c.constraint->body_b];
  Vec4 va = a.linear_velocity, wa = a.angular_velocity;
  Vec4 vb = b.linear_velocity, wb = b.angular_velocity;
  const float inverse_mass_a = a.inverse_mass, inverse_mass_b = b.inverse_mass;
  const Vec4 normal = c.normal, first_axis = c.tangent[0], second_axis = c.tangent[1];
  const int count = c.point_count;
  SolverContactPoint* points = c.points();
  // Friction first, bounded by the current normal impulse, then non-penetration, which must hold best at
  // the end of the pass. Both friction axes share one mass and are clamped to the friction circle together.
  for (int k = 0; k < count; ++k) {
    SolverContactPoint& p = points[reverse ? count - 1 - k : k];
    const float limit = c.friction * p.normal_impulse;
    const float old_first = p.tangent_impulse[0], old_second = p.tangent_impulse[1];
    float first = old_first - p.tangent_mass * RowVelocity(first_axis, p.angular_a[kFirstTangent],
                                                           p.angular_b[kFirstTangent], va, wa, vb, wb);
    float second = old_second - p.tangent_mass * RowVelocity(second_axis, p.angular_a[kSecondTangent],
                                                             p.angular_b[kSecondTangent], va, wa, vb, wb);
    const float length2 = first * first + second * second;
    if (length2 > limit * limit) {
      const float scale = length2 > 0.0f ? limit / std::sqrt(length2) : 0.0f;
      first *= scale;
      second *= scale;
    }
    p.tangent_impulse[0] = first;
    p.tangent_impulse[1] = second;
    const float delta_first = first - old_first, delta_second = second - old_second;
    const Vec4 impulse = delta_first * first_axis + delta_second * second_axis;
    if constexpr (kDynamicA) {
      va -= inverse_mass_a * impulse;
      wa -= delta_first * p.response_a[kFirstTangent] + delta_second * p.response_a[kSecondTangent];
    }
    if constexpr (kDynamicB) {
      vb += inverse_mass_b * impulse;
      wb += delta_first * p.response_b[kFirstTangent] + delta_second * p.response_b[kSecondTangent];
    }
  }
  for (int k = 0; k < count; ++k) {
    SolverContactPoint& p = points[reverse ? count - 1 - k : k];
    const float velocity = RowVelocity(normal, p.angular_a[kNormal], p.angular_b[kNormal], va, wa, vb, wb);
    const float old_impulse = p.normal_impulse;
    p.normal_impulse = std::max(0.0f, old_impulse - (velocity - p.target_velocity) * p.normal_mass);
    const float delta = p.normal_impulse - old_impulse;
    if constexpr (kDynamicA) {
      va -= (inverse_mass_a * delta) * normal;
      wa -= delta * p.response_a[kNormal];
    }
    if constexpr (kDynamicB) {
      vb += (inverse_mass_b * delta) * normal;
      wb += delta * p.response_b[kNormal];
    }
  }
  if constexpr (kDynamicA) {
    a.linear_velocity = va;
    a.angular_velocity = wa;
  }
  if constexpr (kDynamicB) {
    b.linear_velocity = vb;
    b.angular_velocity = wb;
  }
}

}  // namespace

SolverContact* SetupSolverContact(BlockArena& arena, ContactConstraint& constraint,
                                  const SolverBody* bodies) {
  const int count = constraint.point_count;
  void* memory =
      arena.Allocate(sizeof(SolverContact) + count * sizeof(SolverContactPoint), alignof(SolverContact));
  auto* c = new (memory) SolverContact;
  const Vec3 first_tangent = AnyPerpendicular(constraint.normal);
  c->normal = ToVec4(constraint.normal);
  c->tangent[0] = ToVec4(first_tangent);
  c->tangent[1] = ToVec4(constraint.normal.cross(first_tangent));
  c->constraint = &constraint;
  c->friction = constraint.friction;
  c->point_count = constraint.point_count;
  const SolverBody& a = bodies[constraint.body_a];
  const SolverBody& b = bodies[constraint.body_b];
  const Vec4 axes[3] = {c->normal, c->tangent[0], c->tangent[1]};
  for (int i = 0; i < count; ++i) {
    const ContactConstraintPoint& point = constraint.points()[i];
    const Vec4 r_a = ToVec4(point.r_a), r_b = ToVec4(point.r_b);
    SolverContactPoint& p = *new (&c->points()[i]) SolverContactPoint;
    float masses[3];
    for (int axis = 0; axis < 3; ++axis) {
      p.angular_a[axis] = Cross(r_a, axes[axis]);
      p.angular_b[axis] = Cross(r_b, axes[axis]);
      const float k = InverseEffectiveMass(a, b, p.angular_a[axis], p.angular_b[axis], p.response_a[axis],
                                           p.response_b[axis]);
      masses[axis] = k > 0.0f ? 1.0f / k : 0.0f;
    }
    p.normal_mass = masses[kNormal];
    p.tangent_mass = std::min(masses[kFirstTangent], masses[kSecondTangent]);
    p.target_velocity = point.target_velocity;
    p.normal_impulse = point.warm_normal;
    p.tangent_impulse[0] = point.warm_friction.dot(first_tangent);
    p.tangent_impulse[1] = point.warm_friction.dot(ToVec3(c->tangent[1]));
  }
  return c;
}

void WarmStartContact(const SolverContact& c, SolverBody* bodies) {
  const ContactConstraint& constraint = *c.constraint;
  SolverBody& a = bodies[constraint.body_a];
  SolverBody& b = bodies[constraint.body_b];
  for (int i = 0; i < c.point_count; ++i) {
    const SolverContactPoint& p = c.points()[i];
    const Vec4 impulse = p.normal_impulse * c.normal + p.tangent_impulse[0] * c.tangent[0] +
                         p.tangent_impulse[1] * c.tangent[1];
    if (constraint.dynamic_a) {
      a.linear_velocity -= a.inverse_mass * impulse;
      a.angular_velocity -= p.normal_impulse * p.response_a[kNormal] +
                            p.tangent_impulse[0] * p.response_a[kFirstTangent] +
                            p.tangent_impulse[1] * p.response_a[kSecondTangent];
    }
    if (constraint.dynamic_b) {
      b.linear_velocity += b.inverse_mass * impulse;
      b.angular_velocity += p.normal_impulse * p.response_b[kNormal] +
                            p.tangent_impulse[0] * p.response_b[kFirstTangent] +
                            p.tangent_impulse[1] * p.response_b[kSecondTangent];
    }
  }
}

void SolveContactVelocity(SolverContact& c, SolverBody* bodies, bool reverse) {
  const ContactConstraint& constraint = *c.constraint;
  if (constraint.dynamic_a && constraint.dynamic_b) {
    SolveVelocity<true, true>(c, bodies, reverse);
  } else if (constraint.dynamic_a) {
    SolveVelocity<true, false>(c, bodies, reverse);
  } else if (constraint.dynamic_b) {
    SolveVelocity<false, true>(c, bodies, reverse);
  }
}

void StoreContactImpulses(const SolverContact& c) {
  CachedContactPoint* cached = c.constraint->cache->points();
  for (int i = 0; i < c.point_count; ++i) {
    const SolverContactPoint& p = c.points()[i];
    cached[i].normal_impulse = p.normal_impulse;
    cached[i].friction_impulse =
        ToVec3(p.tangent_impulse[0] * c.tangent[0] + p.tangent_impulse[1] * c.tangent[1]);
  }
}

float SolveContactPosition(const ContactConstraint& c, const SolverBody* bodies, SolverPose* poses,
                           const PhysicsSettings& settings) {
  const SolverBody& a = bodies[c.body_a];
  const SolverBody& b = bodies[c.body_b];
  SolverPose& pose_a = poses[c.body_a];
  SolverPose& pose_b = poses[c.body_b];
  const Vec4 normal = ToVec4(c.normal);
  float deepest = 0.0f;
  for (int i = 0; i < c.point_count; ++i) {
    const ContactConstraintPoint& p = c.points()[i];
    const Vec4 r_a = ToVec4(pose_a.rotation * p.local_a);
    const Vec4 r_b = ToVec4(pose_b.rotation * p.local_b);
    const float separation = (pose_b.center_of_mass + r_b - pose_a.center_of_mass - r_a).dot(normal);
    deepest = std::min(deepest, separation);
    const float correction = std::clamp(settings.baumgarte * (separation + settings.penetration_slop),
                                        -settings.max_position_correction, 0.0f);
    if (correction >= 0.0f) continue;
    const Vec4 angular_a = Cross(r_a, normal), angular_b = Cross(r_b, normal);
    Vec4 response_a, response_b;
    const float k = InverseEffectiveMass(a, b, angular_a, angular_b, response_a, response_b);
    if (k <= 0.0f) continue;
    // A pseudo-impulse along the normal: moves and turns the bodies apart by the correction.
    const float impulse = -correction / k;
    if (c.dynamic_a) {
      pose_a.center_of_mass -= (a.inverse_mass * impulse) * normal;
      Turn(pose_a.rotation, -impulse * response_a);
    }
    if (c.dynamic_b) {
      pose_b.center_of_mass += (b.inverse_mass * impulse) * normal;
      Turn(pose_b.rotation, impulse * response_b);
    }
  }
  return deepest;
}

}  // namespace strata
