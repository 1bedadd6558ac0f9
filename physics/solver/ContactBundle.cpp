#include "physics/solver/ContactBundle.h"

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

struct WideQuat {
  WideFloat w;
  WideVec3 v;
};

// v rotated by q: v + w t + v_q x t with t = 2 v_q x v.
WideVec3 Rotate(const WideQuat& q, const WideVec3& v) {
  const WideVec3 twice_cross = WideFloat(2.0f) * Cross(q.v, v);
  return v + q.w * twice_cross + Cross(q.v, twice_cross);
}

// Turns q by the small rotation vector `turn` (first order, renormalised), as ContactSolver does.
void Turn(WideQuat& q, const WideVec3& turn) {
  const WideVec3 half = WideFloat(0.5f) * turn;
  const WideFloat w = q.w - Dot(half, q.v);
  const WideVec3 v = q.v + q.w * half + Cross(half, q.v);
  const WideFloat inverse_length = WideFloat(1.0f) / Sqrt(MulAdd(w, w, Dot(v, v)));
  q.w = w * inverse_length;
  q.v = inverse_length * v;
}

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

void GatherPoses(const SolverPose* poses, const std::uint32_t* index, WideVec3& center, WideQuat& rotation) {
  const float* center_rows[kLanes];
  const float* rotation_rows[kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    center_rows[lane] = poses[index[lane]].center_of_mass.data();
    rotation_rows[lane] = poses[index[lane]].rotation.coeffs().data();  // x, y, z, w
  }
  WideFloat unused;
  GatherRows(center_rows, center.x, center.y, center.z, unused);
  GatherRows(rotation_rows, rotation.v.x, rotation.v.y, rotation.v.z, rotation.w);
}

void ScatterPoses(SolverPose* poses, const std::uint32_t* index, const bool* dynamic, const WideVec3& center,
                  const WideQuat& rotation) {
  float* center_rows[kLanes];
  float* rotation_rows[kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    center_rows[lane] = dynamic[lane] ? poses[index[lane]].center_of_mass.data() : nullptr;
    rotation_rows[lane] = dynamic[lane] ? poses[index[lane]].rotation.coeffs().data() : nullptr;
  }
  ScatterRows(center_rows, center.x, center.y, center.z, WideFloat::Zero());
  ScatterRows(rotation_rows, rotation.v.x, rotation.v.y, rotation.v.z, rotation.w);
}

WideFloat SafeInverse(WideFloat k) {
  return Select(Greater(k, WideFloat::Zero()), WideFloat(1.0f) / Max(k, WideFloat(1e-30f)),
                WideFloat::Zero());
}

}  // namespace

ContactBundle* AllocateBundle(BlockArena& arena, std::span<ContactConstraint* const> constraints) {
  std::uint32_t points = 0;
  for (const ContactConstraint* c : constraints) points = std::max<std::uint32_t>(points, c->point_count);
  const std::size_t bytes =
      sizeof(ContactBundle) + points * (sizeof(ContactBundleRows) + sizeof(ContactBundlePoints));
  auto* bundle = new (arena.Allocate(bytes, alignof(ContactBundle))) ContactBundle;
  bundle->point_count = points;
  for (int lane = 0; lane < kLanes; ++lane) {
    const bool used = lane < static_cast<int>(constraints.size());
    ContactConstraint* c = used ? constraints[lane] : nullptr;
    bundle->constraints[lane] = c;
    bundle->body_a[lane] = c ? c->body_a : 0;
    bundle->body_b[lane] = c ? c->body_b : 0;
    bundle->dynamic_a[lane] = c && c->dynamic_a;
    bundle->dynamic_b[lane] = c && c->dynamic_b;
  }
  return bundle;
}

void SetupBundle(ContactBundle& bundle, const SolverBody* bodies) {
  Lanes3 normal{}, first_tangent{}, second_tangent{};
  alignas(alignof(WideFloat)) Lanes friction{}, inverse_mass_a{}, inverse_mass_b{};
  for (int lane = 0; lane < kLanes; ++lane) {
    const ContactConstraint* c = bundle.constraints[lane];
    if (c == nullptr) continue;
    const Vec3 tangent = AnyPerpendicular(c->normal);
    normal.Set(lane, c->normal);
    first_tangent.Set(lane, tangent);
    second_tangent.Set(lane, c->normal.cross(tangent));
    friction[lane] = c->friction;
    inverse_mass_a[lane] = bodies[c->body_a].inverse_mass;
    inverse_mass_b[lane] = bodies[c->body_b].inverse_mass;
  }
  bundle.normal = normal.Load();
  bundle.tangent[0] = first_tangent.Load();
  bundle.tangent[1] = second_tangent.Load();
  bundle.friction = WideFloat::Load(friction);
  bundle.inverse_mass_a = WideFloat::Load(inverse_mass_a);
  bundle.inverse_mass_b = WideFloat::Load(inverse_mass_b);
  bundle.inverse_inertia_a = GatherInertia(bodies, bundle.body_a);
  bundle.inverse_inertia_b = GatherInertia(bodies, bundle.body_b);
  const WideVec3 axes[3] = {bundle.normal, bundle.tangent[0], bundle.tangent[1]};
  const WideFloat inverse_masses = bundle.inverse_mass_a + bundle.inverse_mass_b;

  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    Lanes3 r_a{}, r_b{}, local_a{}, local_b{}, warm_friction{};
    alignas(alignof(WideFloat)) Lanes warm_normal{}, target{}, present{};
    for (int lane = 0; lane < kLanes; ++lane) {
      const ContactConstraint* c = bundle.constraints[lane];
      if (c == nullptr || j >= c->point_count) continue;
      const ContactConstraintPoint& p = c->points()[j];
      r_a.Set(lane, p.r_a);
      r_b.Set(lane, p.r_b);
      local_a.Set(lane, p.local_a);
      local_b.Set(lane, p.local_b);
      warm_friction.Set(lane, p.warm_friction);
      warm_normal[lane] = p.warm_normal;
      target[lane] = p.target_velocity;
      present[lane] = std::bit_cast<float>(0xffffffffu);
    }
    ContactBundleRows& rows = *new (&bundle.rows()[j]) ContactBundleRows;
    rows.arm_a = r_a.Load();
    rows.arm_b = r_b.Load();
    WideFloat masses[3];
    for (int axis = 0; axis < 3; ++axis) {
      const WideVec3 angular_a = Cross(rows.arm_a, axes[axis]), angular_b = Cross(rows.arm_b, axes[axis]);
      masses[axis] = SafeInverse(inverse_masses + Dot(angular_a, bundle.inverse_inertia_a.Times(angular_a)) +
                                 Dot(angular_b, bundle.inverse_inertia_b.Times(angular_b)));
    }
    // An absent point has zero arms and masses, so it changes nothing in its lane.
    rows.normal_mass = masses[kNormal];
    rows.tangent_mass = Min(masses[kFirstTangent], masses[kSecondTangent]);
    rows.target_velocity = WideFloat::Load(target);
    rows.normal_impulse = WideFloat::Load(warm_normal);
    const WideVec3 warm = warm_friction.Load();
    rows.tangent_impulse[0] = Dot(warm, bundle.tangent[0]);
    rows.tangent_impulse[1] = Dot(warm, bundle.tangent[1]);
    ContactBundlePoints& points = *new (&bundle.points()[j]) ContactBundlePoints;
    points.local_a = local_a.Load();
    points.local_b = local_b.Load();
    points.present = WideFloat::Load(present);
  }
}

namespace {

// The velocities of the bundle's bodies, one per lane, and how an impulse changes them.
struct LaneBodies {
  WideVec3 va, wa, vb, wb;

  LaneBodies(const SolverBody* bodies, const ContactBundle& bundle) {
    GatherVelocities(bodies, bundle.body_a, va, wa);
    GatherVelocities(bodies, bundle.body_b, vb, wb);
  }
  void Scatter(SolverBody* bodies, const ContactBundle& bundle) const {
    ScatterVelocities(bodies, bundle.body_a, bundle.dynamic_a, va, wa);
    ScatterVelocities(bodies, bundle.body_b, bundle.dynamic_b, vb, wb);
  }
  /// Velocity of the point on B relative to the point on A.
  WideVec3 Relative(const ContactBundleRows& p) const {
    return vb - va + Cross(wb, p.arm_b) - Cross(wa, p.arm_a);
  }
  /// Applies `impulse` (world) at the point: against A, along it on B.
  void Apply(const ContactBundle& bundle, const ContactBundleRows& p, const WideVec3& impulse) {
    va -= bundle.inverse_mass_a * impulse;
    wa -= bundle.inverse_inertia_a.Times(Cross(p.arm_a, impulse));
    vb += bundle.inverse_mass_b * impulse;
    wb += bundle.inverse_inertia_b.Times(Cross(p.arm_b, impulse));
  }
};

}  // namespace

void WarmStartBundle(ContactBundle& bundle, SolverBody* bodies) {
  LaneBodies lanes(bodies, bundle);
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    const ContactBundleRows& p = bundle.rows()[j];
    lanes.Apply(
        bundle, p,
        MulAdd(p.normal_impulse, bundle.normal,
               MulAdd(p.tangent_impulse[0], bundle.tangent[0], p.tangent_impulse[1] * bundle.tangent[1])));
  }
  lanes.Scatter(bodies, bundle);
}

void SolveBundleVelocity(ContactBundle& bundle, SolverBody* bodies, bool reverse) {
  LaneBodies lanes(bodies, bundle);
  const int count = static_cast<int>(bundle.point_count);
  ContactBundleRows* rows = bundle.rows();
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
  for (int k = 0; k < count; ++k) {
    ContactBundleRows& p = rows[reverse ? count - 1 - k : k];
    const WideFloat velocity = Dot(bundle.normal, lanes.Relative(p));
    const WideFloat old_impulse = p.normal_impulse;
    p.normal_impulse = Max(WideFloat::Zero(), old_impulse - (velocity - p.target_velocity) * p.normal_mass);
    lanes.Apply(bundle, p, (p.normal_impulse - old_impulse) * bundle.normal);
  }
  lanes.Scatter(bodies, bundle);
}

void StoreBundleImpulses(const ContactBundle& bundle) {
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    const ContactBundleRows& p = bundle.rows()[j];
    const WideVec3 friction =
        MulAdd(p.tangent_impulse[0], bundle.tangent[0], p.tangent_impulse[1] * bundle.tangent[1]);
    Lanes3 staged;
    alignas(alignof(WideFloat)) Lanes normal;
    friction.x.Store(staged.x), friction.y.Store(staged.y), friction.z.Store(staged.z);
    p.normal_impulse.Store(normal);
    for (int lane = 0; lane < kLanes; ++lane) {
      const ContactConstraint* c = bundle.constraints[lane];
      if (c == nullptr || j >= c->point_count) continue;
      CachedContactPoint& cached = c->cache->points()[j];
      cached.normal_impulse = normal[lane];
      cached.friction_impulse = Vec3(staged.x[lane], staged.y[lane], staged.z[lane]);
    }
  }
}

float SolveBundlePosition(const ContactBundle& bundle, SolverPose* poses, const PhysicsSettings& settings) {
  WideVec3 center_a, center_b;
  WideQuat rotation_a, rotation_b;
  GatherPoses(poses, bundle.body_a, center_a, rotation_a);
  GatherPoses(poses, bundle.body_b, center_b, rotation_b);
  const WideSymmetric3& inertia_a = bundle.inverse_inertia_a;
  const WideSymmetric3& inertia_b = bundle.inverse_inertia_b;
  const WideFloat baumgarte(settings.baumgarte), slop(settings.penetration_slop);
  const WideFloat max_correction(-settings.max_position_correction);
  const WideFloat inverse_masses = bundle.inverse_mass_a + bundle.inverse_mass_b;
  WideFloat deepest = WideFloat::Zero();
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    const ContactBundlePoints& p = bundle.points()[j];
    const WideVec3 r_a = Rotate(rotation_a, p.local_a);
    const WideVec3 r_b = Rotate(rotation_b, p.local_b);
    const WideFloat separation = Dot(center_b + r_b - center_a - r_a, bundle.normal);
    deepest = Select(p.present, Min(deepest, separation), deepest);
    const WideFloat correction =
        Select(p.present, Min(Max(baumgarte * (separation + slop), max_correction), WideFloat::Zero()),
               WideFloat::Zero());
    const WideVec3 angular_a = Cross(r_a, bundle.normal), angular_b = Cross(r_b, bundle.normal);
    const WideVec3 response_a = inertia_a.Times(angular_a), response_b = inertia_b.Times(angular_b);
    // A pseudo-impulse along the normal moves and turns the bodies apart by the correction (0 where none).
    const WideFloat impulse =
        (WideFloat::Zero() - correction) *
        SafeInverse(inverse_masses + Dot(angular_a, response_a) + Dot(angular_b, response_b));
    center_a -= (bundle.inverse_mass_a * impulse) * bundle.normal;
    Turn(rotation_a, (WideFloat::Zero() - impulse) * response_a);
    center_b += (bundle.inverse_mass_b * impulse) * bundle.normal;
    Turn(rotation_b, impulse * response_b);
  }
  ScatterPoses(poses, bundle.body_a, bundle.dynamic_a, center_a, rotation_a);
  ScatterPoses(poses, bundle.body_b, bundle.dynamic_b, center_b, rotation_b);
  alignas(alignof(WideFloat)) Lanes lanes;
  deepest.Store(lanes);
  return *std::min_element(lanes, lanes + kLanes);
}

}  // namespace strata
