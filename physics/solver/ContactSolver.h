// ContactSolver: sequential impulses (Catto, GDC 2009) one contact constraint at a time, for the islands and
// splits whose constraints share bodies: small islands and the sequential split of a large one. Setup lays a
// ContactConstraint out as a SolverContact: per point, the Jacobian rows of the normal and both friction
// axes and their images under each body's inverse inertia, so the passes are dot products and multiply-adds
// on 4-wide vectors. Functions touch only the contact and its two solver bodies; callers keep two threads
// off the same dynamic body.
#pragma once

#include "physics/core/BlockArena.h"
#include "physics/solver/ContactConstraint.h"

namespace strata {

/// Velocity rows of one contact point: [0] the normal, [1] and [2] the friction axes.
struct alignas(16) SolverContactPoint {
  Vec4 angular_a[3];   ///< r_a x axis
  Vec4 angular_b[3];   ///< r_b x axis
  Vec4 response_a[3];  ///< inverse inertia of A times angular_a
  Vec4 response_b[3];  ///< inverse inertia of B times angular_b
  float normal_mass;   ///< 1 / effective mass along the normal
  float tangent_mass;  ///< one mass for both friction axes, so friction opposes sliding in every direction
  float target_velocity;
  float normal_impulse;  ///< accumulated
  float tangent_impulse[2];
};

/// A ContactConstraint set up for the sequential solver; its points follow it in memory.
struct alignas(16) SolverContact {
  Vec4 normal;
  Vec4 tangent[2];
  ContactConstraint* constraint;
  float friction;
  std::uint8_t point_count;

  SolverContactPoint* points() { return reinterpret_cast<SolverContactPoint*>(this + 1); }
  const SolverContactPoint* points() const { return reinterpret_cast<const SolverContactPoint*>(this + 1); }
};

/// Sets `constraint` up in `arena` against the bodies' current inverse masses and inertias.
SolverContact* SetupSolverContact(BlockArena& arena, ContactConstraint& constraint, const SolverBody* bodies);
/// Applies the warm-start impulses to the bodies' velocities.
void WarmStartContact(const SolverContact& contact, SolverBody* bodies);
/// One Gauss-Seidel pass: friction (clamped to the circle), then non-penetration. `reverse` visits the points
/// backwards (alternate it per pass so stacks do not lean).
void SolveContactVelocity(SolverContact& contact, SolverBody* bodies, bool reverse);
/// Leaves the accumulated impulses in the constraint's cache entry for next step's warm start.
void StoreContactImpulses(const SolverContact& contact);
/// One non-linear position pass over the constraint's points; returns the deepest penetration seen (m, <= 0).
float SolveContactPosition(const ContactConstraint& constraint, const SolverBody* bodies, SolverPose* poses,
                           const PhysicsSettings& settings);

}  // namespace strata
