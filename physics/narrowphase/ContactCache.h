// ContactCache: impulses of last step's contacts, keyed by body pair and sub-shape, so this step's
// solver starts from them (warm starting). Double-buffered: the step reads last step's map while it
// writes this step's. Used only inside the step (single writer).
#pragma once

#include <unordered_map>

#include "physics/narrowphase/ContactManifold.h"

namespace strata {

/// Identifies a manifold across steps.
struct ContactKey {
  BodyID a;
  BodyID b;
  std::uint32_t sub_shape_b;
  friend bool operator==(const ContactKey&, const ContactKey&) = default;
  friend auto operator<=>(const ContactKey&, const ContactKey&) = default;
};

/// Accumulated impulses of one manifold, with each point's position in body A's local frame.
struct CachedManifold {
  int count = 0;
  Vec3 local_point_a[ContactManifold::kMaxPoints];
  float normal_impulse[ContactManifold::kMaxPoints];
  Vec3 friction_impulse[ContactManifold::kMaxPoints];  ///< world space, so new tangent bases can reuse it
};

/// Last step's and this step's impulses, as key-sorted arrays: the step stores manifolds in pair order,
/// so the arrays come out sorted and a lookup is a binary search with no hashing or node allocation.
class ContactCache {
 public:
  /// Makes this step's entries the previous ones and starts an empty current list.
  void BeginStep() {
    std::swap(previous_, current_);
    current_.clear();
    if (!std::is_sorted(previous_.begin(), previous_.end(), KeyLess))
      std::sort(previous_.begin(), previous_.end(), KeyLess);
  }
  const CachedManifold* FindPrevious(const ContactKey& key) const {
    const auto it = std::lower_bound(previous_.begin(), previous_.end(), key,
                                     [](const Entry& entry, const ContactKey& k) { return entry.key < k; });
    return it != previous_.end() && it->key == key ? &it->manifold : nullptr;
  }
  void Store(const ContactKey& key, const CachedManifold& manifold) { current_.push_back({key, manifold}); }

 private:
  struct Entry {
    ContactKey key;
    CachedManifold manifold;
  };
  static bool KeyLess(const Entry& a, const Entry& b) { return a.key < b.key; }

  std::vector<Entry> previous_;
  std::vector<Entry> current_;
};

}  // namespace strata
