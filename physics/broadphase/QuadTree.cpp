#include "physics/broadphase/QuadTree.h"

#include <algorithm>
#include <cassert>

#include "physics/core/Atomics.h"

namespace strata {

namespace {

constexpr std::memory_order kRelaxed = std::memory_order_relaxed;

AABB SlotBounds(const QuadTreeNode& node, int slot) {
  return {
      {node.min_x[slot].load(kRelaxed), node.min_y[slot].load(kRelaxed), node.min_z[slot].load(kRelaxed)},
      {node.max_x[slot].load(kRelaxed), node.max_y[slot].load(kRelaxed), node.max_z[slot].load(kRelaxed)}};
}

AABB Union(std::span<const QuadTree::Item> items) {
  AABB bounds;
  for (const QuadTree::Item& item : items) bounds.Encapsulate(item.bounds);
  return bounds;
}

// Splits `items` in two at the middle of the longest axis of their centres; by count when that leaves a
// side empty (all centres equal). Returns the size of the first part.
std::size_t SplitInTwo(std::span<QuadTree::Item> items) {
  AABB centres;
  for (const QuadTree::Item& item : items) centres.Encapsulate(item.bounds.Center());
  int axis = 0;
  centres.Size().maxCoeff(&axis);
  const float middle = centres.Center()[axis];
  const auto second = std::partition(items.begin(), items.end(), [&](const QuadTree::Item& item) {
    return item.bounds.Center()[axis] < middle;
  });
  auto first_size = static_cast<std::size_t>(second - items.begin());
  if (first_size == 0 || first_size == items.size()) {
    first_size = items.size() / 2;
    std::nth_element(items.begin(), items.begin() + static_cast<std::ptrdiff_t>(first_size), items.end(),
                     [&](const QuadTree::Item& a, const QuadTree::Item& b) {
                       return a.bounds.Center()[axis] < b.bounds.Center()[axis];
                     });
  }
  return first_size;
}

}  // namespace

AABB BodyLocation::Bounds() const {
  return {{bounds[0].load(kRelaxed), bounds[1].load(kRelaxed), bounds[2].load(kRelaxed)},
          {bounds[3].load(kRelaxed), bounds[4].load(kRelaxed), bounds[5].load(kRelaxed)}};
}

void BodyLocation::SetBounds(const AABB& box) {
  for (int axis = 0; axis < 3; ++axis) {
    bounds[axis].store(box.min[axis], kRelaxed);
    bounds[3 + axis].store(box.max[axis], kRelaxed);
  }
}

Vec3 BodyLocation::Motion() const {
  return {motion[0].load(kRelaxed), motion[1].load(kRelaxed), motion[2].load(kRelaxed)};
}

void BodyLocation::SetMotion(const Vec3& step) {
  for (int axis = 0; axis < 3; ++axis) motion[axis].store(step[axis], kRelaxed);
}

AABB BodyLocation::PredictedBounds() const {
  AABB predicted = Bounds();
  const Vec3 step = Motion();
  // A jump (a teleport, a first placement) says nothing about the next move; a body's own size bounds what a
  // steady move adds, so a slot grows to at most a few times the body.
  if (step.isZero(0.0f) || (step.cwiseAbs().array() > predicted.Size().array()).any()) return predicted;
  const Vec3 ahead = kPredictedMoves * step;
  predicted.Encapsulate(AABB(predicted.min + ahead, predicted.max + ahead));
  // A move is never quite the last one again (a body on the ground swings its swept bounds up and down by a
  // step's fall): some room all round, in proportion to the move.
  const Vec3 room = Vec3::Constant(kRoomPerMove * step.norm());
  return AABB(predicted.min - room, predicted.max + room);
}

std::uint32_t QuadTree::MakeEmptyNode(std::uint32_t parent) {
  const std::uint32_t index = pool_.Allocate();
  QuadTreeNode& fresh = node(index);
  for (int slot = 0; slot < 4; ++slot) {
    fresh.min_x[slot].store(kLargeFloat, kRelaxed), fresh.min_y[slot].store(kLargeFloat, kRelaxed);
    fresh.min_z[slot].store(kLargeFloat, kRelaxed), fresh.max_x[slot].store(-kLargeFloat, kRelaxed);
    fresh.max_y[slot].store(-kLargeFloat, kRelaxed), fresh.max_z[slot].store(-kLargeFloat, kRelaxed);
    fresh.children[slot].store(kInvalid, kRelaxed);
  }
  fresh.parent.store(parent, kRelaxed);
  fresh.changed.store(0, kRelaxed);
  fresh.linked.store(0, kRelaxed);
  return index;
}

void QuadTree::SetParent(std::uint32_t entry, std::uint32_t parent, std::uint32_t slot) {
  if (entry & kBodyTag) {
    BodyLocation& location = locations_[entry & ~kBodyTag];
    location.node.store(parent, std::memory_order_release);
    location.slot.store(static_cast<std::uint8_t>(slot), kRelaxed);
    location.tree.store(tree_index_, kRelaxed);
  } else {
    node(entry).parent.store(parent, std::memory_order_release);
  }
}

void QuadTree::WriteSlot(std::uint32_t node_index, std::uint32_t slot, std::uint32_t entry,
                         const AABB& bounds) {
  QuadTreeNode& target = node(node_index);
  target.children[slot].store(entry, std::memory_order_release);
  // Max before min: the slot stays inside out (invisible) until the last min lands.
  target.max_x[slot].store(bounds.max.x(), kRelaxed), target.max_y[slot].store(bounds.max.y(), kRelaxed);
  target.max_z[slot].store(bounds.max.z(), kRelaxed);
  target.min_x[slot].store(bounds.min.x(), kRelaxed), target.min_y[slot].store(bounds.min.y(), kRelaxed);
  target.min_z[slot].store(bounds.min.z(), std::memory_order_release);
}

std::uint32_t QuadTree::Build(std::span<Item> items, std::uint32_t parent, std::uint32_t& nodes_used) {
  const std::uint32_t index = MakeEmptyNode(parent);
  ++nodes_used;
  // Four groups: halve the items, then halve each half; small sets get one slot per item.
  std::span<Item> groups[4];
  int group_count = 0;
  if (items.size() <= 4) {
    for (std::size_t i = 0; i < items.size(); ++i) groups[group_count++] = items.subspan(i, 1);
  } else {
    const std::size_t half = SplitInTwo(items);
    for (std::span<Item> part : {items.first(half), items.subspan(half)}) {
      if (part.size() == 1) {
        groups[group_count++] = part;
        continue;
      }
      const std::size_t quarter = SplitInTwo(part);
      groups[group_count++] = part.first(quarter);
      groups[group_count++] = part.subspan(quarter);
    }
  }
  for (int slot = 0; slot < group_count; ++slot) {
    const std::span<Item> group = groups[slot];
    const std::uint32_t entry = group.size() == 1 ? group[0].entry : Build(group, index, nodes_used);
    SetParent(entry, index, static_cast<std::uint32_t>(slot));
    WriteSlot(index, static_cast<std::uint32_t>(slot), entry, Union(group));
  }
  return index;
}

std::uint32_t QuadTree::FreeSubtree(std::uint32_t entry) {
  if (entry & kBodyTag || entry == kInvalid) return 0;
  std::uint32_t freed = 0;
  std::vector<std::uint32_t> stack{entry};
  while (!stack.empty()) {
    const std::uint32_t current = stack.back();
    stack.pop_back();
    for (const auto& child : node(current).children) {
      const std::uint32_t c = child.load(kRelaxed);
      if (c != kInvalid && !(c & kBodyTag)) stack.push_back(c);
    }
    pool_.Free(current);
    ++freed;
  }
  return freed;
}

void QuadTree::CollectBodies(std::uint32_t entry, std::vector<std::uint32_t>& bodies) const {
  std::vector<std::uint32_t> stack{entry};
  while (!stack.empty()) {
    const std::uint32_t current = stack.back();
    stack.pop_back();
    if (current == kInvalid) continue;
    if (current & kBodyTag) {
      bodies.push_back(current & ~kBodyTag);
      continue;
    }
    for (const auto& child : node(current).children) stack.push_back(child.load(kRelaxed));
  }
}

bool QuadTree::Link(TreeGenerations& generations, std::uint32_t entry, const AABB& bounds) {
  std::atomic<std::uint32_t>& root_slot = generations.CurrentRootSlot(tree_index_);
  std::uint32_t spare_node = kInvalid;
  for (;;) {
    const std::uint32_t root = root_slot.load(std::memory_order_acquire);
    QuadTreeNode& top = node(root);
    for (std::uint32_t slot = 0; slot < 4; ++slot) {
      std::uint32_t expected = kInvalid;
      if (!top.children[slot].compare_exchange_strong(expected, entry, std::memory_order_acq_rel)) continue;
      SetParent(entry, root, slot);
      WriteSlot(root, slot, entry, bounds);
      MarkChangedUpwards(root);
      if (spare_node == kInvalid) return false;
      pool_.Free(spare_node);  // a new root lost its race, then a slot freed up
      return true;
    }
    // The root is full: a new root whose first child is the old root with bounds that always pass.
    if (spare_node == kInvalid) spare_node = pool_.Allocate();
    QuadTreeNode& fresh = node(spare_node);
    for (std::uint32_t slot = 0; slot < 4; ++slot) {
      fresh.min_x[slot].store(kLargeFloat, kRelaxed), fresh.min_y[slot].store(kLargeFloat, kRelaxed);
      fresh.min_z[slot].store(kLargeFloat, kRelaxed), fresh.max_x[slot].store(-kLargeFloat, kRelaxed);
      fresh.max_y[slot].store(-kLargeFloat, kRelaxed), fresh.max_z[slot].store(-kLargeFloat, kRelaxed);
      fresh.children[slot].store(kInvalid, kRelaxed);
    }
    WriteSlot(spare_node, 0, root, AABB(Vec3::Constant(-kLargeFloat), Vec3::Constant(kLargeFloat)));
    WriteSlot(spare_node, 1, entry, bounds);
    fresh.parent.store(kNoParent, kRelaxed);
    // Born changed, so the next rebuild folds the old root back in.
    fresh.changed.store(1, kRelaxed);
    std::uint32_t expected = root;
    if (root_slot.compare_exchange_strong(expected, spare_node, std::memory_order_acq_rel)) {
      top.parent.store(spare_node, std::memory_order_release);
      SetParent(entry, spare_node, 1);
      return true;
    }
  }
}

std::uint32_t QuadTree::Depth(std::uint32_t root) const {
  std::uint32_t deepest = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{root, 1}};
  while (!stack.empty()) {
    const auto [current, depth] = stack.back();
    stack.pop_back();
    for (const auto& child : node(current).children) {
      const std::uint32_t c = child.load(std::memory_order_acquire);
      if (c == kInvalid) continue;
      if (c & kBodyTag)
        deepest = std::max(deepest, depth);
      else
        stack.push_back({c, depth + 1});
    }
  }
  return deepest;
}

bool QuadTree::IsLinked(std::uint32_t body_index) const {
  const std::uint32_t holder = locations_[body_index].node.load(std::memory_order_acquire);
  if (holder == kInvalid) return false;
  std::atomic<std::uint32_t>& linked = pool_.Get(holder).linked;
  if (linked.load(std::memory_order_acquire) != 0) return true;
  for (std::uint32_t current = holder;;) {
    const std::uint32_t parent = node(current).parent.load(std::memory_order_acquire);
    if (parent == kUnlinked) return false;
    if (parent == kNoParent) break;
    current = parent;
  }
  linked.store(1, std::memory_order_release);  // a cache of the walk's answer: the next check is one load
  return true;
}

bool QuadTree::SlotCovers(const QuadTreeNode& holder, int slot, const AABB& bounds) {
  return holder.min_x[slot].load(kRelaxed) <= bounds.min.x() &&
         holder.min_y[slot].load(kRelaxed) <= bounds.min.y() &&
         holder.min_z[slot].load(kRelaxed) <= bounds.min.z() &&
         holder.max_x[slot].load(kRelaxed) >= bounds.max.x() &&
         holder.max_y[slot].load(kRelaxed) >= bounds.max.y() &&
         holder.max_z[slot].load(kRelaxed) >= bounds.max.z();
}

int QuadTree::SlotOf(const QuadTreeNode& parent, std::uint32_t child) {
  for (int slot = 0; slot < 4; ++slot)
    if (parent.children[slot].load(kRelaxed) == child) return slot;
  return -1;
}

void QuadTree::Widen(std::uint32_t body_index, const AABB& bounds) {
  BodyLocation& location = locations_[body_index];
  location.SetMotion(bounds.Center() - location.Bounds().Center());
  location.SetBounds(bounds);
  std::uint32_t child = kBodyTag | body_index;
  std::uint32_t current = location.node.load(std::memory_order_acquire);
  int slot = location.slot.load(kRelaxed);
  if (current == kNoParent || current == kUnlinked || SlotCovers(node(current), slot, bounds)) return;
  while (current != kNoParent && current != kUnlinked) {
    QuadTreeNode& target = node(current);
    if (slot < 0) slot = SlotOf(target, child);
    assert(slot >= 0);
    AtomicMin(target.min_x[slot], bounds.min.x()), AtomicMin(target.min_y[slot], bounds.min.y());
    AtomicMin(target.min_z[slot], bounds.min.z()), AtomicMax(target.max_x[slot], bounds.max.x());
    AtomicMax(target.max_y[slot], bounds.max.y()), AtomicMax(target.max_z[slot], bounds.max.z());
    // Read first: most moves find their ancestors already marked and write nothing shared.
    if (target.changed.load(kRelaxed) == 0) target.changed.store(1, kRelaxed);
    child = current;
    current = target.parent.load(std::memory_order_acquire);
    slot = -1;
  }
}

void QuadTree::Remove(std::uint32_t body_index) {
  BodyLocation& location = locations_[body_index];
  const std::uint32_t holder = location.node.load(std::memory_order_acquire);
  const int slot = location.slot.load(kRelaxed);
  QuadTreeNode& target = node(holder);
  // Min to +1e30 first: from the first store on, the slot is inside out and no query enters it.
  target.min_x[slot].store(kLargeFloat, kRelaxed), target.min_y[slot].store(kLargeFloat, kRelaxed);
  target.min_z[slot].store(kLargeFloat, kRelaxed);
  target.max_x[slot].store(-kLargeFloat, kRelaxed), target.max_y[slot].store(-kLargeFloat, kRelaxed);
  target.max_z[slot].store(-kLargeFloat, kRelaxed);
  target.children[slot].store(kInvalid, std::memory_order_release);
  location.node.store(kInvalid, std::memory_order_release);
  MarkChangedUpwards(holder);
}

void QuadTree::MarkChangedUpwards(std::uint32_t node_index) {
  std::uint32_t current = node_index;
  while (current != kNoParent && current != kUnlinked) {
    QuadTreeNode& target = node(current);
    if (target.changed.load(kRelaxed) == 0) target.changed.store(1, kRelaxed);
    current = target.parent.load(std::memory_order_acquire);
  }
}

AABB QuadTree::NodeBounds(std::uint32_t node_index) const {
  AABB bounds;
  const QuadTreeNode& source = node(node_index);
  for (int slot = 0; slot < 4; ++slot)
    if (source.children[slot].load(kRelaxed) != kInvalid) bounds.Encapsulate(SlotBounds(source, slot));
  return bounds;
}

bool QuadTree::CollectForRebuild(std::uint32_t root, bool full, std::vector<Item>& items,
                                 std::vector<std::uint32_t>& dropped,
                                 std::vector<std::uint32_t>& stack) const {
  if (!full && node(root).changed.load(kRelaxed) == 0) return false;
  // Bodies of changed nodes come with their predicted bounds; unchanged subtrees are kept whole.
  stack.assign(1, root);
  while (!stack.empty()) {
    const std::uint32_t current = stack.back();
    stack.pop_back();
    dropped.push_back(current);
    const QuadTreeNode& source = node(current);
    for (int slot = 0; slot < 4; ++slot) {
      const std::uint32_t child = source.children[slot].load(kRelaxed);
      if (child == kInvalid) continue;
      if (child & kBodyTag) {
        items.push_back({child, locations_[child & ~kBodyTag].PredictedBounds()});
      } else if (full || node(child).changed.load(kRelaxed) != 0) {
        stack.push_back(child);
      } else if (const AABB bounds = NodeBounds(child); !bounds.IsEmpty()) {
        items.push_back({child, bounds});
      } else {
        dropped.push_back(child);
      }
    }
  }
  return true;
}

std::uint32_t QuadTree::BuildRoot(std::span<Item> items, std::uint32_t& nodes_used) {
  if (items.empty()) {
    ++nodes_used;
    return MakeEmptyNode(kNoParent);
  }
  return Build(items, kNoParent, nodes_used);
}

}  // namespace strata
