// QuadTree: one broad-phase layer's bounding-volume tree with 4 children per node, after the Jolt Physics
// broad phase (Rouwe, GDC). Queries read it lock-free at any time; Widen, Remove and Link run concurrently
// with queries and with each other; Rebuild needs the other writers kept out (QuadTreeBroadPhase does).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "physics/broadphase/TreeGenerations.h"
#include "physics/core/FixedSizeFreeList.h"
#include "physics/math/AABB.h"
#include "physics/math/Overlap4.h"

namespace strata {

/// A tree node: the bounds of its 4 children laid out for a 4-wide test, the children, and the parent.
/// Empty children are inside out at +/-1e30 so no query enters them.
struct alignas(64) QuadTreeNode {
  std::array<std::atomic<float>, 4> min_x, min_y, min_z, max_x, max_y, max_z;
  std::array<std::atomic<std::uint32_t>, 4> children;  // node index, kBodyTag | body index, or kInvalid
  std::atomic<std::uint32_t> parent;                   // node index, kNoParent (root) or kUnlinked
  std::atomic<std::uint32_t> changed;                  // something below moved, came or went since the build
  // Seen to lead up to a linked root (once linked, a node stays linked until it is freed): presence checks
  // then skip the walk up.
  std::atomic<std::uint32_t> linked;
};

/// Where a body sits and what a query needs to report it; one per body index, shared by all trees.
struct BodyLocation {
  std::atomic<std::uint32_t> node{0xffffffffu};  // node holding the body, kInvalid while unlinked
  std::atomic<std::uint8_t> slot{0};
  std::atomic<std::uint8_t> tree{0};
  std::atomic<std::uint8_t> claimed{0};  // 1 from AddBodiesPrepare until removal
  std::atomic<std::uint16_t> layer{0};
  std::atomic<std::uint32_t> generation{0};
  std::array<std::atomic<float>, 6> bounds;  // exact bounds: min x, y, z, max x, y, z
  // How far the bounds' centre went on the last update: a rebuild sizes the slot for a few more such moves.
  std::array<std::atomic<float>, 3> motion;

  AABB Bounds() const;
  void SetBounds(const AABB& box);
  Vec3 Motion() const;
  void SetMotion(const Vec3& step);
  /// The exact bounds swept over the next kPredictedMoves moves like the last, with kRoomPerMove times the
  /// move's length all round; the exact bounds alone when the last move was a jump (longer than the body).
  AABB PredictedBounds() const;
  static constexpr float kPredictedMoves = 3.0f;
  static constexpr float kRoomPerMove = 0.5f;
};

using QuadTreeNodePool = FixedSizeFreeList<QuadTreeNode>;

/// The algorithms over one tree; the nodes live in a pool and the roots in TreeGenerations, both shared
/// with the other layers' trees.
class QuadTree {
 public:
  static constexpr std::uint32_t kInvalid = 0xffffffffu;
  static constexpr std::uint32_t kNoParent = 0xffffffffu;
  static constexpr std::uint32_t kUnlinked = 0xfffffffeu;
  static constexpr std::uint32_t kBodyTag = 0x80000000u;

  /// Something to build a tree over: a body (kBodyTag | index) or a kept node, with its bounds.
  struct Item {
    std::uint32_t entry;
    AABB bounds;
  };

  QuadTree(QuadTreeNodePool& pool, std::vector<BodyLocation>& locations, std::uint8_t tree_index)
      : pool_(pool), locations_(locations), tree_index_(tree_index) {}

  /// Upper bound of the nodes Build uses for `item_count` items (reserve them first).
  static std::uint32_t NodesToBuild(std::size_t item_count) {
    return static_cast<std::uint32_t>(std::max<std::size_t>(item_count, 1));
  }
  /// A node with no children (from a reservation).
  std::uint32_t MakeEmptyNode(std::uint32_t parent);
  /// Builds nodes over `items` (from a reservation), splitting at the middle of the longest axis of their
  /// centres, twice per level. Points the items at their new parents. Returns the top node and adds the
  /// number of nodes it took to `nodes_used`.
  std::uint32_t Build(std::span<Item> items, std::uint32_t parent, std::uint32_t& nodes_used);
  /// Frees the nodes of an unlinked subtree and returns how many it freed.
  std::uint32_t FreeSubtree(std::uint32_t entry);
  /// Bodies in an unlinked subtree (for abort).
  void CollectBodies(std::uint32_t entry, std::vector<std::uint32_t>& bodies) const;

  /// Links `entry` (a body or an unlinked subtree) under the current root: a free root slot claimed with
  /// compare-exchange, else a new root swapped in with compare-exchange. The caller reserves one node for
  /// that new root; returns false when the reservation was not touched (give it back).
  bool Link(TreeGenerations& generations, std::uint32_t entry, const AABB& bounds);

  /// True when the body's location leads up to a linked root (a walk up the first time its node is asked).
  bool IsLinked(std::uint32_t body_index) const;
  /// Grows the body's slot and every ancestor's to cover `bounds` (atomic min/max) and marks them changed.
  /// Records the move for the next rebuild, which sizes the slot for a few more like it (BodyLocation::
  /// PredictedBounds): a body in steady motion then stays inside its slot for several steps, as a resting one
  /// does, and the tree needs no rebuild for it. Bounds within the body's slot stop there: the ancestors
  /// already cover the slot (each earlier growth of it went all the way up, and a rebuild makes parents the
  /// union of their children), so a body moving within its slot writes nothing shared and asks for no
  /// rebuild.
  void Widen(std::uint32_t body_index, const AABB& bounds);
  /// Empties the body's slot (bounds inside out first, so no query sees it after this returns).
  void Remove(std::uint32_t body_index);

  /// First half of a rebuild: the items to rebuild `root` from (bodies of changed nodes with their predicted
  /// bounds, unchanged subtrees whole; everything when `full`) and the nodes the new tree drops. False
  /// (nothing collected) when nothing under `root` changed. `stack` is scratch.
  bool CollectForRebuild(std::uint32_t root, bool full, std::vector<Item>& items,
                         std::vector<std::uint32_t>& dropped, std::vector<std::uint32_t>& stack) const;
  /// Second half: a new root over `items` (an empty root for none), from a reservation of
  /// NodesToBuild(items.size()) nodes.
  std::uint32_t BuildRoot(std::span<Item> items, std::uint32_t& nodes_used);

  /// Visits the bodies under `root` whose slot passes `test`, which marks the children to enter in a
  /// 4-bit mask. A test taking `(bounds, float* distance)` also writes each one's distance, and nearer
  /// children are entered first; an overlap test takes `(bounds)` alone, and its children are entered in
  /// slot order at distance 0, without the sort. `visit(body_index, distance)` returns false to stop.
  template <class ChildTest, class BodyVisitor>
  void Walk(std::uint32_t root, ChildTest&& test, BodyVisitor&& visit) const;
  /// Walk with an overlap test against `box`, in the same order, for the broad phase's most frequent query
  /// (every active body's pairs, every step): the box is loaded once, and children are pushed without a
  /// branch per child. `visit(body_index, 0.0f)` returns false to stop.
  template <class BodyVisitor>
  void WalkOverlapping(std::uint32_t root, const AABB& box, BodyVisitor&& visit) const;

  /// The bounds of one node's 4 children, loaded for a 4-wide test.
  struct ChildBounds {
    alignas(16) float min_x[4], min_y[4], min_z[4], max_x[4], max_y[4], max_z[4];
  };

  /// Nodes on the longest path from `root` down to a body (for stats; walks the whole tree).
  std::uint32_t Depth(std::uint32_t root) const;

  const QuadTreeNode& node(std::uint32_t index) const { return pool_.Get(index); }
  std::uint8_t tree_index() const { return tree_index_; }

 private:
  QuadTreeNode& node(std::uint32_t index) { return pool_.Get(index); }
  void SetParent(std::uint32_t entry, std::uint32_t parent, std::uint32_t slot);
  void WriteSlot(std::uint32_t node_index, std::uint32_t slot, std::uint32_t entry, const AABB& bounds);
  void MarkChangedUpwards(std::uint32_t node_index);
  AABB NodeBounds(std::uint32_t node_index) const;
  static int SlotOf(const QuadTreeNode& parent, std::uint32_t child);
  // Whether a body's slot already holds `bounds` (then so does every ancestor).
  static bool SlotCovers(const QuadTreeNode& holder, int slot, const AABB& bounds);

  QuadTreeNodePool& pool_;
  std::vector<BodyLocation>& locations_;
  std::uint8_t tree_index_;
};

/// Loads a node's child bounds with relaxed atomic reads (inline: every step of every walk runs it).
inline QuadTree::ChildBounds LoadChildBounds(const QuadTreeNode& node) {
  QuadTree::ChildBounds b;
#if defined(__SSE2__) && !defined(__SANITIZE_THREAD__)
  // An atomic float has a float's layout, and the four of a bound sit side by side, 16-byte aligned: one
  // load each (on x86 each float in it is still read whole, as by a relaxed load). The ThreadSanitizer build
  // keeps the atomic loads it can see.
  static_assert(sizeof(std::atomic<float>) == sizeof(float) && alignof(QuadTreeNode) % 16 == 0);
  auto load = [](const std::array<std::atomic<float>, 4>& values, float* out) {
    _mm_store_ps(out, _mm_load_ps(reinterpret_cast<const float*>(values.data())));
  };
  load(node.min_x, b.min_x), load(node.min_y, b.min_y), load(node.min_z, b.min_z);
  load(node.max_x, b.max_x), load(node.max_y, b.max_y), load(node.max_z, b.max_z);
#else
  for (int i = 0; i < 4; ++i) {
    b.min_x[i] = node.min_x[i].load(std::memory_order_relaxed);
    b.min_y[i] = node.min_y[i].load(std::memory_order_relaxed);
    b.min_z[i] = node.min_z[i].load(std::memory_order_relaxed);
    b.max_x[i] = node.max_x[i].load(std::memory_order_relaxed);
    b.max_y[i] = node.max_y[i].load(std::memory_order_relaxed);
    b.max_z[i] = node.max_z[i].load(std::memory_order_relaxed);
  }
#endif
  return b;
}

template <class BodyVisitor>
void QuadTree::WalkOverlapping(std::uint32_t root, const AABB& box, BodyVisitor&& visit) const {
  if (root == kInvalid) return;
  // Up to 3 entries stay per level and a degraded tree can be deep: grow past the inline stack.
  std::array<std::uint32_t, 128> inline_stack;
  std::vector<std::uint32_t> overflow;
  std::uint32_t* stack = inline_stack.data();
  std::size_t capacity = inline_stack.size();
  std::size_t size = 0;
  stack[size++] = root;
  while (size > 0) {
    const std::uint32_t entry = stack[--size];
    if (entry & kBodyTag) {
      if (!visit(entry & ~kBodyTag, 0.0f)) return;
      continue;
    }
    const QuadTreeNode& current = node(entry);
    const ChildBounds bounds = LoadChildBounds(current);
    const int mask =
        OverlapMask4(bounds.min_x, bounds.min_y, bounds.min_z, bounds.max_x, bounds.max_y, bounds.max_z, box);
    if (mask == 0) continue;
    if (size + 4 > capacity) {
      if (overflow.empty()) overflow.assign(inline_stack.begin(), inline_stack.begin() + size);
      overflow.resize(2 * capacity);
      stack = overflow.data();
      capacity = overflow.size();
    }
    // Last slot first, so slot 0 is entered first (Walk's order). A slot being emptied may still show its
    // old bounds with no child: it is written but not kept.
    for (int slot = 3; slot >= 0; --slot) {
      const std::uint32_t child = current.children[slot].load(std::memory_order_acquire);
      stack[size] = child;
      size += static_cast<std::size_t>(((mask >> slot) & 1) != 0 && child != kInvalid);
    }
  }
}

template <class ChildTest, class BodyVisitor>
void QuadTree::Walk(std::uint32_t root, ChildTest&& test, BodyVisitor&& visit) const {
  if (root == kInvalid) return;
  // A degraded tree (many single adds before a rebuild) can be deep: grow past the inline stack.
  struct Entry {
    std::uint32_t entry;
    float distance;
  };
  std::array<Entry, 128> inline_stack;
  std::vector<Entry> overflow;
  std::size_t size = 0;
  auto push = [&](Entry e) {
    if (size < inline_stack.size()) {
      inline_stack[size++] = e;
    } else {
      overflow.push_back(e);
      ++size;
    }
  };
  auto pop = [&]() -> Entry {
    --size;
    if (size >= inline_stack.size()) {
      const Entry e = overflow.back();
      overflow.pop_back();
      return e;
    }
    return inline_stack[size];
  };
  push({root, 0.0f});
  while (size > 0) {
    const Entry top = pop();
    if (top.entry & kBodyTag) {
      if (!visit(top.entry & ~kBodyTag, top.distance)) return;
      continue;
    }
    const QuadTreeNode& current = node(top.entry);
    const ChildBounds bounds = LoadChildBounds(current);
    constexpr bool kNearestFirst = std::is_invocable_v<ChildTest&, const ChildBounds&, float*>;
    float distance[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    int mask = 0;
    if constexpr (kNearestFirst)
      mask = test(bounds, distance);
    else
      mask = test(bounds);
    if (mask == 0) continue;
    std::uint32_t children[4];
    int order[4];
    int count = 0;
    for (int i = 0; i < 4; ++i) {
      if (!(mask & (1 << i))) continue;
      children[i] = current.children[i].load(std::memory_order_acquire);
      if (children[i] == kInvalid) continue;
      order[count++] = i;
    }
    // Push the farthest first so the nearest is entered first (a ray's early out then prunes the rest).
    if constexpr (kNearestFirst)
      for (int i = 1; i < count; ++i)
        for (int j = i; j > 0 && distance[order[j]] > distance[order[j - 1]]; --j)
          std::swap(order[j], order[j - 1]);
    for (int i = 0; i < count; ++i) push({children[order[i]], distance[order[i]]});
  }
}

}  // namespace strata
