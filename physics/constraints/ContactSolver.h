// ContactSolver: sequential impulses (Catto, GDC 2009) with soft contacts (Box2D v3) one contact constraint
// at a time, for the islands and
// splits whose constraints share bodies: small islands and the sequential split of a large one. Setup lays a
// ContactConstraint out as a SolverContact: per point, the Jacobian rows of the normal and both friction
// axes and their images under each body's inverse inertia, so the passes are dot products and multiply-adds
// on 4-wide vectors. Functions touch only the contact and its two solver bodies; callers keep two threads
// off the same dynamic body.
#pragma once

#include "physics/constraints/ContactConstraint.h"
#include "physics/core/BlockArena.h"

namespace strata {

/// Velocity rows of one contact point: [0] the normal, [1] and [2] the friction axes.
struct alignas(16) SolverContactPoint {
  Vec4 angular_a[3];      ///< r_a x axis
  Vec4 angular_b[3];      ///< r_b x axis
  Vec4 response_a[3];     ///< inverse inertia of A times angular_a
  Vec4 response_b[3];     ///< inverse inertia of B times angular_b
  float normal_mass;      ///< 1 / effective mass along the normal
  float tangent_mass;     ///< one mass for both friction axes, so friction opposes sliding in every direction
  float separation;       ///< at the start of the step
  float normal_velocity;  ///< before the solve: what a bounce reverses
  float normal_impulse;   ///< accumulated
  float tangent_impulse[2];
  float max_normal_impulse;  ///< largest single push this step
};

/// A ContactConstraint set up for the sequential solver; its points follow it in memory.
struct alignas(16) SolverContact {
  Vec4 normal;
  Vec4 tangent[2];
  ContactConstraint* constraint;
  Softness softness;
  float friction;
  float restitution;
  std::uint8_t point_count;
  /// Friction > 0 but the points' friction rows not set up yet (an exact island solves friction as one
  /// patch per contact; see SetupPendingFrictionRows).
  bool friction_rows_pending;
  bool reports;  ///< its constraint sums its impulses for contact events (ContactConstraint::reports)

  SolverContactPoint* points() { return reinterpret_cast<SolverContactPoint*>(this + 1); }
  const SolverContactPoint* points() const { return reinterpret_cast<const SolverContactPoint*>(this + 1); }
};

/// How a contact's bodies moved since the step began, as first-order separation tracking needs it.
struct ContactMotion {
  float moved_apart = 0.0f;  ///< along the normal
  Vec4 turned_a = Vec4::Zero();
  Vec4 turned_b = Vec4::Zero();
};
/// The motion of `contact`'s bodies `elapsed` seconds into the step: their deltas where the solver moves
/// them, else their velocity times `elapsed` (kinematic bodies; the fixed body does not move).
ContactMotion MotionSinceStepBegan(const SolverContact& contact, const SolverBody* bodies, float elapsed);
/// A point's separation now: at the start of the step plus how the bodies moved and turned since.
inline float SeparationNow(const SolverContactPoint& p, const ContactMotion& motion) {
  return p.separation + motion.moved_apart + p.angular_b[0].dot(motion.turned_b) -
         p.angular_a[0].dot(motion.turned_a);
}

/// Sets `constraint` up in `arena` against the bodies' current inverse masses and inertias. A frictionless
/// contact gets zero friction rows and no friction impulse. Without `point_friction_rows` the points get
/// their normal rows only, friction impulses kept (an exact island's friction rows are per contact; a third
/// of the setup): call SetupPendingFrictionRows before a sequential pass or a warm start takes the contact.
SolverContact* SetupSolverContact(BlockArena& arena, ContactConstraint& constraint, const SolverBody* bodies,
                                  const SubstepContext& context, bool point_friction_rows = true);
/// Sets up the friction rows SetupSolverContact left out, if any.
void SetupPendingFrictionRows(SolverContact& contact, const SolverBody* bodies);
/// Applies the accumulated impulses to the bodies' velocities (every substep).
void WarmStartContact(const SolverContact& contact, SolverBody* bodies);
/// One Gauss-Seidel pass: friction (clamped to the circle), then non-penetration, softly pushing overlap
/// out with `use_bias`, else (relax) only closing speculative gaps. `reverse` visits the points backwards
/// (alternate it per pass so stacks do not lean). If `deepest` is set it is lowered to the smallest
/// separation seen (m).
void SolveContactVelocity(SolverContact& contact, SolverBody* bodies, const SubstepContext& context,
                          bool use_bias, bool reverse, float* deepest);
/// After the last substep: points that approached faster than the threshold and pushed bounce back.
void ApplyContactRestitution(SolverContact& contact, SolverBody* bodies, const SubstepContext& context);
/// Leaves the accumulated impulses in the constraint's cache entry for next step's warm start (and, for a
/// reporting contact, adds them to the step's sums: the last substep's share).
void StoreContactImpulses(const SolverContact& contact);
/// For a reporting contact: adds the accumulated normal impulses to the step's sums. The accumulated impulse
/// is per substep and a warm start applies it again, so the sums take it at each later substep's warm start
/// and once more when it is stored.
void AddReportedImpulses(const SolverContact& contact);

}  // namespace strata
