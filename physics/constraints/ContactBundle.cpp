#include "physics/constraints/ContactBundle.h"

#include <algorithm>
#include <bit>
#include <new>

namespace strata {

namespace {

constexpr int kLanes = ContactBundle::kLanes;
constexpr int kNormal = 0;
constexpr int kFirstTangent = 1;
constexpr int kSecondTangent = 2;

// Lane-by-lane staging in plain float arrays: setup, gathers and scatters go through these, and only whole
// WideFloat values are loaded from and stored to the bundle.
using Lanes = float[kLanes];
struct alignas(alignof(WideFloat)) Lanes3 {
  Lanes x, y, z;
  void Set(int lane, const Vec3& v) {
    x[lane] = v.x();
    y[lane] = v.y();
    z[lane] = v.z();
  }
  WideVec3 Load() const { return {WideFloat::Load(x), WideFloat::Load(y), WideFloat::Load(z)}; }
};

// The bodies' inverse inertias, one per lane (symmetric: six entries).
WideSymmetric3 GatherInertia(const SolverBody* bodies, const std::uint32_t* index) {
  alignas(alignof(WideFloat)) float entries[6][kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    const Vec4* columns = bodies[index[lane]].inverse_inertia;
    entries[0][lane] = columns[0].x(), entries[1][lane] = columns[1].x(), entries[2][lane] = columns[2].x();
    entries[3][lane] = columns[1].y(), entries[4][lane] = columns[2].y(), entries[5][lane] = columns[2].z();
  }
  return {WideFloat::Load(entries[0]), WideFloat::Load(entries[1]), WideFloat::Load(entries[2]),
          WideFloat::Load(entries[3]), WideFloat::Load(entries[4]), WideFloat::Load(entries[5])};
}

void GatherVelocities(const SolverBody* bodies, const std::uint32_t* index, WideVec3& linear,
                      WideVec3& angular) {
  const float* linear_rows[kLanes];
  const float* angular_rows[kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    linear_rows[lane] = bodies[index[lane]].linear_velocity.data();
    angular_rows[lane] = bodies[index[lane]].angular_velocity.data();
  }
  WideFloat unused;
  GatherRows(linear_rows, linear.x, linear.y, linear.z, unused);
  GatherRows(angular_rows, angular.x, angular.y, angular.z, unused);
}

// Only dynamic sides are written back: the fixed body and kinematic bodies may sit in several lanes.
void ScatterVelocities(SolverBody* bodies, const std::uint32_t* index, const bool* dynamic,
                       const WideVec3& linear, const WideVec3& angular) {
  float* linear_rows[kLanes];
  float* angular_rows[kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    linear_rows[lane] = dynamic[lane] ? bodies[index[lane]].linear_velocity.data() : nullptr;
    angular_rows[lane] = dynamic[lane] ? bodies[index[lane]].angular_velocity.data() : nullptr;
  }
  ScatterRows(linear_rows, linear.x, linear.y, linear.z, WideFloat::Zero());
  ScatterRows(angular_rows, angular.x, angular.y, angular.z, WideFloat::Zero());
}

// Each lane's motion since the step began: the solver body's deltas where the solver moves it, else its
// velocity times `elapsed` (kinematic bodies move at their velocity; the fixed body has none).
void GatherMotion(const SolverBody* bodies, const std::uint32_t* index, WideFloat moving,
                  const WideVec3& velocity, const WideVec3& spin, WideFloat elapsed, WideVec3& moved,
                  WideVec3& turned) {
  const float* position_rows[kLanes];
  const float* rotation_rows[kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    position_rows[lane] = bodies[index[lane]].delta_position.data();
    rotation_rows[lane] = bodies[index[lane]].delta_rotation.data();
  }
  WideFloat unused;
  GatherRows(position_rows, moved.x, moved.y, moved.z, unused);
  GatherRows(rotation_rows, turned.x, turned.y, turned.z, unused);
  const WideVec3 carried = elapsed * velocity, carried_turn = elapsed * spin;
  moved = {Select(moving, moved.x, carried.x), Select(moving, moved.y, carried.y),
           Select(moving, moved.z, carried.z)};
  turned = {Select(moving, turned.x, carried_turn.x), Select(moving, turned.y, carried_turn.y),
            Select(moving, turned.z, carried_turn.z)};
}

WideFloat SafeInverse(WideFloat k) {
  return Select(Greater(k, WideFloat::Zero()), WideFloat(1.0f) / Max(k, WideFloat(1e-30f)),
                WideFloat::Zero());
}

}  // namespace

ContactBundle* AllocateBundle(BlockArena& arena, std::span<ContactConstraint* const> constraints) {
  std::uint32_t points = 0;
  bool reports = false;
  for (const ContactConstraint* c : constraints) {
    points = std::max<std::uint32_t>(points, c->point_count);
    reports = reports || c->reports;
  }
  const std::size_t bytes = sizeof(ContactBundle) + points * sizeof(ContactBundleRows);
  auto* bundle = new (arena.Allocate(bytes, alignof(ContactBundle))) ContactBundle;
  bundle->point_count = points;
  bundle->reports = reports;
  bundle->fixed_b = true;
  bundle->reported_impulses = nullptr;
  for (int lane = 0; lane < kLanes; ++lane) {
    const bool used = lane < static_cast<int>(constraints.size());
    ContactConstraint* c = used ? constraints[lane] : nullptr;
    bundle->constraints[lane] = c;
    bundle->body_a[lane] = c ? c->body_a : 0;
    bundle->body_b[lane] = c ? c->body_b : 0;
    bundle->dynamic_a[lane] = c && c->dynamic_a;
    bundle->dynamic_b[lane] = c && c->dynamic_b;
    bundle->fixed_b = bundle->fixed_b && bundle->body_b[lane] == 0;
  }
  return bundle;
}

void AllocateReportedImpulses(BlockArena& arena, ContactBundle& bundle) {
  // A cache line of its own: neighbouring bundles are solved on other threads.
  constexpr std::size_t kCacheLine = 64;
  if (bundle.reports)
    bundle.reported_impulses =
        static_cast<WideFloat*>(arena.Allocate(std::max(kCacheLine, bundle.point_count * sizeof(WideFloat)),
                                               std::max(kCacheLine, alignof(WideFloat))));
}

void SetupBundle(ContactBundle& bundle, const SolverBody* bodies, const SubstepContext& context) {
  Lanes3 normal{}, first_tangent{}, second_tangent{};
  alignas(alignof(WideFloat)) Lanes friction{}, restitution{}, inverse_mass_a{}, inverse_mass_b{};
  alignas(alignof(WideFloat)) Lanes bias_rate{}, mass_scale{}, impulse_scale{}, moving_a{}, moving_b{};
  constexpr float kAllSet = std::bit_cast<float>(0xffffffffu);
  for (int lane = 0; lane < kLanes; ++lane) {
    const ContactConstraint* c = bundle.constraints[lane];
    if (c == nullptr) continue;
    const Vec3 tangent = AnyPerpendicular(c->normal);
    normal.Set(lane, c->normal);
    first_tangent.Set(lane, tangent);
    second_tangent.Set(lane, c->normal.cross(tangent));
    friction[lane] = c->friction;
    restitution[lane] = c->restitution;
    inverse_mass_a[lane] = bodies[c->body_a].inverse_mass;
    inverse_mass_b[lane] = bodies[c->body_b].inverse_mass;
    const Softness soft =
        SoftnessFor(c->dynamic_a && c->dynamic_b ? context.between_moving : context.against_fixed,
                    inverse_mass_a[lane], inverse_mass_b[lane]);
    bias_rate[lane] = soft.bias_rate;
    mass_scale[lane] = soft.mass_scale;
    impulse_scale[lane] = soft.impulse_scale;
    moving_a[lane] = c->dynamic_a ? kAllSet : 0.0f;
    moving_b[lane] = c->dynamic_b ? kAllSet : 0.0f;
  }
  bundle.normal = normal.Load();
  bundle.tangent[0] = first_tangent.Load();
  bundle.tangent[1] = second_tangent.Load();
  bundle.friction = WideFloat::Load(friction);
  bundle.restitution = WideFloat::Load(restitution);
  bundle.inverse_mass_a = WideFloat::Load(inverse_mass_a);
  bundle.inverse_mass_b = WideFloat::Load(inverse_mass_b);
  bundle.inverse_inertia_a = GatherInertia(bodies, bundle.body_a);
  bundle.inverse_inertia_b = bundle.fixed_b ? WideSymmetric3::Zero() : GatherInertia(bodies, bundle.body_b);
  bundle.bias_rate = WideFloat::Load(bias_rate);
  bundle.mass_scale = WideFloat::Load(mass_scale);
  bundle.impulse_scale = WideFloat::Load(impulse_scale);
  bundle.moving_a = WideFloat::Load(moving_a);
  bundle.moving_b = WideFloat::Load(moving_b);
  const WideVec3 axes[3] = {bundle.normal, bundle.tangent[0], bundle.tangent[1]};
  const WideFloat inverse_masses = bundle.inverse_mass_a + bundle.inverse_mass_b;

  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    Lanes3 r_a{}, r_b{}, warm_friction{};
    alignas(alignof(WideFloat)) Lanes warm_normal{}, separation{}, normal_velocity{};
    for (int lane = 0; lane < kLanes; ++lane) {
      const ContactConstraint* c = bundle.constraints[lane];
      separation[lane] = kLargeFloat;  // an absent point never pushes
      if (c == nullptr || j >= c->point_count) continue;
      const ContactConstraintPoint& p = c->points()[j];
      r_a.Set(lane, p.r_a);
      r_b.Set(lane, p.r_b);
      warm_friction.Set(lane, p.warm_friction);
      warm_normal[lane] = p.warm_normal;
      separation[lane] = p.separation;
      normal_velocity[lane] = p.normal_velocity;
    }
    ContactBundleRows& rows = *new (&bundle.rows()[j]) ContactBundleRows;
    rows.arm_a = r_a.Load();
    rows.arm_b = r_b.Load();
    WideFloat masses[3];
    for (int axis = 0; axis < 3; ++axis) {
      const WideVec3 angular_a = Cross(rows.arm_a, axes[axis]);
      WideFloat k = inverse_masses + Dot(angular_a, bundle.inverse_inertia_a.Times(angular_a));
      if (!bundle.fixed_b) {
        const WideVec3 angular_b = Cross(rows.arm_b, axes[axis]);
        k = k + Dot(angular_b, bundle.inverse_inertia_b.Times(angular_b));
      }
      masses[axis] = SafeInverse(k);
    }
    // An absent point has zero arms and masses, so it changes nothing in its lane.
    rows.normal_mass = masses[kNormal];
    rows.tangent_mass = Min(masses[kFirstTangent], masses[kSecondTangent]);
    rows.separation = WideFloat::Load(separation);
    rows.normal_velocity = WideFloat::Load(normal_velocity);
    rows.normal_impulse = WideFloat::Load(warm_normal);
    const WideVec3 warm = warm_friction.Load();
    rows.tangent_impulse[0] = Dot(warm, bundle.tangent[0]);
    rows.tangent_impulse[1] = Dot(warm, bundle.tangent[1]);
    rows.max_normal_impulse = WideFloat::Zero();
    if (bundle.reports) bundle.reported_impulses[j] = WideFloat::Zero();
  }
}

namespace {

// The velocities of the bundle's bodies, one per lane, and how an impulse changes them. With kFixedB every
// lane's B is the fixed body: it has no velocity and takes no impulse, so its side is left out.
template <bool kFixedB>
struct LaneBodies {
  WideVec3 va, wa, vb, wb;

  LaneBodies(const SolverBody* bodies, const ContactBundle& bundle) {
    GatherVelocities(bodies, bundle.body_a, va, wa);
    if constexpr (kFixedB)
      vb = wb = WideVec3::Zero();
    else
      GatherVelocities(bodies, bundle.body_b, vb, wb);
  }
  void Scatter(SolverBody* bodies, const ContactBundle& bundle) const {
    ScatterVelocities(bodies, bundle.body_a, bundle.dynamic_a, va, wa);
    if constexpr (!kFixedB) ScatterVelocities(bodies, bundle.body_b, bundle.dynamic_b, vb, wb);
  }
  /// Velocity of the point on B relative to the point on A.
  WideVec3 Relative(const ContactBundleRows& p) const {
    if constexpr (kFixedB)
      return WideVec3::Zero() - va - Cross(wa, p.arm_a);
    else
      return vb - va + Cross(wb, p.arm_b) - Cross(wa, p.arm_a);
  }
  /// Applies `impulse` (world) at the point: against A, along it on B.
  void Apply(const ContactBundle& bundle, const ContactBundleRows& p, const WideVec3& impulse) {
    va -= bundle.inverse_mass_a * impulse;
    wa -= bundle.inverse_inertia_a.Times(Cross(p.arm_a, impulse));
    if constexpr (!kFixedB) {
      vb += bundle.inverse_mass_b * impulse;
      wb += bundle.inverse_inertia_b.Times(Cross(p.arm_b, impulse));
    }
  }
};

// Accumulates `impulse` into the point's normal impulse (never pulling) and applies the change.
template <bool kFixedB>
void PushNormal(const ContactBundle& bundle, ContactBundleRows& p, LaneBodies<kFixedB>& lanes,
                WideFloat impulse) {
  const WideFloat old_impulse = p.normal_impulse;
  p.normal_impulse = Max(WideFloat::Zero(), old_impulse + impulse);
  const WideFloat applied = p.normal_impulse - old_impulse;
  p.max_normal_impulse = Max(p.max_normal_impulse, applied);
  lanes.Apply(bundle, p, applied * bundle.normal);
}

template <bool kFixedB>
void WarmStart(const ContactBundle& bundle, SolverBody* bodies) {
  LaneBodies<kFixedB> lanes(bodies, bundle);
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    const ContactBundleRows& p = bundle.rows()[j];
    lanes.Apply(
        bundle, p,
        MulAdd(p.normal_impulse, bundle.normal,
               MulAdd(p.tangent_impulse[0], bundle.tangent[0], p.tangent_impulse[1] * bundle.tangent[1])));
  }
  lanes.Scatter(bodies, bundle);
}

template <bool kFixedB>
void SolveVelocity(ContactBundle& bundle, SolverBody* bodies, const SubstepContext& context, bool use_bias,
                   bool reverse, float* deepest) {
  LaneBodies<kFixedB> lanes(bodies, bundle);
  const WideFloat elapsed(context.elapsed);
  WideVec3 moved_a, turned_a, moved_b = WideVec3::Zero(), turned_b = WideVec3::Zero();
  GatherMotion(bodies, bundle.body_a, bundle.moving_a, lanes.va, lanes.wa, elapsed, moved_a, turned_a);
  if constexpr (!kFixedB)
    GatherMotion(bodies, bundle.body_b, bundle.moving_b, lanes.vb, lanes.wb, elapsed, moved_b, turned_b);
  const WideFloat moved_apart = Dot(bundle.normal, moved_b - moved_a);
  const int count = static_cast<int>(bundle.point_count);
  ContactBundleRows* rows = bundle.rows();
  const WideFloat inverse_h(context.inverse_h);
  const WideFloat max_push(-context.max_push_velocity);
  WideFloat lowest(kLargeFloat);
  for (int k = 0; k < count; ++k) {
    ContactBundleRows& p = rows[reverse ? count - 1 - k : k];
    // Separation now: at the start of the step plus how the bodies moved and turned since (first order).
    WideFloat separation = p.separation + moved_apart;
    if constexpr (!kFixedB) separation = separation + Dot(turned_b, Cross(p.arm_b, bundle.normal));
    separation = separation - Dot(turned_a, Cross(p.arm_a, bundle.normal));
    lowest = Min(lowest, separation);
    const WideFloat gap = Greater(separation, WideFloat::Zero());
    // A gap may close within this substep and no further; overlap is pushed out softly.
    WideFloat bias = Max(separation, WideFloat::Zero()) * inverse_h;
    WideFloat mass_scale(1.0f), impulse_scale = WideFloat::Zero();
    if (use_bias) {
      bias = Select(gap, bias, Max(bundle.bias_rate * separation, max_push));
      mass_scale = Select(gap, mass_scale, bundle.mass_scale);
      impulse_scale = Select(gap, impulse_scale, bundle.impulse_scale);
    }
    const WideFloat velocity = Dot(bundle.normal, lanes.Relative(p));
    PushNormal(bundle, p, lanes,
               WideFloat::Zero() - p.normal_mass * mass_scale * (velocity + bias) -
                   impulse_scale * p.normal_impulse);
  }
  // Friction after non-penetration, bounded by the normal impulse just solved (see ContactSolver).
  for (int k = 0; k < count; ++k) {
    ContactBundleRows& p = rows[reverse ? count - 1 - k : k];
    const WideFloat limit = bundle.friction * p.normal_impulse;
    const WideVec3 relative = lanes.Relative(p);
    const WideFloat old_first = p.tangent_impulse[0], old_second = p.tangent_impulse[1];
    WideFloat first = old_first - p.tangent_mass * Dot(bundle.tangent[0], relative);
    WideFloat second = old_second - p.tangent_mass * Dot(bundle.tangent[1], relative);
    const WideFloat length2 = MulAdd(first, first, second * second);
    const WideFloat scale = Select(Greater(length2, limit * limit),
                                   limit / Sqrt(Max(length2, WideFloat(1e-30f))), WideFloat(1.0f));
    first = first * scale;
    second = second * scale;
    p.tangent_impulse[0] = first;
    p.tangent_impulse[1] = second;
    lanes.Apply(bundle, p,
                MulAdd(first - old_first, bundle.tangent[0], (second - old_second) * bundle.tangent[1]));
  }
  lanes.Scatter(bodies, bundle);
  if (deepest == nullptr) return;
  alignas(alignof(WideFloat)) Lanes lanes_lowest;
  lowest.Store(lanes_lowest);
  *deepest = std::min(*deepest, *std::min_element(lanes_lowest, lanes_lowest + kLanes));
}

template <bool kFixedB>
void ApplyRestitution(ContactBundle& bundle, SolverBody* bodies, const SubstepContext& context) {
  LaneBodies<kFixedB> lanes(bodies, bundle);
  const WideFloat threshold(-context.restitution_threshold);
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    ContactBundleRows& p = bundle.rows()[j];
    // Bounce only where the approach was fast and the contact did push (a speculative gap that stayed open
    // must not bounce).
    const WideFloat pushed = Greater(p.max_normal_impulse, WideFloat::Zero());
    const WideFloat fast = Greater(threshold, p.normal_velocity);
    const WideFloat bounces =
        Select(pushed, Select(fast, Greater(bundle.restitution, WideFloat::Zero()), WideFloat::Zero()),
               WideFloat::Zero());
    const WideFloat velocity = Dot(bundle.normal, lanes.Relative(p));
    const WideFloat impulse =
        WideFloat::Zero() - p.normal_mass * MulAdd(bundle.restitution, p.normal_velocity, velocity);
    PushNormal(bundle, p, lanes, Select(bounces, impulse, WideFloat::Zero()));
  }
  lanes.Scatter(bodies, bundle);
}

}  // namespace

void WarmStartBundle(const ContactBundle& bundle, SolverBody* bodies) {
  if (bundle.fixed_b)
    WarmStart<true>(bundle, bodies);
  else
    WarmStart<false>(bundle, bodies);
}

void SolveBundleVelocity(ContactBundle& bundle, SolverBody* bodies, const SubstepContext& context,
                         bool use_bias, bool reverse, float* deepest) {
  if (bundle.fixed_b)
    SolveVelocity<true>(bundle, bodies, context, use_bias, reverse, deepest);
  else
    SolveVelocity<false>(bundle, bodies, context, use_bias, reverse, deepest);
}

void ApplyBundleRestitution(ContactBundle& bundle, SolverBody* bodies, const SubstepContext& context) {
  if (bundle.fixed_b)
    ApplyRestitution<true>(bundle, bodies, context);
  else
    ApplyRestitution<false>(bundle, bodies, context);
}

void AddBundleReportedImpulses(ContactBundle& bundle) {
  WideFloat* sums = bundle.reported_impulses;
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) sums[j] = sums[j] + bundle.rows()[j].normal_impulse;
}

void StoreBundleImpulses(ContactBundle& bundle) {
  if (bundle.reports) AddBundleReportedImpulses(bundle);
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    const ContactBundleRows& p = bundle.rows()[j];
    const WideVec3 friction =
        MulAdd(p.tangent_impulse[0], bundle.tangent[0], p.tangent_impulse[1] * bundle.tangent[1]);
    Lanes3 staged;
    alignas(alignof(WideFloat)) Lanes normal, reported;
    friction.x.Store(staged.x), friction.y.Store(staged.y), friction.z.Store(staged.z);
    p.normal_impulse.Store(normal);
    // The reporting lanes' step sums go to their constraints' records in the same pass.
    if (bundle.reports) bundle.reported_impulses[j].Store(reported);
    for (int lane = 0; lane < kLanes; ++lane) {
      const ContactConstraint* c = bundle.constraints[lane];
      if (c == nullptr || j >= c->point_count) continue;
      CachedContactPoint& cached = c->cache->points()[j];
      cached.normal_impulse = normal[lane];
      cached.friction_impulse = Vec3(staged.x[lane], staged.y[lane], staged.z[lane]);
      if (c->reports) c->cache->reported_impulses(c->point_count)[j] = reported[lane];
    }
  }
}

}  // namespace strata
