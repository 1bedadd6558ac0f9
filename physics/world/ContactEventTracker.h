// ContactEventTracker: turns the manifolds the step's narrow-phase jobs reported (pairs with a body created
// with report_contacts) into contact begin / persist / end events against the pairs that touched last step.
// The step looks only at the pairs of its active bodies: a touching pair whose bodies both sleep (or one
// sleeps on a static body) stays touching, without events, until one of them wakes, leaves or is destroyed.
// Step thread only: Update runs once a step, after the solve, while the step holds every body lock.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "physics/body/BodyManager.h"
#include "physics/math/Math.h"
#include "physics/world/StepEvents.h"

namespace strata {

/// One manifold of a reporting pair, as a narrow-phase job found it: what the events sum up, one record
/// after another (its geometry lies apart: only a touching pair's deepest manifold is read for it).
struct ReportedManifold {
  // Provided, so that a record made in its array is not zeroed before its members are set.
  ReportedManifold() {}
  BodyID a;  ///< the pair as the narrow phase ordered it (A found it)
  BodyID b;
  /// Per point, the normal impulse over the step (N s), where the solver sums it (its CachedManifold); zero
  /// when neither side moves this step.
  const float* impulses;
  float separation;  ///< the smallest of its points' as the step began
  float approach_speed;
  int point_count;
};

/// A reported manifold's normal and points, at the same index as its ReportedManifold.
struct ReportedGeometry {
  ReportedGeometry() {}
  Vec3 normal;                            ///< A to B
  Vec3 points[ContactEvent::kMaxPoints];  ///< world, midway between the surfaces
};

/// What one narrow-phase job reported, in the order it found it.
struct JobReports {
  std::span<const ReportedManifold> manifolds;
  std::span<const ReportedGeometry> geometry;
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
  void Update(std::span<const JobReports> jobs, std::span<const std::uint8_t> active_flags,
              const BodyManager& bodies, StepEvents& events);

 private:
  struct Touching {
    std::uint64_t key;  // lower index << 32 | higher index
    BodyID a;           // the lower index
    BodyID b;
  };
  // A pair's manifolds summed up; its event is made from them only when it is reported.
  struct Pair {
    std::uint64_t key;
    BodyID low;  // the body of the lower index: the event's body_a
    BodyID high;
    const ReportedGeometry* deepest;  // the manifold the event takes its normal and points from
    float separation;                 // the deepest's
    float approach_speed;
    float normal_impulse;
    int point_count;  // the deepest's
    bool touching;
    bool turned;  // the narrow phase found the pair from the higher index: the normal turns
  };

  void Summarize(std::span<const JobReports> jobs);
  static void Merge(const ReportedManifold& manifold, const ReportedGeometry& geometry, Pair& pair);
  static void WriteEvent(const Pair& pair, ContactEvent& event);

  std::vector<Pair> pairs_;                                     // this step's reporting pairs
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order_;  // their keys and indices, by key
  std::vector<std::uint64_t> found_keys_;                       // their keys as found, for the next step
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sort_scratch_;
  std::vector<Touching> touching_;
  std::vector<Touching> next_touching_;
};

}  // namespace strata
