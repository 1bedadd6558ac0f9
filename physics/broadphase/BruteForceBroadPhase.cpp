#include "physics/broadphase/BruteForceBroadPhase.h"

#include <cassert>
#include <cstring>
#include <mutex>
#include <string>

namespace strata {

struct BruteForceBroadPhase::PreparedBatch final : AddBatch::State {
  std::vector<BodyID> ids;
  std::vector<AABB> bounds;
  std::vector<ObjectLayer> layers;
};

BruteForceBroadPhase::BruteForceBroadPhase(std::uint32_t capacity, std::shared_ptr<const LayerSetup> layers)
    : layers_(std::move(layers)), dense_of_index_(capacity, kAbsent), prepared_(capacity, 0) {}

std::uint32_t BruteForceBroadPhase::DenseSlot(BodyID id) const {
  if (id.IsInvalid() || id.index >= dense_of_index_.size()) return kAbsent;
  const std::uint32_t slot = dense_of_index_[id.index];
  return slot != kAbsent && ids_[slot] == id ? slot : kAbsent;
}

void BruteForceBroadPhase::Insert(BodyID id, const AABB& bounds, ObjectLayer layer) {
  dense_of_index_[id.index] = static_cast<std::uint32_t>(ids_.size());
  ids_.push_back(id);
  layers_of_.push_back(layer);
  min_x_.push_back(bounds.min.x()), min_y_.push_back(bounds.min.y()), min_z_.push_back(bounds.min.z());
  max_x_.push_back(bounds.max.x()), max_y_.push_back(bounds.max.y()), max_z_.push_back(bounds.max.z());
}

Result<AddBatch> BruteForceBroadPhase::AddBodiesPrepare(std::span<const BodyID> ids,
                                                        std::span<const AABB> bounds,
                                                        std::span<const ObjectLayer> layers) {
  if (Status valid = CheckAddBatch(ids, bounds, layers, layers_->ObjectLayerCount()); !valid)
    return valid.error();
  std::unique_lock lock(mutex_);
  for (const BodyID id : ids) {
    if (id.index >= dense_of_index_.size())
      return MakeError(ErrorCode::kStaleBodyId,
                       "body " + std::to_string(id.index) + " is outside the broad phase");
    if (dense_of_index_[id.index] != kAbsent || prepared_[id.index])
      return MakeError(ErrorCode::kInvalidState, "body " + std::to_string(id.index) +
                                                     " is already in the broad phase or a prepared batch");
  }
  for (const BodyID id : ids) prepared_[id.index] = 1;
  auto state = std::make_unique<PreparedBatch>();
  state->ids.assign(ids.begin(), ids.end());
  state->bounds.assign(bounds.begin(), bounds.end());
  state->layers.assign(layers.begin(), layers.end());
  return AddBatch(this, std::move(state), ids.size());
}

Status BruteForceBroadPhase::AddBodiesFinalize(AddBatch& batch) {
  if (batch.owner() != this)
    return MakeError(ErrorCode::kInvalidArgument, "batch belongs to another broad phase");
  if (!batch.prepared()) return MakeError(ErrorCode::kInvalidState, "batch was already finalized or aborted");
  const std::unique_ptr<AddBatch::State> taken = batch.TakeState();
  const auto& state = static_cast<const PreparedBatch&>(*taken);
  std::unique_lock lock(mutex_);
  for (std::size_t i = 0; i < state.ids.size(); ++i) {
    prepared_[state.ids[i].index] = 0;
    Insert(state.ids[i], state.bounds[i], state.layers[i]);
  }
  return Status::Ok();
}

void BruteForceBroadPhase::AddBodiesAbort(AddBatch& batch) {
  if (batch.owner() != this || !batch.prepared()) return;
  const std::unique_ptr<AddBatch::State> taken = batch.TakeState();
  std::unique_lock lock(mutex_);
  for (const BodyID id : static_cast<const PreparedBatch&>(*taken).ids) prepared_[id.index] = 0;
}

Status BruteForceBroadPhase::RemoveBodies(std::span<const BodyID> ids) {
  std::unique_lock lock(mutex_);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (DenseSlot(ids[i]) == kAbsent)
      return MakeError(ErrorCode::kInvalidState,
                       "body " + std::to_string(ids[i].index) + " is not in the broad phase");
    for (std::size_t j = 0; j < i; ++j)
      if (ids[j] == ids[i])
        return MakeError(ErrorCode::kInvalidState,
                         "body " + std::to_string(ids[i].index) + " is listed twice");
  }
  for (const BodyID id : ids) {
    const std::uint32_t slot = dense_of_index_[id.index];
    const std::uint32_t last = static_cast<std::uint32_t>(ids_.size()) - 1;
    // Swap-remove keeps the arrays dense.
    auto move_last = [&](auto& array) {
      array[slot] = array[last];
      array.pop_back();
    };
    dense_of_index_[ids_[last].index] = slot;
    dense_of_index_[id.index] = kAbsent;
    move_last(ids_), move_last(layers_of_);
    move_last(min_x_), move_last(min_y_), move_last(min_z_), move_last(max_x_), move_last(max_y_),
        move_last(max_z_);
  }
  return Status::Ok();
}

Status BruteForceBroadPhase::UpdateBody(BodyID id, const AABB& bounds) {
  if (Status valid = CheckBounds(bounds); !valid) return valid;
  std::unique_lock lock(mutex_);
  const std::uint32_t slot = DenseSlot(id);
  if (slot == kAbsent)
    return MakeError(ErrorCode::kInvalidState,
                     "body " + std::to_string(id.index) + " is not in the broad phase");
  min_x_[slot] = bounds.min.x(), min_y_[slot] = bounds.min.y(), min_z_[slot] = bounds.min.z();
  max_x_[slot] = bounds.max.x(), max_y_[slot] = bounds.max.y(), max_z_[slot] = bounds.max.z();
  return Status::Ok();
}

bool BruteForceBroadPhase::Contains(BodyID id) const {
  std::shared_lock lock(mutex_);
  return DenseSlot(id) != kAbsent;
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
          if (!layers.ShouldCollide(layers_of_[s], layers_of_[j])) continue;
          out.push_back({a, b});
        }
      }
    }
  }
}

template <class Visitor>
void BruteForceBroadPhase::ForEachAccepted(const QueryFilter& filter, Visitor&& visit) const {
  std::shared_lock lock(mutex_);
  for (std::size_t j = 0; j < ids_.size(); ++j)
    if (filter.AcceptsLayer(layers_of_[j]) && ids_[j].index != filter.ignore_body_index && !visit(j)) return;
}

void BruteForceBroadPhase::CollideAABB(const BroadPhasePin&, const AABB& box, const QueryFilter& filter,
                                       BroadPhaseCollector& collector) const {
  ForEachAccepted(filter, [&](std::size_t j) {
    if (const AABB bounds = BoundsAt(j); bounds.Overlaps(box)) collector.AddOverlap(ids_[j], bounds);
    return !collector.ShouldStop();
  });
}

void BruteForceBroadPhase::CollideSphere(const BroadPhasePin&, const Vec3& center, float radius,
                                         const QueryFilter& filter, BroadPhaseCollector& collector) const {
  ForEachAccepted(filter, [&](std::size_t j) {
    if (SquaredDistanceToBox(BoundsAt(j), center) <= radius * radius) collector.AddHit(ids_[j], 0.0f);
    return !collector.ShouldStop();
  });
}

void BruteForceBroadPhase::CastRay(const BroadPhasePin& pin, const Vec3& origin, const Vec3& direction,
                                   const QueryFilter& filter, BroadPhaseCollector& collector) const {
  CastAABB(pin, AABB(origin, origin), direction, filter, collector);
}

void BruteForceBroadPhase::CastAABB(const BroadPhasePin&, const AABB& box, const Vec3& displacement,
                                    const QueryFilter& filter, BroadPhaseCollector& collector) const {
  const Vec3 inverse = SafeInverse(displacement);
  const Vec3 center = box.Center();
  const Vec3 half = box.HalfExtents();
  ForEachAccepted(filter, [&](std::size_t j) {
    const float entry =
        BoundsAt(j).Expanded(half).RayEntry(center, inverse, std::min(1.0f, collector.early_out_fraction()));
    if (entry >= 0.0f) collector.AddHit(ids_[j], entry);
    return !collector.ShouldStop();
  });
}

}  // namespace strata
