// ContactConstraint: one contact manifold as the narrow phase hands it to the solver: the two solver bodies,
// the normal, the material, and per point the lever arms, the separation when the step began, the normal
// velocity then (what a bounce reverses) and last step's impulses. Built by a
// narrow-phase job into its own arena with exactly as many points as the manifold has; the solver then lays
// it out for its loops (ContactSolver for one constraint at a time, ContactBundle for eight at once).
#pragma once

#include <cstdint>
#include <span>

#include "physics/PhysicsSettings.h"
#include "physics/body/SolverBody.h"
#include "physics/core/BlockArena.h"
#include "physics/narrowphase/BodyPairCache.h"
#include "physics/narrowphase/ContactManifold.h"

namespace strata {

/// One point of a ContactConstraint.
struct ContactConstraintPoint {
  Vec3 r_a;            ///< from A's centre of mass to the point on A, world axes, at the start of the step
  Vec3 r_b;            ///< from B's centre of mass to the point on B
  Vec3 warm_friction;  ///< last step's friction impulse, world (0 if the point is new)
  float warm_normal;   ///< last step's normal impulse
  float separation;    ///< along the normal at the start of the step; < 0 where the bodies overlap
  /// Of B relative to A along the normal when the points meet (< 0: approaching): what a bounce reverses.
  float normal_velocity;
};

/// A manifold ready for the solver; its points follow it in memory.
struct ContactConstraint {
  Vec3 normal;           ///< unit, A to B
  std::uint32_t body_a;  ///< solver body index (0 = the fixed body)
  std::uint32_t body_b;
  float friction;
  float restitution;
  CachedManifold* cache;  ///< where the solver leaves this step's impulses for the next one
  std::uint8_t point_count;
  bool dynamic_a;  ///< the solver moves A
  bool dynamic_b;
  /// Its pair reports contact events: the solver sums each point's normal impulse over the step's substeps
  /// into the cache's reported_impulses() (CachedManifold::reports).
  bool reports;

  ContactConstraintPoint* points() { return reinterpret_cast<ContactConstraintPoint*>(this + 1); }
  const ContactConstraintPoint* points() const {
    return reinterpret_cast<const ContactConstraintPoint*>(this + 1);
  }
  static std::size_t Bytes(int points) {
    return sizeof(ContactConstraint) + points * sizeof(ContactConstraintPoint);
  }
};

/// A manifold point as the constraint builder takes it: each body's lever arm to it and the gap there.
struct ContactArms {
  Vec3 r_a;          ///< from A's centre of mass to the point on A
  Vec3 r_b;          ///< from B's centre of mass to the point on B
  float separation;  ///< along the normal; < 0 where the bodies overlap
};

/// A contact spring (Catto, "Solver2D", and Box2D v3's soft step): a stiffness given as a frequency and a
/// damping ratio, stepped implicitly at the substep, as `bias_rate` (1/s: the overlap pushed out per second)
/// and `stiffness` (h omega (2 zeta + h omega), Box2D's a2).
struct SoftSpring {
  float bias_rate = 0.0f;
  float stiffness = 0.0f;
};
/// The spring of `hertz` and `damping_ratio` stepped at `h` seconds.
SoftSpring MakeSoftSpring(float hertz, float damping_ratio, float h);

/// How a soft contact solves: aim for the bias, scale the impulse that would remove the velocity error by
/// `mass_scale` and relax the accumulated one by `impulse_scale` (a rigid contact is {0, 1, 0}).
struct Softness {
  float bias_rate = 0.0f;
  float mass_scale = 1.0f;
  float impulse_scale = 0.0f;
};
/// The softness of a contact between bodies of inverse masses `a` and `b` (0 = does not move). Box2D scales
/// the spring by the pair's effective mass, so a 1000 kg box on a 1 kg box rests on a 1 kg spring and
/// sinks 0.3 m; here the spring is scaled by the heavier body's mass: the light body's side becomes nearly
/// rigid, and a contact's sag under its load is what the heavier body alone would give (g / omega^2).
Softness SoftnessFor(const SoftSpring& spring, float inverse_mass_a, float inverse_mass_b);

/// What the passes of one substep need besides the constraints and bodies.
struct SubstepContext {
  SoftSpring between_moving;  ///< contacts between two bodies the solver moves
  SoftSpring against_fixed;   ///< contacts with a static, kinematic or sleeping body (twice as stiff)
  float inverse_h = 0.0f;     ///< 1 / substep
  float max_push_velocity = 0.0f;
  float elapsed = 0.0f;  ///< seconds since the step began at the poses the pass sees (kinematic motion)
  float restitution_threshold = 0.0f;
  float weight_per_impulse = 0.0f;  ///< 1 / (|g| h): the mass a per-substep impulse holds up, per kg*m/s
};

/// One side of a manifold as the constraint builder needs it.
struct ContactSide {
  std::uint32_t solver_index;  ///< 0 = the fixed body (static, sleeping, or not moved by the solver)
  bool dynamic;
  const SolverBody* body;  ///< velocities (after forces) of the solver body
  /// What gravity and forces add to its velocity per substep (the first substep's share is already in the
  /// velocities), and that substep's length: a bounce reverses the approach speed at impact (see
  /// ContactConstraintPoint::normal_velocity).
  Vec3 velocity_gain = Vec3::Zero();
  float substep = 0.0f;
};

/// The approach speed along the normal when two points `separation` apart meet, from the relative normal
/// velocity now (holding one substep's `gain_per_substep`, gained over `substep` seconds) at the step's
/// start: the start velocity itself where the points touch already, separate, or are not pulled together.
float ApproachAtImpact(float normal_velocity, float gain_per_substep, float substep, float separation);

/// Builds the constraint for a manifold (unit normal A to B, its points) in `arena`, with warm-start impulses
/// from `cache`, which holds last step's impulses for the same points in the same order; it reports when the
/// cache does.
ContactConstraint* BuildContactConstraint(BlockArena& arena, const Vec3& normal,
                                          std::span<const ContactArms> points, const ContactSide& a,
                                          const ContactSide& b, float friction, float restitution,
                                          CachedManifold* cache);

}  // namespace strata
