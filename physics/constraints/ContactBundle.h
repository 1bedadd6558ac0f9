// ContactBundle: the contact constraints of one parallel split solved together, one per SIMD lane (as in
// Box2D v3's wide contact solver). A split never has two constraints that move the same body, so the lanes
// are independent: each lane runs the sequence ContactSolver runs for its constraint (friction on the
// circle, then soft non-penetration, points alternating direction per pass), a register of lanes at a time.
// A point's separation is tracked through the substeps from the bodies' motion since the step began, not
// from their poses.
// The lanes are stored compactly, as Box2D stores its anchors: per point only the lever arms, masses,
// separation and impulses; a row's velocity is the contact point's relative velocity along the axis, and an
// impulse turns a body by its inverse inertia times (arm x impulse), with the two inverse inertias kept once
// per bundle. The solve then streams a third of the bytes precomputed Jacobians would need. Bodies are
// gathered into lanes at the start of a pass and scattered back (dynamic sides only) at its end. A bundle
// belongs to one job at a time.
#pragma once

#include <cstdint>
#include <span>

#include "physics/constraints/ContactConstraint.h"
#include "physics/core/BlockArena.h"
#include "physics/math/WideFloat.h"

namespace strata {

/// Data of point j of the bundle's constraints.
struct ContactBundleRows {
  WideVec3 arm_a;  ///< from A's centre of mass to the point on A, world, at the start of the step
  WideVec3 arm_b;
  WideFloat normal_mass;
  WideFloat tangent_mass;     ///< one mass for both friction axes
  WideFloat separation;       ///< at the start of the step (huge in lanes without point j)
  WideFloat normal_velocity;  ///< before the solve: what a bounce reverses
  WideFloat normal_impulse;
  WideFloat tangent_impulse[2];
  WideFloat max_normal_impulse;  ///< largest single push this step: a bounce needs the contact to have acted
};

/// A symmetric 3x3 matrix per lane: an inverse inertia in world space.
struct WideSymmetric3 {
  WideFloat xx, xy, xz, yy, yz, zz;
  static WideSymmetric3 Zero() {
    const WideFloat zero = WideFloat::Zero();
    return {zero, zero, zero, zero, zero, zero};
  }
  WideVec3 Times(const WideVec3& v) const {
    return {MulAdd(xx, v.x, MulAdd(xy, v.y, xz * v.z)), MulAdd(xy, v.x, MulAdd(yy, v.y, yz * v.z)),
            MulAdd(xz, v.x, MulAdd(yz, v.y, zz * v.z))};
  }
};

/// Up to kLanes constraints of one split, laid out lane by lane; the rows follow it in memory.
struct alignas(alignof(WideFloat)) ContactBundle {
  static constexpr int kLanes = WideFloat::kLanes;
  WideVec3 normal;
  WideVec3 tangent[2];
  WideFloat friction;
  WideFloat restitution;
  WideFloat inverse_mass_a;
  WideFloat inverse_mass_b;
  WideSymmetric3 inverse_inertia_a;  ///< zero for sides the solver does not move
  WideSymmetric3 inverse_inertia_b;
  WideFloat bias_rate;  ///< the lane's Softness: against a fixed body or between moving ones
  WideFloat mass_scale;
  WideFloat impulse_scale;
  WideFloat moving_a;  ///< mask: the solver moves A (its motion this step is in its delta; else v * t)
  WideFloat moving_b;
  ContactConstraint* constraints[kLanes];  ///< null in empty lanes
  std::uint32_t body_a[kLanes];            ///< solver bodies (the fixed body 0 in empty lanes)
  std::uint32_t body_b[kLanes];
  bool dynamic_a[kLanes];
  bool dynamic_b[kLanes];
  std::uint32_t point_count;  ///< most points of any lane
  /// Every lane's B is the fixed body (a body on the ground, on a level mesh): B's side is never gathered,
  /// moved or scattered. The splitter puts such constraints first in each split, so most bundles are one
  /// kind or the other.
  bool fixed_b;
  /// A lane's constraint reports contact events: the bundle sums each point's normal impulse over the step in
  /// `reported_impulses` (one row a point; null in bundles without such a lane). They lie apart from the
  /// bundles (AllocateReportedImpulses), so that the solver's passes stream the bundles alone.
  bool reports;
  WideFloat* reported_impulses;

  ContactBundleRows* rows() { return reinterpret_cast<ContactBundleRows*>(this + 1); }
  const ContactBundleRows* rows() const { return reinterpret_cast<const ContactBundleRows*>(this + 1); }
};

/// Reserves a bundle for `constraints` (at most kLanes, no two moving the same body) in `arena`; SetupBundle
/// fills it in later, possibly on another thread.
ContactBundle* AllocateBundle(BlockArena& arena, std::span<ContactConstraint* const> constraints);
/// A reporting bundle's impulse sums, from `arena` once a group's bundles are all allocated.
void AllocateReportedImpulses(BlockArena& arena, ContactBundle& bundle);
/// Lays the bundle's constraints out lane by lane against the bodies' current inverse masses and inertias.
void SetupBundle(ContactBundle& bundle, const SolverBody* bodies, const SubstepContext& context);
/// Applies the accumulated impulses to the bodies' velocities (every substep: they are per-substep impulses).
void WarmStartBundle(const ContactBundle& bundle, SolverBody* bodies);
/// One Gauss-Seidel pass over each lane's constraint (see SolveContactVelocity); with `use_bias` overlap is
/// pushed out softly, without it (relax) only speculative gaps are closed. If `deepest` is set it is lowered
/// to the smallest separation seen (m).
void SolveBundleVelocity(ContactBundle& bundle, SolverBody* bodies, const SubstepContext& context,
                         bool use_bias, bool reverse, float* deepest);
/// After the last substep: points that approached faster than the threshold and pushed bounce back with
/// the restitution times their approach speed.
void ApplyBundleRestitution(ContactBundle& bundle, SolverBody* bodies, const SubstepContext& context);
/// Leaves the accumulated impulses in each constraint's cache entry (and, in a reporting bundle, the step's
/// summed normal impulses in each reporting constraint).
void StoreBundleImpulses(ContactBundle& bundle);
/// In a reporting bundle: adds the accumulated normal impulses to the step's sums (see AddReportedImpulses).
void AddBundleReportedImpulses(ContactBundle& bundle);

}  // namespace strata
