// BroadPhase: finds which bodies' bounds overlap (pairs for the step, candidates for queries). An
// interface so the lock-free quad tree and the brute-force oracle are interchangeable.
// Every member may be called from any thread; implementations say what, if anything, they wait for.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "physics/BodyID.h"
#include "physics/broadphase/Layers.h"
#include "physics/core/Result.h"
#include "physics/math/AABB.h"

namespace strata {

class BroadPhase;

/// Two bodies whose bounds overlap; `a` is the active (moving) one.
struct BodyPair {
  BodyID a;
  BodyID b;
  friend auto operator<=>(const BodyPair&, const BodyPair&) = default;
};

/// A body whose bounds a ray (or swept box) enters at `fraction`.
struct BroadPhaseRayHit {
  BodyID id;
  float fraction;
};

/// Receives the bodies a query finds. Lowering `early_out_fraction` prunes a ray or sweep to hits nearer
/// than it; ForceEarlyOut stops any query.
class BroadPhaseCollector {
 public:
  virtual ~BroadPhaseCollector() = default;
  /// `fraction` is where a ray or sweep enters the body's bounds, 0 for overlap queries.
  virtual void AddHit(BodyID id, float fraction) = 0;
  /// CollideAABB reports through this, with the bounds the broad phase holds for the body (read without any
  /// lock, so they may lag a concurrent move by one update): what a reader that must not lock bodies knows
  /// of a moving one. By default the bounds are dropped.
  virtual void AddOverlap(BodyID id, const AABB& bounds) {
    (void)bounds;
    AddHit(id, 0.0f);
  }

  float early_out_fraction() const { return early_out_fraction_; }
  void SetEarlyOutFraction(float fraction) { early_out_fraction_ = fraction; }
  void ForceEarlyOut() { early_out_fraction_ = -1.0f; }
  bool ShouldStop() const { return early_out_fraction_ < 0.0f; }

 private:
  float early_out_fraction_ = kLargeFloat;
};

/// Holds one generation of a broad phase alive: queries through the pin read its trees, and the nodes they
/// reach are not freed, however many steps pass, until the pin is released (or destroyed). Move-only.
class BroadPhasePin {
 public:
  BroadPhasePin() = default;
  BroadPhasePin(const BroadPhase* owner, std::uint32_t record, std::uint64_t generation)
      : owner_(owner), record_(record), generation_(generation) {}
  BroadPhasePin(BroadPhasePin&& other) noexcept { *this = std::move(other); }
  BroadPhasePin& operator=(BroadPhasePin&& other) noexcept;
  BroadPhasePin(const BroadPhasePin&) = delete;
  BroadPhasePin& operator=(const BroadPhasePin&) = delete;
  ~BroadPhasePin() { Release(); }

  void Release();
  bool pinned() const { return owner_ != nullptr; }
  const BroadPhase* owner() const { return owner_; }
  std::uint32_t record() const { return record_; }
  /// Generation number (increases by one per swapped-in rebuild); 0 for a broad phase without generations.
  std::uint64_t generation() const { return generation_; }

 private:
  const BroadPhase* owner_ = nullptr;
  std::uint32_t record_ = 0;
  std::uint64_t generation_ = 0;
};

/// A batch of bodies prepared for insertion (AddBodiesPrepare): finalize it once, or abort it; a batch
/// destroyed while still prepared aborts itself. Move-only.
class AddBatch {
 public:
  /// What an implementation keeps between prepare and finalize.
  struct State {
    virtual ~State() = default;
  };

  AddBatch() = default;
  AddBatch(BroadPhase* owner, std::unique_ptr<State> state, std::size_t size)
      : owner_(owner), state_(std::move(state)), size_(size) {}
  AddBatch(AddBatch&& other) noexcept = default;
  AddBatch& operator=(AddBatch&& other) noexcept;
  AddBatch(const AddBatch&) = delete;
  AddBatch& operator=(const AddBatch&) = delete;
  ~AddBatch();

  /// True until finalized or aborted.
  bool prepared() const { return state_ != nullptr; }
  std::size_t size() const { return size_; }
  BroadPhase* owner() const { return owner_; }
  State* state() const { return state_.get(); }
  /// Hands the state to the implementation that finalizes or aborts the batch.
  std::unique_ptr<State> TakeState() { return std::move(state_); }

 private:
  BroadPhase* owner_ = nullptr;
  std::unique_ptr<State> state_;
  std::size_t size_ = 0;
};

/// Memory and maintenance figures for tools and tests.
struct BroadPhaseStats {
  std::size_t nodes_in_use = 0;
  std::size_t node_bytes = 0;     ///< node blocks allocated so far
  std::size_t retired_nodes = 0;  ///< dropped by a rebuild, kept for pinned older generations
  std::size_t retired_bytes = 0;
  std::size_t pinned_old_generations = 0;
  std::uint64_t generation = 0;
  std::size_t rebuilds_skipped = 0;  ///< rebuilds put off because no generation record or node was free
  std::size_t max_depth = 0;         ///< deepest body below a root, over all trees (walks the trees)
};

/// Spatial index over the bounds of the bodies in the world.
class BroadPhase {
 public:
  virtual ~BroadPhase() = default;

  /// Inserts one body (not yet present): a batch of one. Cheap, but a tree degrades until the next Update.
  Status AddBody(BodyID id, const AABB& bounds, ObjectLayer layer);
  /// Builds the structure for a batch on the caller's thread without touching anything shared (the bodies
  /// are claimed so nobody else adds them meanwhile). Fails, claiming nothing, on bad bounds or layers,
  /// a repeated id or a body already present or prepared.
  virtual Result<AddBatch> AddBodiesPrepare(std::span<const BodyID> ids, std::span<const AABB> bounds,
                                            std::span<const ObjectLayer> layers) = 0;
  /// Makes a prepared batch present. O(1) in the batch size for the quad tree. Fails for a batch that was
  /// already finalized or aborted, or that belongs to another broad phase.
  virtual Status AddBodiesFinalize(AddBatch& batch) = 0;
  /// Drops a prepared batch and releases its bodies' claims; a no-op for a batch that is not prepared.
  virtual void AddBodiesAbort(AddBatch& batch) = 0;
  /// Removes a present body.
  Status RemoveBody(BodyID id) { return RemoveBodies({&id, 1}); }
  /// Removes several present bodies; all are checked first, so either all go or none.
  virtual Status RemoveBodies(std::span<const BodyID> ids) = 0;
  /// New bounds for a present body. Concurrent calls for the same body are the caller's to avoid.
  virtual Status UpdateBody(BodyID id, const AABB& bounds) = 0;
  /// Starts loading what UpdateBody(id) will touch, so that a caller holding the body's lock for the update
  /// holds it for less; changes nothing.
  virtual void PrefetchUpdate(BodyID /*id*/) const {}
  virtual bool Contains(BodyID id) const = 0;
  virtual std::size_t body_count() const = 0;

  /// Rebuilds what changed since the last call into a new generation (called by the physics step).
  virtual void Update() = 0;
  /// Rebuilds everything (after a level load).
  virtual void Optimize() = 0;
  virtual BroadPhaseStats stats() const = 0;

  /// Pins the current generation for queries that must not lose their tree (see BroadPhasePin).
  virtual BroadPhasePin Pin() const = 0;

  /// Appends every overlapping (active body, other body) pair the layer setup allows. `active_flags`
  /// is indexed by body index; a pair of two active bodies is reported once, with the lower index as `a`.
  virtual void FindPairs(std::span<const BodyID> active, std::span<const std::uint8_t> active_flags,
                         const LayerSetup& layers, std::vector<BodyPair>& out) const = 0;

  /// Bodies whose bounds overlap `box`.
  virtual void CollideAABB(const BroadPhasePin& pin, const AABB& box, const QueryFilter& filter,
                           BroadPhaseCollector& collector) const = 0;
  /// Bodies whose bounds come within `radius` of `center`.
  virtual void CollideSphere(const BroadPhasePin& pin, const Vec3& center, float radius,
                             const QueryFilter& filter, BroadPhaseCollector& collector) const = 0;
  /// Bodies whose bounds the ray origin + t * direction (t in [0, collector's early out, at most 1]) enters.
  virtual void CastRay(const BroadPhasePin& pin, const Vec3& origin, const Vec3& direction,
                       const QueryFilter& filter, BroadPhaseCollector& collector) const = 0;
  /// Bodies whose bounds `box` touches while moving by t * displacement, t in [0, 1].
  virtual void CastAABB(const BroadPhasePin& pin, const AABB& box, const Vec3& displacement,
                        const QueryFilter& filter, BroadPhaseCollector& collector) const = 0;

  /// Convenience forms: pin for the duration of the call and append to a vector.
  void CollideAABB(const AABB& box, const QueryFilter& filter, std::vector<BodyID>& out) const;
  void CollideSphere(const Vec3& center, float radius, const QueryFilter& filter,
                     std::vector<BodyID>& out) const;
  void CastRay(const Vec3& origin, const Vec3& direction, const QueryFilter& filter,
               std::vector<BroadPhaseRayHit>& out) const;
  void CastAABB(const AABB& box, const Vec3& displacement, const QueryFilter& filter,
                std::vector<BroadPhaseRayHit>& out) const;

 protected:
  friend class BroadPhasePin;
  /// Gives back a pin taken by Pin().
  virtual void ReleasePin(std::uint32_t record) const = 0;
};

/// Input checks shared by the implementations, so both broad phases reject the same things the same way.
Status CheckBounds(const AABB& bounds);
Status CheckAddBatch(std::span<const BodyID> ids, std::span<const AABB> bounds,
                     std::span<const ObjectLayer> layers, ObjectLayer layer_count);
/// Squared distance from `point` to `box` (0 inside).
float SquaredDistanceToBox(const AABB& box, const Vec3& point);

}  // namespace strata
