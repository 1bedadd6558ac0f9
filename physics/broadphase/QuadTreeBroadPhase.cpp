#include "physics/broadphase/QuadTreeBroadPhase.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "physics/math/Overlap4.h"

namespace strata {

namespace {

constexpr std::memory_order kRelaxed = std::memory_order_relaxed;
using ChildBounds = QuadTree::ChildBounds;

std::string Describe(BodyID id) {
  return "body " + std::to_string(id.index) + "#" + std::to_string(id.generation);
}

std::uint64_t LayerBit(ObjectLayer layer) {
  return layer < 64 ? std::uint64_t{1} << layer : ~std::uint64_t{0};
}

// The 4-wide child tests over the structure-of-arrays bounds.
int SphereMask(const ChildBounds& b, const Vec3& center, float radius_squared) {
  int mask = 0;
  for (int i = 0; i < 4; ++i) {
    const float dx = std::max({b.min_x[i] - center.x(), 0.0f, center.x() - b.max_x[i]});
    const float dy = std::max({b.min_y[i] - center.y(), 0.0f, center.y() - b.max_y[i]});
    const float dz = std::max({b.min_z[i] - center.z(), 0.0f, center.z() - b.max_z[i]});
    // An inside-out (empty) slot has min > max: reject it explicitly, the distance alone would not.
    const bool valid = (b.min_x[i] <= b.max_x[i]) & (b.min_y[i] <= b.max_y[i]) & (b.min_z[i] <= b.max_z[i]);
    mask |= static_cast<int>(valid & (dx * dx + dy * dy + dz * dz <= radius_squared)) << i;
  }
  return mask;
}

// A ray (origin + t * direction) against 4 boxes grown by `grow` (half extents of a swept box). Entry and
// exit are taken per axis by the sign of the direction, so an inside-out slot stays a miss.
struct Ray4 {
  Vec3 origin;
  Vec3 direction;
  Vec3 inverse;
  Vec3 grow;

  int Test(const ChildBounds& b, float max_fraction, float* entry) const {
    float t_min[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    float t_max[4] = {max_fraction, max_fraction, max_fraction, max_fraction};
    bool inside[4] = {true, true, true, true};
    const float* mins[3] = {b.min_x, b.min_y, b.min_z};
    const float* maxs[3] = {b.max_x, b.max_y, b.max_z};
    for (int axis = 0; axis < 3; ++axis) {
      const float o = origin[axis];
      if (direction[axis] == 0.0f) {
        for (int i = 0; i < 4; ++i)
          inside[i] = inside[i] && mins[axis][i] - grow[axis] <= o && o <= maxs[axis][i] + grow[axis];
        continue;
      }
      const float inv = inverse[axis];
      const float* near = direction[axis] > 0.0f ? mins[axis] : maxs[axis];
      const float* far = direction[axis] > 0.0f ? maxs[axis] : mins[axis];
      const float near_grow = direction[axis] > 0.0f ? -grow[axis] : grow[axis];
      for (int i = 0; i < 4; ++i) {
        t_min[i] = std::max(t_min[i], (near[i] + near_grow - o) * inv);
        t_max[i] = std::min(t_max[i], (far[i] - near_grow - o) * inv);
      }
    }
    int mask = 0;
    for (int i = 0; i < 4; ++i) {
      entry[i] = t_min[i];
      mask |= static_cast<int>(inside[i] & (t_min[i] <= t_max[i])) << i;
    }
    return mask;
  }

  float Entry(const AABB& box, float max_fraction) const {
    return box.Expanded(grow).RayEntry(origin, inverse, max_fraction);
  }
};

}  // namespace

struct QuadTreeBroadPhase::PreparedBatch final : AddBatch::State {
  struct Part {
    std::uint8_t tree;
    std::uint32_t entry;  // subtree root node, or a single body
    AABB bounds;
  };
  std::vector<Part> parts;  // one per tree the batch touches: finalize does O(trees) work, not O(bodies)
  std::size_t body_count = 0;
  std::uint32_t reserved_spares = 0;  // one node per part for a new root, if the root is full
};

std::uint32_t QuadTreeBroadPhase::DefaultNodeCapacity(std::uint32_t max_bodies) {
  // A tree over n bodies needs about n/3 nodes, but a full rebuild reserves up to n while the old tree
  // still holds its own, and every old generation a reader still pins keeps its nodes: a reader pinning
  // through a few rebuilds of a busy world holds several trees' worth. Blocks are allocated on first use,
  // so this is a ceiling the pool grows towards, not memory taken up front.
  const std::uint64_t nodes = kNodesPerBody * static_cast<std::uint64_t>(max_bodies) + kSpareNodes;
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(nodes, QuadTree::kBodyTag - 1));
}

bool QuadTreeBroadPhase::ReserveNodes(std::uint32_t count) {
  if (pool_.Reserve(count)) return true;
  // Short only while readers pin old generations: the next rebuilds free their nodes once the pins go.
  // Wait for that (adds are rare, a reader's pin is short), up to a bound, rather than fail the batch.
  const auto deadline = std::chrono::steady_clock::now() + kNodeWait;
  auto pause = std::chrono::microseconds(50);
  while (std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(pause);
    if (pool_.Reserve(count)) return true;
    pause = std::min(2 * pause, std::chrono::microseconds(5000));
  }
  return false;
}

std::array<std::uint32_t, TreeGenerations::kMaxTrees> QuadTreeBroadPhase::MakeEmptyRoots() {
  std::array<std::uint32_t, TreeGenerations::kMaxTrees> roots;
  roots.fill(TreeGenerations::kNoRoot);
  const bool reserved = pool_.Reserve(static_cast<std::uint32_t>(trees_.size()));
  assert(reserved);
  (void)reserved;
  for (std::size_t t = 0; t < trees_.size(); ++t) roots[t] = trees_[t].MakeEmptyNode(QuadTree::kNoParent);
  return roots;
}

QuadTreeBroadPhase::QuadTreeBroadPhase(std::uint32_t max_bodies, std::shared_ptr<const LayerSetup> layers,
                                       std::uint32_t max_nodes)
    : max_bodies_(max_bodies),
      layers_(std::move(layers)),
      pool_(max_nodes != 0 ? max_nodes : DefaultNodeCapacity(max_bodies)),
      locations_(max_bodies),
      trees_([&] {
        std::vector<QuadTree> trees;
        for (BroadPhaseLayer t = 0; t < layers_->BroadPhaseLayerCount(); ++t)
          trees.emplace_back(pool_, locations_, t);
        return trees;
      }()),
      generations_(MakeEmptyRoots()),
      tree_layer_mask_(trees_.size(), 0),
      collides_with_layers_(layers_->ObjectLayerCount(), 0) {
  assert(trees_.size() <= kMaxBroadPhaseLayers);
  for (ObjectLayer layer = 0; layer < layers_->ObjectLayerCount(); ++layer) {
    tree_layer_mask_[layers_->ToBroadPhaseLayer(layer)] |= LayerBit(layer);
    for (ObjectLayer other = 0; other < layers_->ObjectLayerCount(); ++other)
      if (layers_->ShouldCollide(layer, other)) collides_with_layers_[layer] |= LayerBit(other);
  }
}

QuadTreeBroadPhase::~QuadTreeBroadPhase() = default;

BroadPhasePin QuadTreeBroadPhase::Pin() const {
  const TreeGenerations::PinToken token = generations_.Pin();
  return {this, token.record, token.generation};
}

void QuadTreeBroadPhase::ReleasePin(std::uint32_t record) const {
  generations_.Unpin(record);
}

Status QuadTreeBroadPhase::CheckPresent(BodyID id) const {
  if (id.IsInvalid() || id.index >= max_bodies_)
    return MakeError(ErrorCode::kStaleBodyId, Describe(id) + " is outside the broad phase");
  const BodyLocation& location = locations_[id.index];
  if (location.claimed.load(std::memory_order_acquire) != 1 ||
      location.generation.load(kRelaxed) != id.generation ||
      !trees_[location.tree.load(kRelaxed)].IsLinked(id.index))
    return MakeError(ErrorCode::kInvalidState, Describe(id) + " is not in the broad phase");
  return Status::Ok();
}

bool QuadTreeBroadPhase::Contains(BodyID id) const {
  return CheckPresent(id).ok();
}

Result<AddBatch> QuadTreeBroadPhase::AddBodiesPrepare(std::span<const BodyID> ids,
                                                      std::span<const AABB> bounds,
                                                      std::span<const ObjectLayer> layers) {
  if (Status valid = CheckAddBatch(ids, bounds, layers, layers_->ObjectLayerCount()); !valid)
    return valid.error();
  for (const BodyID id : ids)
    if (id.index >= max_bodies_)
      return MakeError(ErrorCode::kStaleBodyId, Describe(id) + " is outside the broad phase");
  // Claim every body so no other batch or single add takes it meanwhile; undo on the first refusal.
  for (std::size_t i = 0; i < ids.size(); ++i) {
    std::uint8_t expected = 0;
    if (locations_[ids[i].index].claimed.compare_exchange_strong(expected, 1, std::memory_order_acq_rel))
      continue;
    for (std::size_t j = 0; j < i; ++j) locations_[ids[j].index].claimed.store(0, std::memory_order_release);
    return MakeError(ErrorCode::kInvalidState,
                     Describe(ids[i]) + " is already in the broad phase or a prepared batch");
  }
  std::vector<std::vector<QuadTree::Item>> items(trees_.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    BodyLocation& location = locations_[ids[i].index];
    const BroadPhaseLayer tree = layers_->ToBroadPhaseLayer(layers[i]);
    location.node.store(QuadTree::kInvalid, kRelaxed);
    location.tree.store(tree, kRelaxed);
    location.layer.store(layers[i], kRelaxed);
    location.generation.store(ids[i].generation, kRelaxed);
    location.SetBounds(bounds[i]);
    location.SetMotion(Vec3::Zero());
    items[tree].push_back({QuadTree::kBodyTag | ids[i].index, bounds[i]});
  }
  std::uint32_t needed = 0;
  for (const auto& tree_items : items)
    if (!tree_items.empty())
      needed += (tree_items.size() > 1 ? QuadTree::NodesToBuild(tree_items.size()) : 0) + 1;
  if (!ReserveNodes(needed)) {
    for (const BodyID id : ids) locations_[id.index].claimed.store(0, std::memory_order_release);
    return MakeError(
        ErrorCode::kCapacityExceeded,
        "broad phase node pool is full (" + std::to_string(pool_.capacity()) + " nodes, " +
            std::to_string(generations_.retired_node_count()) +
            " of them kept for readers that pin old generations) after waiting " +
            std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(kNodeWait).count()) +
            " ms for them");
  }
  auto state = std::make_unique<PreparedBatch>();
  std::uint32_t used = 0;
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    std::vector<QuadTree::Item>& tree_items = items[t];
    if (tree_items.empty()) continue;
    AABB total;
    for (const QuadTree::Item& item : tree_items) total.Encapsulate(item.bounds);
    const std::uint32_t entry =
        tree_items.size() == 1 ? tree_items[0].entry : trees_[t].Build(tree_items, QuadTree::kUnlinked, used);
    state->parts.push_back({static_cast<std::uint8_t>(t), entry, total});
    ++state->reserved_spares;
  }
  pool_.Unreserve(needed - used - state->reserved_spares);
  state->body_count = ids.size();
  return AddBatch(this, std::move(state), ids.size());
}

Status QuadTreeBroadPhase::AddBodiesFinalize(AddBatch& batch) {
  if (batch.owner() != this)
    return MakeError(ErrorCode::kInvalidArgument, "batch belongs to another broad phase");
  if (!batch.prepared()) return MakeError(ErrorCode::kInvalidState, "batch was already finalized or aborted");
  const std::unique_ptr<AddBatch::State> taken = batch.TakeState();
  const auto& state = static_cast<const PreparedBatch&>(*taken);
  const StripedGatePass modification(modification_gate_);
  for (const PreparedBatch::Part& part : state.parts)
    if (!trees_[part.tree].Link(generations_, part.entry, part.bounds)) pool_.Unreserve(1);
  body_count_.fetch_add(state.body_count, kRelaxed);
  return Status::Ok();
}

void QuadTreeBroadPhase::AddBodiesAbort(AddBatch& batch) {
  if (batch.owner() != this || !batch.prepared()) return;
  const std::unique_ptr<AddBatch::State> taken = batch.TakeState();
  const auto& state = static_cast<const PreparedBatch&>(*taken);
  std::vector<std::uint32_t> bodies;
  for (const PreparedBatch::Part& part : state.parts) {
    trees_[part.tree].CollectBodies(part.entry, bodies);
    trees_[part.tree].FreeSubtree(part.entry);
  }
  pool_.Unreserve(state.reserved_spares);
  for (const std::uint32_t body : bodies) {
    locations_[body].node.store(QuadTree::kInvalid, kRelaxed);
    locations_[body].claimed.store(0, std::memory_order_release);
  }
}

Status QuadTreeBroadPhase::RemoveBodies(std::span<const BodyID> ids) {
  const StripedGatePass modification(modification_gate_);
  for (const BodyID id : ids)
    if (Status present = CheckPresent(id); !present) return present;
  // Claim each for removal (1 -> 2) so two threads removing the same body cannot both succeed.
  for (std::size_t i = 0; i < ids.size(); ++i) {
    std::uint8_t expected = 1;
    if (locations_[ids[i].index].claimed.compare_exchange_strong(expected, 2, std::memory_order_acq_rel))
      continue;
    for (std::size_t j = 0; j < i; ++j) locations_[ids[j].index].claimed.store(1, std::memory_order_release);
    return MakeError(ErrorCode::kInvalidState,
                     Describe(ids[i]) + (expected == 2 ? " is listed twice or being removed"
                                                       : " is not in the broad phase"));
  }
  for (const BodyID id : ids) {
    BodyLocation& location = locations_[id.index];
    trees_[location.tree.load(kRelaxed)].Remove(id.index);
    location.claimed.store(0, std::memory_order_release);
  }
  body_count_.fetch_sub(ids.size(), kRelaxed);
  return Status::Ok();
}

void QuadTreeBroadPhase::PrefetchUpdate(BodyID id) const {
  if (id.index >= max_bodies_) return;
  // The node index is read without the body's lock: a stale one only prefetches a line nobody needs (pool
  // blocks are never freed while the broad phase lives). Acquire, as every reader of it, so that a node in a
  // fresh block comes with its block.
  const std::uint32_t holder = locations_[id.index].node.load(std::memory_order_acquire);
  if (holder == QuadTree::kInvalid) return;
  const char* const node = reinterpret_cast<const char*>(&pool_.Get(holder));
  __builtin_prefetch(node), __builtin_prefetch(node + 64);
}

Status QuadTreeBroadPhase::UpdateBody(BodyID id, const AABB& bounds) {
  if (Status valid = CheckBounds(bounds); !valid) return valid;
  const StripedGatePass modification(modification_gate_);
  if (Status present = CheckPresent(id); !present) return present;
  trees_[locations_[id.index].tree.load(kRelaxed)].Widen(id.index, bounds);
  return Status::Ok();
}

void QuadTreeBroadPhase::Rebuild(bool full) {
  const StripedGateClosure no_modifications(modification_gate_);
  auto free_node = [&](std::uint32_t node) { pool_.Free(node); };
  if (!full && !AnyTreeChanged()) {
    // Most steps of a steady world: every body moved within its slot. The generation stays; only what
    // readers have let go of since is freed.
    if (generations_.retired_node_count() > 0) generations_.Reclaim(free_node);
    return;
  }
  generations_.Reclaim(free_node);
  if (!generations_.CanPublish()) {
    rebuilds_skipped_.fetch_add(1, kRelaxed);
    return;
  }
  std::array<std::uint32_t, TreeGenerations::kMaxTrees> roots;
  roots.fill(TreeGenerations::kNoRoot);
  // Scratch kept between rebuilds (only one runs at a time: it closes the gate), so a steady world's
  // rebuild allocates nothing.
  std::vector<std::vector<QuadTree::Item>>& items = rebuild_items_;
  std::vector<std::uint32_t>& retired = rebuild_retired_;
  std::array<bool, TreeGenerations::kMaxTrees> rebuild{};
  items.resize(trees_.size());
  retired.clear();
  std::uint32_t needed = 0;
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    items[t].clear();
    roots[t] = generations_.CurrentRootSlot(static_cast<std::uint32_t>(t)).load(std::memory_order_acquire);
    rebuild[t] = trees_[t].CollectForRebuild(roots[t], full, items[t], retired, rebuild_stack_);
    if (rebuild[t]) needed += QuadTree::NodesToBuild(items[t].size());
  }
  if (needed == 0) return;  // nothing changed anywhere: the current generation stays
  // A rebuild can wait and an add cannot: keep room for every body not yet present to be added one at a
  // time (at most two nodes each), however many nodes generations pinned by slow readers still hold.
  const auto add_headroom = static_cast<std::uint32_t>(
      2 * (max_bodies_ - std::min<std::size_t>(max_bodies_, body_count())) + trees_.size());
  if (!pool_.Reserve(needed + add_headroom)) {
    rebuilds_skipped_.fetch_add(1, kRelaxed);
    return;
  }
  pool_.Unreserve(add_headroom);
  std::uint32_t used = 0;
  for (std::size_t t = 0; t < trees_.size(); ++t)
    if (rebuild[t]) roots[t] = trees_[t].BuildRoot(items[t], used);
  pool_.Unreserve(needed - used);
  generations_.Publish(roots, retired);
  generations_.Reclaim(free_node);  // frees at once what no reader pinned
}

bool QuadTreeBroadPhase::AnyTreeChanged() {
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    const std::uint32_t root =
        generations_.CurrentRootSlot(static_cast<std::uint32_t>(t)).load(std::memory_order_acquire);
    if (std::as_const(trees_[t]).node(root).changed.load(kRelaxed) != 0) return true;
  }
  return false;
}

BroadPhaseStats QuadTreeBroadPhase::stats() const {
  BroadPhaseStats stats;
  stats.nodes_in_use = pool_.in_use();
  stats.node_bytes = pool_.reserved_bytes();
  stats.retired_nodes = generations_.retired_node_count();
  stats.retired_bytes = stats.retired_nodes * sizeof(QuadTreeNode);
  stats.pinned_old_generations = generations_.pinned_old_generations();
  stats.generation = generations_.current_generation();
  stats.rebuilds_skipped = rebuilds_skipped_.load(kRelaxed);
  const BroadPhasePin pin = Pin();
  for (std::size_t t = 0; t < trees_.size(); ++t)
    stats.max_depth = std::max<std::size_t>(
        stats.max_depth, trees_[t].Depth(generations_.Root(pin.record(), static_cast<std::uint32_t>(t))));
  return stats;
}

template <class ChildTest, class BodyVisitor>
void QuadTreeBroadPhase::WalkTrees(const BroadPhasePin& pin, const QueryFilter& filter, ChildTest&& test,
                                   BodyVisitor&& visit) const {
  if (pin.owner() != this) {
    const BroadPhasePin own = Pin();
    WalkTrees(own, filter, test, visit);
    return;
  }
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    if ((tree_layer_mask_[t] & filter.object_layers) == 0) continue;
    bool stopped = false;
    auto visit_body = [&](std::uint32_t body, float distance) {
      const BodyLocation& location = locations_[body];
      if (location.claimed.load(std::memory_order_acquire) == 0 || body == filter.ignore_body_index ||
          !filter.AcceptsLayer(location.layer.load(kRelaxed)))
        return true;
      stopped = !visit(BodyID{body, location.generation.load(kRelaxed)}, location, distance);
      return !stopped;
    };
    const std::uint32_t root = generations_.Root(pin.record(), static_cast<std::uint32_t>(t));
    if constexpr (std::is_same_v<std::decay_t<ChildTest>, AABB>)
      trees_[t].WalkOverlapping(root, test, visit_body);
    else
      trees_[t].Walk(root, test, visit_body);
    if (stopped) return;
  }
}

void QuadTreeBroadPhase::CollideAABB(const BroadPhasePin& pin, const AABB& box, const QueryFilter& filter,
                                     BroadPhaseCollector& collector) const {
  WalkTrees(pin, filter, box, [&](BodyID id, const BodyLocation& location, float) {
    const AABB bounds = location.Bounds();
    if (bounds.Overlaps(box)) collector.AddOverlap(id, bounds);
    return !collector.ShouldStop();
  });
}

void QuadTreeBroadPhase::CollideSphere(const BroadPhasePin& pin, const Vec3& center, float radius,
                                       const QueryFilter& filter, BroadPhaseCollector& collector) const {
  const float radius_squared = radius * radius;
  WalkTrees(
      pin, filter, [&](const ChildBounds& b) { return SphereMask(b, center, radius_squared); },
      [&](BodyID id, const BodyLocation& location, float) {
        if (SquaredDistanceToBox(location.Bounds(), center) <= radius_squared) collector.AddHit(id, 0.0f);
        return !collector.ShouldStop();
      });
}

void QuadTreeBroadPhase::CastRay(const BroadPhasePin& pin, const Vec3& origin, const Vec3& direction,
                                 const QueryFilter& filter, BroadPhaseCollector& collector) const {
  CastAABB(pin, AABB(origin, origin), direction, filter, collector);
}

void QuadTreeBroadPhase::CastAABB(const BroadPhasePin& pin, const AABB& box, const Vec3& displacement,
                                  const QueryFilter& filter, BroadPhaseCollector& collector) const {
  const Ray4 ray{box.Center(), displacement, SafeInverse(displacement), box.HalfExtents()};
  WalkTrees(
      pin, filter,
      [&](const ChildBounds& b, float* entry) {
        return ray.Test(b, std::min(1.0f, collector.early_out_fraction()), entry);
      },
      [&](BodyID id, const BodyLocation& location, float) {
        const float entry = ray.Entry(location.Bounds(), std::min(1.0f, collector.early_out_fraction()));
        if (entry >= 0.0f) collector.AddHit(id, entry);
        return !collector.ShouldStop();
      });
}

void QuadTreeBroadPhase::FindPairs(std::span<const BodyID> active, std::span<const std::uint8_t> active_flags,
                                   const LayerSetup& layers, std::vector<BodyPair>& out) const {
  const BroadPhasePin pin = Pin();
  const bool own_layers = &layers == layers_.get();
  const bool layer_mask_exact = own_layers && layers_->ObjectLayerCount() <= 64;
  for (const BodyID a : active) {
    const BodyLocation& location = locations_[a.index];
    if (location.claimed.load(std::memory_order_acquire) != 1) continue;
    const ObjectLayer layer_a = location.layer.load(kRelaxed);
    const AABB box = location.Bounds();
    QueryFilter filter;
    filter.object_layers = own_layers ? collides_with_layers_[layer_a] : ~std::uint64_t{0};
    filter.ignore_body_index = a.index;
    WalkTrees(pin, filter, box, [&](BodyID b, const BodyLocation& other, float) {
      if (active_flags[b.index] && b.index < a.index) return true;  // reported from b's side
      if (!other.Bounds().Overlaps(box)) return true;
      // The filter's layer mask already said yes, and it is exact for our own table of up to 64 layers.
      if (!layer_mask_exact && !layers.ShouldCollide(layer_a, other.layer.load(kRelaxed))) return true;
      out.push_back({a, b});
      return true;
    });
  }
}

}  // namespace strata
