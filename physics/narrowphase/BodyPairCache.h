// BodyPairCache: what the narrow phase found for each body pair last step (relative pose, manifolds with
// their points in each body's frame, and the impulses the solver ended with), so this step can skip the
// shape test of pairs that barely moved relative to each other and warm-start every contact.
// Entries hang off the active body that found the pair (its "owner"), in ascending order of the other
// body, which is the order the narrow phase visits them every step; a lookup is therefore a walk along
// last step's list for the same owner, with no hashing and no lock. Double-buffered: the step reads last
// step's entries while its narrow-phase jobs write this step's, each job into its own arena and only for
// the owners it processes. BeginStep runs on one thread between steps; the rest from the narrow-phase jobs.
#pragma once

#include <cstdint>
#include <vector>

#include "physics/BodyID.h"
#include "physics/core/BlockArena.h"
#include "physics/math/Math.h"
#include "physics/narrowphase/SlidingFace.h"

namespace strata {

/// One contact point as remembered between steps.
struct CachedContactPoint {
  Vec3 local_a;           ///< from A's centre of mass, in A's frame
  Vec3 local_b;           ///< from B's centre of mass, in B's frame
  Vec3 friction_impulse;  ///< world space, so a new tangent basis can take it over
  float normal_impulse;
};

/// One manifold of a pair (one pair of sub-shapes) with its points stored right after it.
struct CachedManifold {
  CachedManifold* next = nullptr;
  const SlidingFace* face = nullptr;  ///< where a slide may carry the points, if anywhere
  Vec3 normal_a;                      ///< contact normal (A to B) in A's frame
  std::uint32_t sub_shape_a = 0;
  std::uint32_t sub_shape_b = 0;
  std::uint16_t point_count = 0;
  /// Its pair reports contact events: reported_impulses() follow the points.
  bool reports = false;

  CachedContactPoint* points() { return reinterpret_cast<CachedContactPoint*>(this + 1); }
  const CachedContactPoint* points() const { return reinterpret_cast<const CachedContactPoint*>(this + 1); }
  /// Only when `reports`: per point, the normal impulse applied over this step (N s), which the solver sums
  /// here and the step's contact events read. Beside the impulses the solver stores anyway, so reporting
  /// touches no other memory.
  float* reported_impulses() { return reported_impulses(point_count); }
  const float* reported_impulses() const { return reinterpret_cast<const float*>(points() + point_count); }
  /// The same for a caller that holds the point count (the solver's constraint): it need not load this
  /// header, which the solver otherwise never reads.
  float* reported_impulses(std::uint32_t points_held) {
    return reinterpret_cast<float*>(points() + points_held);
  }
};

/// A body pair's entry: the relative pose when its manifolds were computed, and the manifolds (maybe none:
/// a pair whose bounds overlap but whose shapes are apart is remembered too). A is the owner.
struct CachedBodyPair {
  BodyID other;  ///< the body paired with the owner
  BodyID a;
  BodyID b;
  CachedBodyPair* next_of_owner = nullptr;
  CachedManifold* manifolds = nullptr;
  Vec3 delta_position;  ///< B's centre of mass relative to A's, in A's frame
  Quat delta_rotation;  ///< A's rotation inverted times B's
  /// Two convex shapes found apart beyond the reach: a unit direction in A's frame, from A towards B, that
  /// they were apart along (zero otherwise), for GapAlong to try first next step.
  Vec3 separating_axis = Vec3::Zero();
};

/// Last step's and this step's body-pair entries.
class BodyPairCache {
 public:
  /// Walks last step's entries of one owner in step with the narrow phase, which visits the owner's pairs in
  /// ascending order of the other body, as it did last step.
  class PreviousPairs {
   public:
    /// Last step's entry for (owner, other), or null. Calls must come in ascending order of `other`.
    const CachedBodyPair* Find(BodyID other) {
      while (next_ != nullptr && next_->other.index < other.index) next_ = next_->next_of_owner;
      if (next_ == nullptr || next_->other != other) return nullptr;
      return next_;
    }

   private:
    friend class BodyPairCache;
    explicit PreviousPairs(const CachedBodyPair* first) : next_(first) {}
    const CachedBodyPair* next_;
  };

  /// Room for owners with body index below `max_bodies`; entries live in blocks from `pool`.
  BodyPairCache(std::uint32_t max_bodies, BlockPool& pool);

  /// Makes this step's entries the previous ones and starts empty ones, with `job_count` arenas to add to.
  void BeginStep(std::uint32_t job_count);

  /// Last step's entries of `owner` (none if it found no pairs last step). Any thread.
  PreviousPairs Previous(BodyID owner) const;

  /// Starts `owner`'s entries for this step; then Create its pairs in ascending order of the other body.
  /// One job per owner.
  void BeginOwner(BodyID owner);
  /// Adds this step's entry for the pair of `owner` (last BeginOwner of this job) and `other`, allocated in
  /// job `job`'s arena; (a, b) is the pair as the narrow phase orders it.
  CachedBodyPair* Create(std::uint32_t job, BodyID owner, BodyID other, BodyID a, BodyID b,
                         const Vec3& delta_position, const Quat& delta_rotation);
  /// Appends a manifold of sub-shapes (`sub_shape_a`, `sub_shape_b`) with `point_count` (uninitialised)
  /// points to `pair`, from job `job`'s arena; with `reports`, also its reported impulses, zeroed.
  CachedManifold* AddManifold(std::uint32_t job, CachedBodyPair& pair, std::uint32_t sub_shape_a,
                              std::uint32_t sub_shape_b, const Vec3& normal_a, std::uint32_t point_count,
                              bool reports);

  /// Gives `manifold` a copy of `face`, from job `job`'s arena.
  void SetFace(std::uint32_t job, CachedManifold& manifold, const SlidingFace& face);

  /// Entries added this step so far (exact once the narrow phase is over).
  std::size_t current_pair_count() const;
  /// Bytes of the owner tables (the entries are in the pool's blocks).
  std::size_t table_bytes() const;
  /// Bytes this step's entries take in the pool's blocks.
  std::size_t arena_bytes() const;

 private:
  // An owner's list in one step; `step` tells a list from this step from one left over from an older step.
  struct OwnerList {
    CachedBodyPair* first = nullptr;
    CachedBodyPair* last = nullptr;
    std::uint64_t step = 0;
  };
  // One narrow-phase job's allocations, on its own cache lines.
  struct alignas(64) JobSlot {
    BlockArena arena;
    std::size_t pairs = 0;
  };
  struct Generation {
    std::vector<OwnerList> owners;  // by body index
    std::vector<JobSlot> jobs;
    std::uint64_t step = 0;
  };

  BlockPool& pool_;
  Generation generations_[2];
  int current_ = 0;
  std::uint64_t step_ = 0;
};

}  // namespace strata
