// ContactEventTracker: turns the manifolds the step's narrow-phase jobs reported (pairs with a body created
// with report_contacts) into contact begin / persist / end events against the pairs that touched last step.
// The step looks only at the pairs of its active bodies: a touching pair whose bodies both sleep (or one
// sleeps on a static body) stays touching, without events, until one of them wakes, leaves or is destroyed.
// Step thread only: Update runs once a step, after the solve, while the step holds every body lock.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "physics/body/BodyManager.h"
#include "physics/solver/ContactConstraint.h"
#include "physics/world/StepEvents.h"

namespace strata {

/// One manifold of a reporting pair, as a narrow-phase job found it.
struct ReportedManifold {
  BodyID a;  ///< the pair as the narrow phase ordered it (A found it)
  BodyID b;
  /// Where the solver leaves the manifold's impulses; null when neither side moves this step (a kinematic
  /// body touching a sleeping one).
  const ContactConstraint* constraint = nullptr;
  Vec3 normal;  ///< A to B
  float separation = 0.0f;
  float approach_speed = 0.0f;
  int point_count = 0;
  Vec3 points[ContactEvent::kMaxPoints] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                                           Vec3::Zero()};  ///< world, midway between the surfaces
};

/// Last step's touching pairs and the diff that makes this step's events.
class ContactEventTracker {
 public:
  /// True when no pair touched last step: with nothing reported this step, Update would do nothing.
  bool idle() const { return touching_.empty(); }
  std::size_t touching_count() const { return touching_.size(); }

  /// This step's events from every job's reported manifolds (each job's in the order it found them).
  /// `active_flags` (by body index) says which bodies' pairs the step looked at; `bodies` tells whether a
  /// body of a pair that touched last step is still in the world.
  void Update(std::span<const std::span<const ReportedManifold>> jobs,
              std::span<const std::uint8_t> active_flags, const BodyManager& bodies, StepEvents& events);

 private:
  struct Touching {
    std::uint64_t key;  // lower index << 32 | higher index
    BodyID a;           // the lower index
    BodyID b;
  };
  struct Pair {
    std::uint64_t key;
    bool touching;
    float deepest;
    ContactEvent event;
  };

  void Summarize(std::span<const std::span<const ReportedManifold>> jobs);
  static void Merge(const ReportedManifold& manifold, Pair& pair);

  std::vector<Pair> pairs_;  // this step's reporting pairs, by key
  std::vector<Touching> touching_;
  std::vector<Touching> next_touching_;
};

}  // namespace strata
