// BruteForceBroadPhase: tests every pair of bounds. Kept as the oracle the quad tree is checked
// against, and fine for small worlds. Thread-safe: one reader/writer lock around flat arrays.
#pragma once

#include <shared_mutex>

#include "physics/broadphase/BroadPhase.h"

namespace strata {

/// O(N) per query, O(active x N) per pair search, over structure-of-arrays bounds.
class BruteForceBroadPhase final : public BroadPhase {
 public:
  explicit BruteForceBroadPhase(std::uint32_t capacity);

  void AddBody(BodyID id, const AABB& bounds, ObjectLayer layer) override;
  void RemoveBody(BodyID id) override;
  void UpdateBody(BodyID id, const AABB& bounds) override;
  std::size_t body_count() const override;
  void FindPairs(std::span<const BodyID> active, std::span<const std::uint8_t> active_flags,
                 const LayerSetup& layers, std::vector<BodyPair>& out) const override;
  void CollideAABB(const AABB& box, const QueryFilter& filter, std::vector<BodyID>& out) const override;
  void CastRay(const Vec3& origin, const Vec3& direction, float max_fraction, const QueryFilter& filter,
               std::vector<BroadPhaseRayHit>& out) const override;

 private:
  static constexpr std::uint32_t kAbsent = 0xffffffffu;

  // Dense arrays of present bodies, laid out for the overlap loop.
  std::vector<float> min_x_, min_y_, min_z_, max_x_, max_y_, max_z_;
  std::vector<BodyID> ids_;
  std::vector<ObjectLayer> layers_;
  std::vector<std::uint32_t> dense_of_index_;  // body index -> dense position or kAbsent
  mutable std::shared_mutex mutex_;
};

}  // namespace strata
