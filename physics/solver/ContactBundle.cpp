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

// The inverse inertia of one body per lane, by matrix entry.
struct WideInertia {
  WideFloat m[3][3];
  WideVec3 Times(const WideVec3& v) const {
    return {MulAdd(m[0][0], v.x, MulAdd(m[0][1], v.y, m[0][2] * v.z)),
            MulAdd(m[1][0], v.x, MulAdd(m[1][1], v.y, m[1][2] * v.z)),
            MulAdd(m[2][0], v.x, MulAdd(m[2][1], v.y, m[2][2] * v.z))};
  }
};

WideInertia GatherInertia(const SolverBody* bodies, const std::uint32_t* index) {
  alignas(alignof(WideFloat)) float entries[3][3][kLanes];
  for (int lane = 0; lane < kLanes; ++lane) {
    const SolverBody& body = bodies[index[lane]];
    for (int column = 0; column < 3; ++column)
      for (int row = 0; row < 3; ++row) entries[row][column][lane] = body.inverse_inertia[column][row];
  }
  WideInertia inertia;
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 3; ++column) inertia.m[row][column] = WideFloat::Load(entries[row][column]);
  return inertia;
}

void GatherVelocities(const SolverBody* bodies, const std::uint32_t* index, WideVec3& linear,
                      WideVec3& angular) {
  Lanes3 v, w;
  for (int lane = 0; lane < kLanes; ++lane) {
    const SolverBody& body = bodies[index[lane]];
    v.x[lane] = body.linear_velocity.x();
    v.y[lane] = body.linear_velocity.y();
    v.z[lane] = body.linear_velocity.z();
    w.x[lane] = body.angular_velocity.x();
    w.y[lane] = body.angular_velocity.y();
    w.z[lane] = body.angular_velocity.z();
  }
  linear = v.Load();
  angular = w.Load();
}

// Only dynamic sides are written back: the fixed body and kinematic bodies may sit in several lanes.
void ScatterVelocities(SolverBody* bodies, const std::uint32_t* index, const bool* dynamic,
                       const WideVec3& linear, const WideVec3& angular) {
  Lanes3 v, w;
  linear.x.Store(v.x), linear.y.Store(v.y), linear.z.Store(v.z);
  angular.x.Store(w.x), angular.y.Store(w.y), angular.z.Store(w.z);
  for (int lane = 0; lane < kLanes; ++lane) {
    if (!dynamic[lane]) continue;
    SolverBody& body = bodies[index[lane]];
    body.linear_velocity = Vec4(v.x[lane], v.y[lane], v.z[lane], 0.0f);
    body.angular_velocity = Vec4(w.x[lane], w.y[lane], w.z[lane], 0.0f);
  }
}

void GatherPoses(const SolverPose* poses, const std::uint32_t* index, WideVec3& center, WideQuat& rotation) {
  Lanes3 c, v;
  alignas(alignof(WideFloat)) Lanes w;
  for (int lane = 0; lane < kLanes; ++lane) {
    const SolverPose& pose = poses[index[lane]];
    c.x[lane] = pose.center_of_mass.x();
    c.y[lane] = pose.center_of_mass.y();
    c.z[lane] = pose.center_of_mass.z();
    w[lane] = pose.rotation.w();
    v.x[lane] = pose.rotation.x();
    v.y[lane] = pose.rotation.y();
    v.z[lane] = pose.rotation.z();
  }
  center = c.Load();
  rotation.w = WideFloat::Load(w);
  rotation.v = v.Load();
}

void ScatterPoses(SolverPose* poses, const std::uint32_t* index, const bool* dynamic, const WideVec3& center,
                  const WideQuat& rotation) {
  Lanes3 c, v;
  alignas(alignof(WideFloat)) Lanes w;
  center.x.Store(c.x), center.y.Store(c.y), center.z.Store(c.z);
  rotation.w.Store(w);
  rotation.v.x.Store(v.x), rotation.v.y.Store(v.y), rotation.v.z.Store(v.z);
  for (int lane = 0; lane < kLanes; ++lane) {
    if (!dynamic[lane]) continue;
    SolverPose& pose = poses[index[lane]];
    pose.center_of_mass = Vec4(c.x[lane], c.y[lane], c.z[lane], 0.0f);
    pose.rotation = Quat(w[lane], v.x[lane], v.y[lane], v.z[lane]);
  }
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
  const WideInertia inertia_a = GatherInertia(bodies, bundle.body_a);
  const WideInertia inertia_b = GatherInertia(bodies, bundle.body_b);
  const WideVec3 axes[3] = {bundle.normal, bundle.tangent[0], bundle.tangent[1]};
  const WideFloat inverse_masses = bundle.inverse_mass_a + bundle.inverse_mass_b;

  const std::uint32_t all_bits = 0xffffffffu;
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
      present[lane] = std::bit_cast<float>(all_bits);
    }
    ContactBundleRows& rows = *new (&bundle.rows()[j]) ContactBundleRows;
    const WideVec3 arm_a = r_a.Load(), arm_b = r_b.Load();
    WideFloat masses[3];
    for (int axis = 0; axis < 3; ++axis) {
      rows.angular_a[axis] = Cross(arm_a, axes[axis]);
      rows.angular_b[axis] = Cross(arm_b, axes[axis]);
      rows.response_a[axis] = inertia_a.Times(rows.angular_a[axis]);
      rows.response_b[axis] = inertia_b.Times(rows.angular_b[axis]);
      masses[axis] = SafeInverse(inverse_masses + Dot(rows.angular_a[axis], rows.response_a[axis]) +
                                 Dot(rows.angular_b[axis], rows.response_b[axis]));
    }
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

void WarmStartBundle(ContactBundle& bundle, SolverBody* bodies) {
  WideVec3 va, wa, vb, wb;
  GatherVelocities(bodies, bundle.body_a, va, wa);
  GatherVelocities(bodies, bundle.body_b, vb, wb);
  for (std::uint32_t j = 0; j < bundle.point_count; ++j) {
    const ContactBundleRows& p = bundle.rows()[j];
    const WideVec3 impulse =
        MulAdd(p.normal_impulse, bundle.normal,
               MulAdd(p.tangent_impulse[0], bundle.tangent[0], p.tangent_impulse[1] * bundle.tangent[1]));
    va -= bundle.inverse_mass_a * impulse;
    wa -= MulAdd(p.normal_impulse, p.response_a[kNormal],
                 MulAdd(p.tangent_impulse[0], p.response_a[kFirstTangent],
                        p.tangent_impulse[1] * p.response_a[kSecondTangent]));
    vb += bundle.inverse_mass_b * impulse;
    wb += MulAdd(p.normal_impulse, p.response_b[kNormal],
                 MulAdd(p.tangent_impulse[0], p.response_b[kFirstTangent],
                        p.tangent_impulse[1] * p.response_b[kSecondTangent]));
  }
  ScatterVelocities(bodies, bundle.body_a, bundle.dynamic_a, va, wa);
  ScatterVelocities(bodies, bundle.body_b, bundle.dynamic_b, vb, wb);
}

void SolveBundleVelocity(ContactBundle& bundle, SolverBody* bodies, bool reverse) {
  WideVec3 va, wa, vb, wb;
  GatherVelocities(bodies, bundle.body_a, va, wa);
  GatherVelocities(bodies, bundle.body_b, vb, wb);
  const WideFloat inverse_mass_a = bundle.inverse_mass_a, inverse_mass_b = bundle.inverse_mass_b;
  const int count = static_cast<int>(bundle.point_count);
  ContactBundleRows* rows = bundle.rows();
  // A lane without point j has zero rows and masses there, so the point changes nothing in that lane.
  for (int k = 0; k < count; ++k) {
    ContactBundleRows& p = rows[reverse ? count - 1 - k : k];
    const WideFloat limit = bundle.friction * p.normal_impulse;
    const WideVec3 relative = vb - va;
    const WideFloat first_velocity = Dot(bundle.tangent[0], relative) + Dot(p.angular_b[kFirstTangent], wb) -
                                     Dot(p.angular_a[kFirstTangent], wa);
    const WideFloat second_velocity = Dot(bundle.tangent[1], relative) +
                                      Dot(p.angular_b[kSecondTangent], wb) -
                                      Dot(p.angular_a[kSecondTangent], wa);
    const WideFloat old_first = p.tangent_impulse[0], old_second = p.tangent_impulse[1];
    WideFloat first = old_first - p.tangent_mass * first_velocity;
    WideFloat second = old_second - p.tangent_mass * second_velocity;
    const WideFloat length2 = MulAdd(first, first, second * second);
    const WideFloat scale = Select(Greater(length2, limit * limit),
                                   limit / Sqrt(Max(length2, WideFloat(1e-30f))), WideFloat(1.0f));
    first = first * scale;
    second = second * scale;
    p.tangent_impulse[0] = first;
    p.tangent_impulse[1] = second;
    const WideFloat delta_first = first - old_first, delta_second = second - old_second;
    const WideVec3 impulse = MulAdd(delta_first, bundle.tangent[0], delta_second * bundle.tangent[1]);
    va -= inverse_mass_a * impulse;
    wa -= MulAdd(delta_first, p.response_a[kFirstTangent], delta_second * p.response_a[kSecondTangent]);
    vb += inverse_mass_b * impulse;
    wb += MulAdd(delta_first, p.response_b[kFirstTangent], delta_second * p.response_b[kSecondTangent]);
  }
  for (int k = 0; k < count; ++k) {
    ContactBundleRows& p = rows[reverse ? count - 1 - k : k];
    const WideFloat velocity =
        Dot(bundle.normal, vb - va) + Dot(p.angular_b[kNormal], wb) - Dot(p.angular_a[kNormal], wa);
    const WideFloat old_impulse = p.normal_impulse;
    p.normal_impulse = Max(WideFloat::Zero(), old_impulse - (velocity - p.target_velocity) * p.normal_mass);
    const WideFloat delta = p.normal_impulse - old_impulse;
    va -= (inverse_mass_a * delta) * bundle.normal;
    wa -= delta * p.response_a[kNormal];
    vb += (inverse_mass_b * delta) * bundle.normal;
    wb += delta * p.response_b[kNormal];
  }
  ScatterVelocities(bodies, bundle.body_a, bundle.dynamic_a, va, wa);
  ScatterVelocities(bodies, bundle.body_b, bundle.dynamic_b, vb, wb);
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

float SolveBundlePosition(const ContactBundle& bundle, const SolverBody* bodies, SolverPose* poses,
                          const PhysicsSettings& settings) {
  WideVec3 center_a, center_b;
  WideQuat rotation_a, rotation_b;
  GatherPoses(poses, bundle.body_a, center_a, rotation_a);
  GatherPoses(poses, bundle.body_b, center_b, rotation_b);
  const WideInertia inertia_a = GatherInertia(bodies, bundle.body_a);
  const WideInertia inertia_b = GatherInertia(bodies, bundle.body_b);
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
