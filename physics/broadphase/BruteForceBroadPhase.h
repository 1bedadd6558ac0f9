// BruteForceBroadPhase: tests every pair of bounds. Kept as the oracle the quad tree is checked
// against, and fine for small worlds. Thread-safe: one reader/writer lock around flat arrays, so every
// query sees the latest state and a pin holds nothing.
#pragma once

#include <memory>
#include <shared_mutex>

#include "physics/broadphase/BroadPhase.h"

namespace strata {

/// O(N) per query, O(active x N) per pair search, over structure-of-arrays bounds.
class BruteForceBroadPhase final : public BroadPhase {
 public:
  BruteForceBroadPhase(std::uint32_t capacity, std::shared_ptr<const LayerSetup> layers);

  Result<AddBatch> AddBodiesPrepare(std::span<const BodyID> ids, std::span<const AABB> bounds,
                                    std::span<const ObjectLayer> layers) override;
  Status AddBodiesFinalize(AddBatch& batch) override;
  void AddBodiesAbort(AddBatch& batch) override;
  Status RemoveBodies(std::span<const BodyID> ids) override;
  Status UpdateBody(BodyID id, const AABB& bounds) override;
  bool Contains(BodyID id) const override;
  std::size_t body_count() const override;
  void Update() override {}
  void Optimize() override {}
  BroadPhaseStats stats() const override { return {}; }
  BroadPhasePin Pin() const override { return {}; }

  void FindPairs(std::span<const BodyID> active, std::span<const std::uint8_t> active_flags,
                 const LayerSetup& layers, std::vector<BodyPair>& out) const override;
  using BroadPhase::CastAABB;
  using BroadPhase::CastRay;
  using BroadPhase::CollideAABB;
  using BroadPhase::CollideSphere;
  void CollideAABB(const BroadPhasePin& pin, const AABB& box, const QueryFilter& filter,
                   BroadPhaseCollector& collector) const override;
  void CollideSphere(const BroadPhasePin& pin, const Vec3& center, float radius, const QueryFilter& filter,
                     BroadPhaseCollector& collector) const override;
  void CastRay(const BroadPhasePin& pin, const Vec3& origin, const Vec3& direction, const QueryFilter& filter,
               BroadPhaseCollector& collector) const override;
  void CastAABB(const BroadPhasePin& pin, const AABB& box, const Vec3& displacement,
                const QueryFilter& filter, BroadPhaseCollector& collector) const override;

 protected:
  void ReleasePin(std::uint32_t) const override {}

 private:
  static constexpr std::uint32_t kAbsent = 0xffffffffu;
  struct PreparedBatch;

  std::uint32_t DenseSlot(BodyID id) const;
  AABB BoundsAt(std::size_t slot) const {
    return {{min_x_[slot], min_y_[slot], min_z_[slot]}, {max_x_[slot], max_y_[slot], max_z_[slot]}};
  }
  void Insert(BodyID id, const AABB& bounds, ObjectLayer layer);
  /// Calls `visit(slot)` for every present body the filter accepts, under the read lock.
  template <class Visitor>
  void ForEachAccepted(const QueryFilter& filter, Visitor&& visit) const;

  std::shared_ptr<const LayerSetup> layers_;
  // Dense arrays of present bodies, laid out for the overlap loop.
  std::vector<float> min_x_, min_y_, min_z_, max_x_, max_y_, max_z_;
  std::vector<BodyID> ids_;
  std::vector<ObjectLayer> layers_of_;
  std::vector<std::uint32_t> dense_of_index_;  // body index -> dense position or kAbsent
  std::vector<std::uint8_t> prepared_;         // body index -> claimed by a prepared batch
  mutable std::shared_mutex mutex_;
};

}  // namespace strata
