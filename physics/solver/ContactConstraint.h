// ContactConstraint: one contact manifold as the narrow phase hands it to the solver: the two solver bodies,
// the normal, the material, and per point the lever arms, the points in each body's frame, the normal
// velocity to aim for (a bounce or closing a speculative gap) and last step's impulses. Built by a
// narrow-phase job into its own arena with exactly as many points as the manifold has; the solver then lays
// it out for its loops (ContactSolver for one constraint at a time, ContactBundle for eight at once).
#pragma once

#include <cstdint>
#include <span>

#include "physics/core/BlockArena.h"
#include "physics/narrowphase/BodyPairCache.h"
#include "physics/narrowphase/ContactManifold.h"
#include "physics/solver/SolverBody.h"
#include "physics/world/PhysicsSettings.h"

namespace strata {

/// One point of a ContactConstraint.
struct ContactConstraintPoint {
  Vec3 r_a;            ///< from A's centre of mass to the point on A, world axes, at the start of the step
  Vec3 r_b;            ///< from B's centre of mass to the point on B
  Vec3 local_a;        ///< r_a in A's frame (the position passes); the world point when A is the fixed body
  Vec3 local_b;        ///< r_b in B's frame; the world point when B is the fixed body
  Vec3 warm_friction;  ///< last step's friction impulse, world (0 if the point is new)
  float warm_normal;   ///< last step's normal impulse
  float target_velocity;  ///< normal velocity to aim for
};

/// A manifold ready for the solver; its points follow it in memory.
struct ContactConstraint {
  Vec3 normal;           ///< unit, A to B
  std::uint32_t body_a;  ///< solver body index (0 = the fixed body)
  std::uint32_t body_b;
  float friction;
  float bounce_shift;     ///< metres to pull the bodies together after integration (a speculative bounce)
  CachedManifold* cache;  ///< where the solver leaves this step's impulses for the next one
  std::uint8_t point_count;
  bool dynamic_a;  ///< the solver moves A
  bool dynamic_b;

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

/// One side of a manifold as the constraint builder needs it.
struct ContactSide {
  std::uint32_t solver_index;  ///< 0 = the fixed body (static, sleeping, or not moved by the solver)
  bool dynamic;
  const SolverBody* body;  ///< velocities (after forces) of the solver body
  Vec3 center_of_mass;     ///< world, the body's own even when it stands in as the fixed body
  float gravity_factor;    ///< 0 unless dynamic
};

/// Builds the constraint for a manifold (unit normal A to B, its points) in `arena`: targets (restitution
/// above min_velocity_for_restitution, or closing the speculative gap), bounce shift, warm-start impulses.
/// `cache` holds the points in each body's frame and last step's impulses, in the same order.
ContactConstraint* BuildContactConstraint(BlockArena& arena, const Vec3& normal,
                                          std::span<const ContactArms> points, const ContactSide& a,
                                          const ContactSide& b, float friction, float restitution,
                                          CachedManifold* cache, float dt, const PhysicsSettings& settings);

/// Moves bouncing bodies back by the travel a mid-step impact would not have made (after integration).
void ApplyContactBounceShift(const ContactConstraint& constraint, const SolverBody* bodies,
                             SolverPose* poses);

}  // namespace strata
