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
};

struct ContactKeyHash {
  std::size_t operator()(const ContactKey& key) const noexcept {
    std::size_t h = std::hash<BodyID>()(key.a);
    h ^= std::hash<BodyID>()(key.b) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= key.sub_shape_b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    return h;
  }
};

/// Accumulated impulses of one manifold, with each point's position in body A's local frame.
struct CachedManifold {
  int count = 0;
  Vec3 local_point_a[ContactManifold::kMaxPoints];
  float normal_impulse[ContactManifold::kMaxPoints];
  Vec3 friction_impulse[ContactManifold::kMaxPoints];  ///< world space, so new tangent bases can reuse it
};

/// Last step's and this step's impulses.
class ContactCache {
 public:
  /// Makes this step's entries the previous ones and starts an empty current map.
  void BeginStep() {
    std::swap(previous_, current_);
    current_.clear();
  }
  const CachedManifold* FindPrevious(const ContactKey& key) const {
    const auto it = previous_.find(key);
    return it == previous_.end() ? nullptr : &it->second;
  }
  void Store(const ContactKey& key, const CachedManifold& manifold) { current_[key] = manifold; }
  std::size_t size() const { return current_.size(); }
  void Clear() {
    previous_.clear();
    current_.clear();
  }

 private:
  std::unordered_map<ContactKey, CachedManifold, ContactKeyHash> previous_;
  std::unordered_map<ContactKey, CachedManifold, ContactKeyHash> current_;
};

}  // namespace strata
