#include "physics/broadphase/BruteForceBroadPhase.h"

#include <cassert>
#include <cstring>
#include <mutex>

namespace strata {

BruteForceBroadPhase::BruteForceBroadPhase(std::uint32_t capacity) : dense_of_index_(capacity, kAbsent) {}

void BruteForceBroadPhase::AddBody(BodyID id, const AABB& bounds, ObjectLayer layer) {
  std::unique_lock lock(mutex_);
  assert(dense_of_index_[id.index] == kAbsent);
  dense_of_index_[id.index] = static_cast<std::uint32_t>(ids_.size());
  ids_.push_back(id);
  layers_.push_back(layer);
  min_x_.push_back(bounds.min.x()), min_y_.push_back(bounds.min.y()), min_z_.push_back(bounds.min.z());
  max_x_.push_back(bounds.max.x()), max_y_.push_back(bounds.max.y()), max_z_.push_back(bounds.max.z());
}

void BruteForceBroadPhase::RemoveBody(BodyID id) {
  std::unique_lock lock(mutex_);
  const std::uint32_t slot = dense_of_index_[id.index];
  assert(slot != kAbsent);
  const std::uint32_t last = static_cast<std::uint32_t>(ids_.size()) - 1;
  // Swap-remove keeps the arrays dense.
  auto move_last = [&](auto& array) {
    array[slot] = array[last];
    array.pop_back();
  };
  dense_of_index_[ids_[last].index] = slot;
  dense_of_index_[id.index] = kAbsent;
  move_last(ids_), move_last(layers_);
  move_last(min_x_), move_last(min_y_), move_last(min_z_), move_last(max_x_), move_last(max_y_),
      move_last(max_z_);
}

void BruteForceBroadPhase::UpdateBody(BodyID id, const AABB& bounds) {
  std::unique_lock lock(mutex_);
  const std::uint32_t slot = dense_of_index_[id.index];
  assert(slot != kAbsent);
  min_x_[slot] = bounds.min.x(), min_y_[slot] = bounds.min.y(), min_z_[slot] = bounds.min.z();
  max_x_[slot] = bounds.max.x(), max_y_[slot] = bounds.max.y(), max_z_[slot] = bounds.max.z();
}

std::size_t BruteForceBroadPhase::body_count() const {
  std::shared_lock lock(mutex_);
  return ids_.size();
}

void BruteForceBroadPhase::FindPairs(std::span<const BodyID> active,
                                     std::span<const std::uint8_t> active_flags, const LayerSetup& layers,
                                     std::vector<BodyPair>& out) const {
  std::shared_lock lock(mutex_);
  const std::size_t n = ids_.size();
  for (const BodyID a : active) {
    const std::uint32_t s = dense_of_index_[a.index];
    if (s == kAbsent) continue;
    const float ax0 = min_x_[s], ay0 = min_y_[s], az0 = min_z_[s], ax1 = max_x_[s], ay1 = max_y_[s],
                az1 = max_z_[s];
    // Test a block of bounds with a branch-free loop the compiler vectorizes, then visit only the hits.
    constexpr std::size_t kBlock = 64;
    std::uint8_t hits[kBlock];
    for (std::size_t start = 0; start < n; start += kBlock) {
      const std::size_t count = std::min(kBlock, n - start);
      const float* x0 = &min_x_[start];
      const float* y0 = &min_y_[start];
      const float* z0 = &min_z_[start];
      const float* x1 = &max_x_[start];
      const float* y1 = &max_y_[start];
      const float* z1 = &max_z_[start];
      for (std::size_t k = 0; k < count; ++k)
        hits[k] = (ax0 <= x1[k]) & (x0[k] <= ax1) & (ay0 <= y1[k]) & (y0[k] <= ay1) & (az0 <= z1[k]) &
                  (z0[k] <= az1);
      for (std::size_t k = count; k < kBlock; ++k) hits[k] = 0;
      // Hits are rare: skip eight misses at a time.
      for (std::size_t word = 0; word < kBlock; word += 8) {
        std::uint64_t eight;
        std::memcpy(&eight, hits + word, sizeof(eight));
        if (eight == 0) continue;
        for (std::size_t k = word; k < word + 8; ++k) {
          const std::size_t j = start + k;
          if (!hits[k] || j == s) continue;
          const BodyID b = ids_[j];
          if (active_flags[b.index] && b.index < a.index) continue;  // reported from b's side
          if (!layers.ShouldCollide(layers_[s], layers_[j])) continue;
          out.push_back({a, b});
        }
      }
    }
  }
}

void BruteForceBroadPhase::CollideAABB(const AABB& box, const QueryFilter& filter,
                                       std::vector<BodyID>& out) const {
  std::shared_lock lock(mutex_);
  for (std::size_t j = 0; j < ids_.size(); ++j) {
    const bool overlap = box.min.x() <= max_x_[j] && min_x_[j] <= box.max.x() && box.min.y() <= max_y_[j] &&
                         min_y_[j] <= box.max.y() && box.min.z() <= max_z_[j] && min_z_[j] <= box.max.z();
    if (overlap && filter.AcceptsLayer(layers_[j]) && ids_[j].index != filter.ignore_body_index)
      out.push_back(ids_[j]);
  }
}

void BruteForceBroadPhase::CastRay(const Vec3& origin, const Vec3& direction, float max_fraction,
                                   const QueryFilter& filter, std::vector<BroadPhaseRayHit>& out) const {
  std::shared_lock lock(mutex_);
  const Vec3 inverse = SafeInverse(direction);
  for (std::size_t j = 0; j < ids_.size(); ++j) {
    if (!filter.AcceptsLayer(layers_[j]) || ids_[j].index == filter.ignore_body_index) continue;
    const AABB bounds({min_x_[j], min_y_[j], min_z_[j]}, {max_x_[j], max_y_[j], max_z_[j]});
    const float entry = bounds.RayEntry(origin, inverse, max_fraction);
    if (entry >= 0.0f) out.push_back({ids_[j], entry});
  }
}

}  // namespace strata
