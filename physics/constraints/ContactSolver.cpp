#include "physics/constraints/ContactSolver.h"

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

// A side the solver does not move (static, sleeping, kinematic) has no inverse inertia: its response is zero
// without the product (most contacts of a level have one such side).
inline float InverseEffectiveMass(const SolverBody& a, const SolverBody& b, bool dynamic_a, bool dynamic_b,
                                  const Vec4& angular_a, const Vec4& angular_b, Vec4& response_a,
                                  Vec4& response_b) {
  response_a = dynamic_a ? a.InverseInertiaTimes(angular_a) : Vec4::Zero();
  response_b = dynamic_b ? b.InverseInertiaTimes(angular_b) : Vec4::Zero();
  float k = a.inverse_mass + b.inverse_mass;
  if (dynamic_a) k += angular_a.dot(response_a);
  if (dynamic_b) k += angular_b.dot(response_b);
  return k;
}

// Point `p`'s rows for axes [first_axis, end_axis) of `axes` (normal, first tangent, second tangent), and
// each row's mass (1 / inverse effective mass) in `masses`.
void SetupPointRows(const ContactConstraint& constraint, const ContactConstraintPoint& point,
                    const SolverBody* bodies, const Vec4 axes[3], int first_axis, int end_axis,
                    SolverContactPoint& p, float masses[3]) {
  const SolverBody& a = bodies[constraint.body_a];
  const SolverBody& b = bodies[constraint.body_b];
  const Vec4 r_a = ToVec4(point.r_a), r_b = ToVec4(point.r_b);
  for (int axis = first_axis; axis < end_axis; ++axis) {
    p.angular_a[axis] = Cross(r_a, axes[axis]);
    p.angular_b[axis] = Cross(r_b, axes[axis]);
    const float k = InverseEffectiveMass(a, b, constraint.dynamic_a, constraint.dynamic_b, p.angular_a[axis],
                                         p.angular_b[axis], p.response_a[axis], p.response_b[axis]);
    masses[axis] = k > 0.0f ? 1.0f / k : 0.0f;
  }
}

// How a side moved and turned since the step began: its deltas if the solver moves it, else its velocity
// times the elapsed time (kinematic bodies; the fixed body does not move).
inline void SideMotion(const SolverBody& body, bool dynamic, float elapsed, Vec4& moved, Vec4& turned) {
  moved = dynamic ? body.delta_position : body.linear_velocity * elapsed;
  turned = dynamic ? body.delta_rotation : body.angular_velocity * elapsed;
}

template <bool kDynamicA, bool kDynamicB>
void ApplyNormal(const SolverContact& c, const SolverContactPoint& p, float delta, float inverse_mass_a,
                 float inverse_mass_b, Vec4& va, Vec4& wa, Vec4& vb, Vec4& wb) {
  if constexpr (kDynamicA) {
    va -= (inverse_mass_a * delta) * c.normal;
    wa -= delta * p.response_a[kNormal];
  }
  if constexpr (kDynamicB) {
    vb += (inverse_mass_b * delta) * c.normal;
    wb += delta * p.response_b[kNormal];
  }
}

// Writes the pass's velocities back to the sides the solver moves.
template <bool kDynamicA, bool kDynamicB>
void StoreVelocities(SolverBody& a, SolverBody& b, const Vec4& va, const Vec4& wa, const Vec4& vb,
                     const Vec4& wb) {
  if constexpr (kDynamicA) {
    a.linear_velocity = va;
    a.angular_velocity = wa;
  }
  if constexpr (kDynamicB) {
    b.linear_velocity = vb;
    b.angular_velocity = wb;
  }
}

template <bool kDynamicA, bool kDynamicB>
void SolveVelocity(SolverContact& c, SolverBody* bodies, const SubstepContext& context, bool use_bias,
                   bool reverse, float* deepest) {
  SolverBody& a = bodies[c.constraint->body_a];
  SolverBody& b = bodies[c.constraint->body_b];
  Vec4 va = a.linear_velocity, wa = a.angular_velocity;
  Vec4 vb = b.linear_velocity, wb = b.angular_velocity;
  Vec4 moved_a, turned_a, moved_b, turned_b;
  SideMotion(a, kDynamicA, context.elapsed, moved_a, turned_a);
  SideMotion(b, kDynamicB, context.elapsed, moved_b, turned_b);
  const float moved_apart = c.normal.dot(moved_b - moved_a);
  const float inverse_mass_a = a.inverse_mass, inverse_mass_b = b.inverse_mass;
  const Vec4 first_axis = c.tangent[0], second_axis = c.tangent[1];
  const int count = c.point_count;
  SolverContactPoint* points = c.points();
  float lowest = kLargeFloat;
  for (int k = 0; k < count; ++k) {
    SolverContactPoint& p = points[reverse ? count - 1 - k : k];
    // Separation now: at the start of the step plus how the bodies moved and turned since (first order).
    const float separation =
        p.separation + moved_apart + p.angular_b[kNormal].dot(turned_b) - p.angular_a[kNormal].dot(turned_a);
    lowest = std::min(lowest, separation);
    // A gap may close within this substep and no further; overlap is pushed out softly.
    float bias = 0.0f, mass_scale = 1.0f, impulse_scale = 0.0f;
    if (separation > 0.0f) {
      bias = separation * context.inverse_h;
    } else if (use_bias) {
      bias = std::max(c.softness.bias_rate * separation, -context.max_push_velocity);
      mass_scale = c.softness.mass_scale;
      impulse_scale = c.softness.impulse_scale;
    }
    const float velocity = RowVelocity(c.normal, p.angular_a[kNormal], p.angular_b[kNormal], va, wa, vb, wb);
    const float old_impulse = p.normal_impulse;
    p.normal_impulse = std::max(
        0.0f, old_impulse - p.normal_mass * mass_scale * (velocity + bias) - impulse_scale * old_impulse);
    const float delta = p.normal_impulse - old_impulse;
    p.max_normal_impulse = std::max(p.max_normal_impulse, delta);
    ApplyNormal<kDynamicA, kDynamicB>(c, p, delta, inverse_mass_a, inverse_mass_b, va, wa, vb, wb);
  }
  // Friction, bounded by the normal impulse just solved (as Box2D v3 orders them: a limit from before this
  // substep's gravity lets a box on a slope creep). Both friction axes share one mass and are clamped to the
  // friction circle together. A frictionless contact holds no friction impulse (Setup leaves it none), so
  // its rows would only clamp zero to zero.
  for (int k = 0; k < (c.friction > 0.0f ? count : 0); ++k) {
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
  if (deepest != nullptr) *deepest = std::min(*deepest, lowest);
  StoreVelocities<kDynamicA, kDynamicB>(a, b, va, wa, vb, wb);
}

template <bool kDynamicA, bool kDynamicB>
void Restitution(SolverContact& c, SolverBody* bodies, const SubstepContext& context) {
  SolverBody& a = bodies[c.constraint->body_a];
  SolverBody& b = bodies[c.constraint->body_b];
  Vec4 va = a.linear_velocity, wa = a.angular_velocity;
  Vec4 vb = b.linear_velocity, wb = b.angular_velocity;
  for (int i = 0; i < c.point_count; ++i) {
    SolverContactPoint& p = c.points()[i];
    // Only where the approach was fast and the contact did push (a gap that stayed open must not bounce).
    if (p.normal_velocity > -context.restitution_threshold || p.max_normal_impulse <= 0.0f) continue;
    const float velocity = RowVelocity(c.normal, p.angular_a[kNormal], p.angular_b[kNormal], va, wa, vb, wb);
    const float old_impulse = p.normal_impulse;
    p.normal_impulse =
        std::max(0.0f, old_impulse - p.normal_mass * (velocity + c.restitution * p.normal_velocity));
    ApplyNormal<kDynamicA, kDynamicB>(c, p, p.normal_impulse - old_impulse, a.inverse_mass, b.inverse_mass,
                                      va, wa, vb, wb);
  }
  StoreVelocities<kDynamicA, kDynamicB>(a, b, va, wa, vb, wb);
}

}  // namespace

ContactMotion MotionSinceStepBegan(const SolverContact& c, const SolverBody* bodies, float elapsed) {
  const ContactConstraint& constraint = *c.constraint;
  Vec4 moved_a, moved_b;
  ContactMotion motion;
  SideMotion(bodies[constraint.body_a], constraint.dynamic_a, elapsed, moved_a, motion.turned_a);
  SideMotion(bodies[constraint.body_b], constraint.dynamic_b, elapsed, moved_b, motion.turned_b);
  motion.moved_apart = c.normal.dot(moved_b - moved_a);
  return motion;
}

SolverContact* SetupSolverContact(BlockArena& arena, ContactConstraint& constraint, const SolverBody* bodies,
                                  const SubstepContext& context, bool point_friction_rows) {
  const int count = constraint.point_count;
  void* memory =
      arena.Allocate(sizeof(SolverContact) + count * sizeof(SolverContactPoint), alignof(SolverContact));
  auto* c = new (memory) SolverContact;
  // The basis in 4-wide vectors (a 3-vector temporary here was re-read in wider loads than it was stored in).
  c->normal = ToVec4(constraint.normal);
  c->tangent[0] = ToVec4(AnyPerpendicular(constraint.normal));
  c->tangent[1] = Cross(c->normal, c->tangent[0]);
  c->constraint = &constraint;
  c->softness = SoftnessFor(
      constraint.dynamic_a && constraint.dynamic_b ? context.between_moving : context.against_fixed,
      bodies[constraint.body_a].inverse_mass, bodies[constraint.body_b].inverse_mass);
  c->friction = constraint.friction;
  c->restitution = constraint.restitution;
  c->point_count = constraint.point_count;
  const Vec4 axes[3] = {c->normal, c->tangent[0], c->tangent[1]};
  // A frictionless contact's friction rows would never push: they are left zero (no impulse, no arm, no
  // response), which spares two thirds of the setup and of each pass. The exact solve holds such rows at
  // their zero bound.
  const bool with_friction = c->friction > 0.0f;
  c->friction_rows_pending = with_friction && !point_friction_rows;
  c->reports = constraint.reports;
  const int axis_count = with_friction && point_friction_rows ? 3 : 1;
  for (int i = 0; i < count; ++i) {
    const ContactConstraintPoint& point = constraint.points()[i];
    SolverContactPoint& p = *new (&c->points()[i]) SolverContactPoint;
    float masses[3] = {0.0f, 0.0f, 0.0f};
    SetupPointRows(constraint, point, bodies, axes, 0, axis_count, p, masses);
    for (int axis = axis_count; axis < 3; ++axis)
      p.angular_a[axis] = p.angular_b[axis] = p.response_a[axis] = p.response_b[axis] = Vec4::Zero();
    p.normal_mass = masses[kNormal];
    p.tangent_mass = std::min(masses[kFirstTangent], masses[kSecondTangent]);
    p.separation = point.separation;
    p.normal_velocity = point.normal_velocity;
    p.max_normal_impulse = 0.0f;
    p.normal_impulse = point.warm_normal;
    p.tangent_impulse[0] = with_friction ? point.warm_friction.dot(ToVec3(c->tangent[0])) : 0.0f;
    p.tangent_impulse[1] = with_friction ? point.warm_friction.dot(ToVec3(c->tangent[1])) : 0.0f;
  }
  return c;
}

void SetupPendingFrictionRows(SolverContact& c, const SolverBody* bodies) {
  if (!c.friction_rows_pending) return;
  c.friction_rows_pending = false;
  const Vec4 axes[3] = {c.normal, c.tangent[0], c.tangent[1]};
  for (int i = 0; i < c.point_count; ++i) {
    SolverContactPoint& p = c.points()[i];
    float masses[3] = {0.0f, 0.0f, 0.0f};
    SetupPointRows(*c.constraint, c.constraint->points()[i], bodies, axes, kFirstTangent, 3, p, masses);
    p.tangent_mass = std::min(masses[kFirstTangent], masses[kSecondTangent]);
  }
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

void SolveContactVelocity(SolverContact& c, SolverBody* bodies, const SubstepContext& context, bool use_bias,
                          bool reverse, float* deepest) {
  const ContactConstraint& constraint = *c.constraint;
  if (constraint.dynamic_a && constraint.dynamic_b)
    SolveVelocity<true, true>(c, bodies, context, use_bias, reverse, deepest);
  else if (constraint.dynamic_a)
    SolveVelocity<true, false>(c, bodies, context, use_bias, reverse, deepest);
  else if (constraint.dynamic_b)
    SolveVelocity<false, true>(c, bodies, context, use_bias, reverse, deepest);
}

void ApplyContactRestitution(SolverContact& c, SolverBody* bodies, const SubstepContext& context) {
  const ContactConstraint& constraint = *c.constraint;
  if (c.restitution <= 0.0f) return;
  if (constraint.dynamic_a && constraint.dynamic_b)
    Restitution<true, true>(c, bodies, context);
  else if (constraint.dynamic_a)
    Restitution<true, false>(c, bodies, context);
  else if (constraint.dynamic_b)
    Restitution<false, true>(c, bodies, context);
}

void StoreContactImpulses(const SolverContact& c) {
  CachedContactPoint* cached = c.constraint->cache->points();
  for (int i = 0; i < c.point_count; ++i) {
    const SolverContactPoint& p = c.points()[i];
    cached[i].normal_impulse = p.normal_impulse;
    cached[i].friction_impulse =
        ToVec3(p.tangent_impulse[0] * c.tangent[0] + p.tangent_impulse[1] * c.tangent[1]);
  }
  if (c.reports) AddReportedImpulses(c);
}

void AddReportedImpulses(const SolverContact& c) {
  float* sums = c.constraint->cache->reported_impulses(c.point_count);
  for (int i = 0; i < c.point_count; ++i) sums[i] += c.points()[i].normal_impulse;
}

}  // namespace strata
