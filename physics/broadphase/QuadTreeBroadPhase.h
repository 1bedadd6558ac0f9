// QuadTreeBroadPhase: the default broad phase: one lock-free QuadTree per broad-phase layer, body
// locations for O(1) move and remove, batch insertion in O(1), and pinned tree generations.
// Queries never lock. Adds, removes and moves run concurrently with queries and each other; they pass a
// striped gate (no shared cache line) that only Update/Optimize (the step's rebuild, ~1 ms) close.
#pragma once

#include <chrono>

#include <memory>

#include "physics/broadphase/BroadPhase.h"
#include "physics/broadphase/QuadTree.h"
#include "physics/broadphase/TreeGenerations.h"
#include "physics/core/StripedGate.h"

namespace strata {

/// Lock-free quad-tree broad phase with generations that long-running readers can pin.
class QuadTreeBroadPhase final : public BroadPhase {
 public:
  static constexpr std::uint32_t kMaxBroadPhaseLayers = TreeGenerations::kMaxTrees;
  static constexpr std::uint32_t kNodesPerBody = 16;
  static constexpr std::uint32_t kSpareNodes = 1 << 16;
  static constexpr std::chrono::milliseconds kNodeWait{2000};
  /// The node pool's ceiling for `max_bodies`: room for the tree, a full rebuild beside it and the
  /// generations readers pin (the pool allocates its blocks as it grows towards it).
  static std::uint32_t DefaultNodeCapacity(std::uint32_t max_bodies);

  /// Room for body indices below `max_bodies`. `max_nodes` 0 picks DefaultNodeCapacity(max_bodies). The
  /// layer setup must have at most kMaxBroadPhaseLayers layers.
  /// A batch that finds the pool short (readers pinning many old generations) waits up to kNodeWait for
  /// rebuilds to free their nodes before it fails.
  QuadTreeBroadPhase(std::uint32_t max_bodies, std::shared_ptr<const LayerSetup> layers,
                     std::uint32_t max_nodes = 0);
  ~QuadTreeBroadPhase() override;

  Result<AddBatch> AddBodiesPrepare(std::span<const BodyID> ids, std::span<const AABB> bounds,
                                    std::span<const ObjectLayer> layers) override;
  Status AddBodiesFinalize(AddBatch& batch) override;
  void AddBodiesAbort(AddBatch& batch) override;
  Status RemoveBodies(std::span<const BodyID> ids) override;
  Status UpdateBody(BodyID id, const AABB& bounds) override;
  void PrefetchUpdate(BodyID id) const override;
  bool Contains(BodyID id) const override;
  std::size_t body_count() const override { return body_count_.load(std::memory_order_relaxed); }

  void Update() override { Rebuild(false); }
  void Optimize() override { Rebuild(true); }
  BroadPhaseStats stats() const override;
  BroadPhasePin Pin() const override;

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
  void ReleasePin(std::uint32_t record) const override;

 private:
  struct PreparedBatch;

  void Rebuild(bool full);
  // Whether any tree's current root was marked changed (a body left its slot, came or went) since it was
  // built.
  bool AnyTreeChanged();
  Status CheckPresent(BodyID id) const;
  /// Walks every tree the filter can accept bodies from, in the pinned generation. `test` is a child test
  /// (QuadTree::Walk) or the AABB to overlap (QuadTree::WalkOverlapping).
  template <class ChildTest, class BodyVisitor>
  void WalkTrees(const BroadPhasePin& pin, const QueryFilter& filter, ChildTest&& test,
                 BodyVisitor&& visit) const;
  std::array<std::uint32_t, TreeGenerations::kMaxTrees> MakeEmptyRoots();
  // pool_.Reserve, waiting up to kNodeWait while old generations hold the nodes.
  bool ReserveNodes(std::uint32_t count);

  const std::uint32_t max_bodies_;
  std::shared_ptr<const LayerSetup> layers_;
  QuadTreeNodePool pool_;
  std::vector<BodyLocation> locations_;
  std::vector<QuadTree> trees_;
  TreeGenerations generations_;
  std::vector<std::uint64_t> tree_layer_mask_;       // per tree: object layers it holds (bit 63 = 63 and up)
  std::vector<std::uint64_t> collides_with_layers_;  // per object layer: layers it collides with
  StripedGate modification_gate_;
  std::vector<std::vector<QuadTree::Item>> rebuild_items_;  // Rebuild's scratch (one rebuild at a time)
  std::vector<std::uint32_t> rebuild_retired_;
  std::vector<std::uint32_t> rebuild_stack_;
  std::atomic<std::size_t> body_count_{0};
  std::atomic<std::size_t> rebuilds_skipped_{0};
};

}  // namespace strata
