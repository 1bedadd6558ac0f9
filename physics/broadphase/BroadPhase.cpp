#include "physics/broadphase/BroadPhase.h"

#include <algorithm>
#include <string>

namespace strata {

namespace {

// Collects into a vector, the form most callers want.
class VectorCollector final : public BroadPhaseCollector {
 public:
  explicit VectorCollector(std::vector<BroadPhaseRayHit>& out) : out_(out) {}
  void AddHit(BodyID id, float fraction) override { out_.push_back({id, fraction}); }

 private:
  std::vector<BroadPhaseRayHit>& out_;
};

class IdCollector final : public BroadPhaseCollector {
 public:
  explicit IdCollector(std::vector<BodyID>& out) : out_(out) {}
  void AddHit(BodyID id, float) override { out_.push_back(id); }

 private:
  std::vector<BodyID>& out_;
};

}  // namespace

BroadPhasePin& BroadPhasePin::operator=(BroadPhasePin&& other) noexcept {
  if (this == &other) return *this;
  Release();
  owner_ = std::exchange(other.owner_, nullptr);
  record_ = other.record_;
  generation_ = other.generation_;
  return *this;
}

void BroadPhasePin::Release() {
  if (owner_ == nullptr) return;
  owner_->ReleasePin(record_);
  owner_ = nullptr;
}

AddBatch& AddBatch::operator=(AddBatch&& other) noexcept {
  if (this == &other) return *this;
  if (prepared()) owner_->AddBodiesAbort(*this);
  owner_ = other.owner_;
  state_ = std::move(other.state_);
  size_ = other.size_;
  return *this;
}

AddBatch::~AddBatch() {
  if (prepared()) owner_->AddBodiesAbort(*this);
}

Status BroadPhase::AddBody(BodyID id, const AABB& bounds, ObjectLayer layer) {
  Result<AddBatch> batch = AddBodiesPrepare({&id, 1}, {&bounds, 1}, {&layer, 1});
  if (!batch) return batch.error();
  return AddBodiesFinalize(*batch);
}

void BroadPhase::CollideAABB(const AABB& box, const QueryFilter& filter, std::vector<BodyID>& out) const {
  IdCollector collector(out);
  CollideAABB(Pin(), box, filter, collector);
}

void BroadPhase::CollideSphere(const Vec3& center, float radius, const QueryFilter& filter,
                               std::vector<BodyID>& out) const {
  IdCollector collector(out);
  CollideSphere(Pin(), center, radius, filter, collector);
}

void BroadPhase::CastRay(const Vec3& origin, const Vec3& direction, const QueryFilter& filter,
                         std::vector<BroadPhaseRayHit>& out) const {
  VectorCollector collector(out);
  CastRay(Pin(), origin, direction, filter, collector);
}

void BroadPhase::CastAABB(const AABB& box, const Vec3& displacement, const QueryFilter& filter,
                          std::vector<BroadPhaseRayHit>& out) const {
  VectorCollector collector(out);
  CastAABB(Pin(), box, displacement, filter, collector);
}

Status CheckBounds(const AABB& bounds) {
  if (!bounds.IsValid())
    return MakeError(ErrorCode::kInvalidArgument, "bounds must be finite with min <= max");
  // Beyond this the inside-out markers of empty slots would no longer be outside every real box.
  constexpr float kWorldLimit = 1e18f;
  if ((bounds.min.array() < -kWorldLimit).any() || (bounds.max.array() > kWorldLimit).any())
    return MakeError(ErrorCode::kInvalidArgument, "bounds are outside +/-1e18");
  return Status::Ok();
}

Status CheckAddBatch(std::span<const BodyID> ids, std::span<const AABB> bounds,
                     std::span<const ObjectLayer> layers, ObjectLayer layer_count) {
  if (ids.size() != bounds.size() || ids.size() != layers.size())
    return MakeError(ErrorCode::kInvalidArgument, "a batch needs one bounds and one layer per body");
  if (ids.empty()) return MakeError(ErrorCode::kInvalidArgument, "a batch needs at least one body");
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i].IsInvalid()) return MakeError(ErrorCode::kStaleBodyId, "batch holds an invalid body id");
    if (Status valid = CheckBounds(bounds[i]); !valid)
      return MakeError(ErrorCode::kInvalidArgument,
                       "body " + std::to_string(ids[i].index) + ": " + valid.message());
    if (layers[i] >= layer_count)
      return MakeError(ErrorCode::kInvalidArgument, "body " + std::to_string(ids[i].index) +
                                                        ": object layer " + std::to_string(layers[i]) +
                                                        " is not in the layer setup");
  }
  std::vector<std::uint32_t> indices(ids.size());
  std::transform(ids.begin(), ids.end(), indices.begin(), [](BodyID id) { return id.index; });
  std::sort(indices.begin(), indices.end());
  if (const auto repeated = std::adjacent_find(indices.begin(), indices.end()); repeated != indices.end())
    return MakeError(ErrorCode::kInvalidArgument, "body " + std::to_string(*repeated) + " is listed twice");
  return Status::Ok();
}

float SquaredDistanceToBox(const AABB& box, const Vec3& point) {
  const Vec3 nearest = point.cwiseMax(box.min).cwiseMin(box.max);
  return (nearest - point).squaredNorm();
}

}  // namespace strata
