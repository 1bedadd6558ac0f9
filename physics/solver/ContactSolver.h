// ContactSolver: sequential impulses (Catto, GDC 2009) over contact manifolds: accumulated and clamped
// normal impulses, two-axis friction, restitution above a velocity threshold, speculative contacts,
// warm starting from the ContactCache, then non-linear position correction. Runs inside the step only.
#pragma once

#include <span>
#include <vector>

#include "physics/narrowphase/ContactCache.h"
#include "physics/solver/SolverBody.h"
#include "physics/world/PhysicsSettings.h"

namespace strata {

/// Material of a manifold's two bodies.
struct ContactMaterial {
  float friction;
  float restitution;
};

/// Solves one step's contacts over a SolverBody array.
class ContactSolver {
 public:
  /// Builds constraints for `manifolds` (bodies given as indices into `bodies`), warm-started from `cache`.
  void Setup(std::span<const ContactManifold> manifolds, std::span<const std::uint32_t> body_a,
             std::span<const std::uint32_t> body_b, std::span<const ContactMaterial> materials,
             std::span<const SolverBody> bodies, const ContactCache& cache, float dt,
             const PhysicsSettings& settings);
  /// Applies the cached impulses to the velocities.
  void WarmStart(std::span<SolverBody> bodies) const;
  /// One Gauss-Seidel pass over every constraint (`iteration` = pass number within the step).
  void SolveVelocities(std::span<SolverBody> bodies, int iteration);
  /// Writes this step's impulses into the cache for the next step.
  void StoreImpulses(ContactCache& cache) const;
  /// Moves bouncing bodies back to where a mid-step impact would have left them (after integration).
  void ApplyBounceCorrection(std::span<SolverBody> bodies) const;
  /// One non-linear Gauss-Seidel position pass; returns the largest remaining penetration (m).
  float SolvePositions(std::span<SolverBody> bodies, const PhysicsSettings& settings) const;

  std::size_t constraint_count() const { return constraints_.size(); }

 private:
  // One constraint axis at one point, with everything the inner loop needs precomputed: the angular
  // Jacobians (r x axis) and their images under each body's inverse inertia.
  struct AxisPart {
    Vec3 angular_a, angular_b;
    Vec3 response_a, response_b;  // inverse inertia * angular
    float mass;                   // 1 / effective mass along the axis
    float impulse;                // accumulated
  };
  struct Point {
    AxisPart normal;
    AxisPart tangent[2];
    Vec3 local_a, local_b;  // contact point from each centre of mass in the body's frame (position pass)
    float target_velocity;  // the normal velocity the constraint aims for (bounce or speculative)
    float separation;
  };
  struct Constraint {
    std::uint32_t a, b;
    Vec3 normal;
    Vec3 tangent[2];
    float friction;
    float
        bounce_shift;  // metres to pull the bodies together after integration (bouncing speculative contact)
    int count;
    Point points[ContactManifold::kMaxPoints];
    ContactKey key;
  };

  std::vector<Constraint> constraints_;
};

}  // namespace strata
