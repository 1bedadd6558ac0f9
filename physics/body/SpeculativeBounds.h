// SpeculativeBounds: the bounds a body has in the broad phase: its world bounds grown by the speculative
// contact distance and, while it moves, swept over the coming step, so contacts are found before bodies
// touch. Shared by BodyInterface (a body added or teleported) and the step (every moved body). Reads from
// any thread; the setters run while the step holds every body lock.
#pragma once

#include <atomic>

#include "physics/body/Body.h"

namespace strata {

class SpeculativeBounds {
 public:
  explicit SpeculativeBounds(float speculative_distance) : speculative_distance_(speculative_distance) {}

  /// `body`'s broad-phase bounds for a step of `dt` seconds (0: the last step's, 1/60 s before the first).
  AABB Of(const Body& body, float dt) const {
    AABB bounds = body.world_bounds().Expanded(speculative_distance());
    if (!body.IsActive()) return bounds;
    const float step = dt > 0.0f ? dt : last_dt_.load(std::memory_order_relaxed);
    const Vec3 travel = body.linear_velocity() * step;
    const float turn = body.angular_velocity().norm() * step * body.local_bounds().HalfExtents().norm();
    AABB swept = bounds;
    swept.min += travel;
    swept.max += travel;
    bounds.Encapsulate(swept);
    return bounds.Expanded(turn);
  }

  float speculative_distance() const { return speculative_distance_.load(std::memory_order_relaxed); }
  void set_speculative_distance(float distance) {
    speculative_distance_.store(distance, std::memory_order_relaxed);
  }
  /// Records the step about to run; true if it is longer than the last (bounds must be swept again).
  bool BeginStep(float dt) {
    const bool longer = dt > last_dt_.load(std::memory_order_relaxed);
    last_dt_.store(dt, std::memory_order_relaxed);
    return longer;
  }

 private:
  std::atomic<float> speculative_distance_;
  std::atomic<float> last_dt_{1.0f / 60.0f};
};

}  // namespace strata
