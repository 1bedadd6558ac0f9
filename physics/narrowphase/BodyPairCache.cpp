#include "physics/narrowphase/BodyPairCache.h"

#include <algorithm>
#include <new>

#include "physics/narrowphase/ContactManifold.h"

namespace strata {

BodyPairCache::BodyPairCache(std::uint32_t max_bodies, BlockPool& pool) : pool_(pool) {
  for (Generation& generation : generations_) generation.owners.resize(max_bodies);
}

void BodyPairCache::BeginStep(std::uint32_t job_count) {
  current_ ^= 1;
  Generation& generation = generations_[current_];
  // Owner lists of this buffer's last use stay behind but carry an older step number, so they read as empty.
  generation.step = ++step_;
  if (generation.jobs.size() < job_count) {
    generation.jobs.resize(job_count);
    for (JobSlot& job : generation.jobs) job.arena.SetPool(pool_);
  }
  for (JobSlot& job : generation.jobs) {
    job.arena.Recycle();
    job.pairs = 0;
  }
}

BodyPairCache::PreviousPairs BodyPairCache::Previous(BodyID owner) const {
  const Generation& previous = generations_[current_ ^ 1];
  const OwnerList& list = previous.owners[owner.index];
  // A list is last step's only if it was written then (by this owner, not an earlier body in its slot).
  if (list.step != previous.step || previous.step + 1 != step_ || list.first == nullptr ||
      (list.first->a != owner && list.first->b != owner))
    return PreviousPairs(nullptr);
  return PreviousPairs(list.first);
}

void BodyPairCache::BeginOwner(BodyID owner) {
  Generation& generation = generations_[current_];
  generation.owners[owner.index] = {nullptr, nullptr, generation.step};
}

CachedBodyPair* BodyPairCache::Create(std::uint32_t job, BodyID owner, BodyID other, BodyID a, BodyID b,
                                      const Vec3& delta_position, const Quat& delta_rotation) {
  Generation& generation = generations_[current_];
  JobSlot& slot = generation.jobs[job];
  auto* entry = new (slot.arena.AllocateArray<CachedBodyPair>(1)) CachedBodyPair;
  entry->other = other;
  entry->a = a;
  entry->b = b;
  entry->delta_position = delta_position;
  entry->delta_rotation = delta_rotation;
  ++slot.pairs;
  OwnerList& list = generation.owners[owner.index];
  if (list.last == nullptr)
    list.first = entry;
  else
    list.last->next_of_owner = entry;
  list.last = entry;
  return entry;
}

CachedManifold* BodyPairCache::AddManifold(std::uint32_t job, CachedBodyPair& pair, std::uint32_t sub_shape_a,
                                           std::uint32_t sub_shape_b, const Vec3& normal_a,
                                           std::uint32_t point_count, bool reports) {
  BlockArena& arena = generations_[current_].jobs[job].arena;
  // Room for the most points a manifold has: zeroing a fixed count is a single store.
  constexpr int kReported = ContactManifold::kMaxPoints;
  const std::size_t bytes = sizeof(CachedManifold) + point_count * sizeof(CachedContactPoint) +
                            (reports ? kReported * sizeof(float) : 0);
  void* memory = arena.Allocate(bytes, alignof(CachedManifold));
  auto* manifold = new (memory) CachedManifold;
  manifold->normal_a = normal_a;
  manifold->sub_shape_a = sub_shape_a;
  manifold->sub_shape_b = sub_shape_b;
  manifold->point_count = static_cast<std::uint16_t>(point_count);
  manifold->reports = reports;
  if (reports) std::fill_n(manifold->reported_impulses(point_count), kReported, 0.0f);
  // Appended, not prepended: replaying keeps the order, so constraint order does not flip every step.
  CachedManifold** tail = &pair.manifolds;
  while (*tail != nullptr) tail = &(*tail)->next;
  *tail = manifold;
  return manifold;
}

void BodyPairCache::SetFace(std::uint32_t job, CachedManifold& manifold, const SlidingFace& face) {
  BlockArena& arena = generations_[current_].jobs[job].arena;
  void* memory = arena.Allocate(sizeof(SlidingFace), alignof(SlidingFace));
  manifold.face = new (memory) SlidingFace(face);
}

std::size_t BodyPairCache::current_pair_count() const {
  std::size_t total = 0;
  for (const JobSlot& job : generations_[current_].jobs) total += job.pairs;
  return total;
}

std::size_t BodyPairCache::arena_bytes() const {
  std::size_t total = 0;
  for (const JobSlot& job : generations_[current_].jobs) total += job.arena.bytes_in_use();
  return total;
}

std::size_t BodyPairCache::table_bytes() const {
  return 2 * generations_[0].owners.size() * sizeof(OwnerList);
}

}  // namespace strata
