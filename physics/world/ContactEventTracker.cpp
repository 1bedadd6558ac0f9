#include "physics/world/ContactEventTracker.h"

#include <algorithm>
#include <array>
#include <utility>

namespace strata {

namespace {

std::uint64_t PairKey(BodyID a, BodyID b) {
  return (static_cast<std::uint64_t>(std::min(a.index, b.index)) << 32) | std::max(a.index, b.index);
}

float SummedImpulse(const ReportedManifold& manifold) {
  float sum = 0.0f;
  for (int i = 0; i < manifold.point_count; ++i) sum += manifold.impulses[i];
  return sum;
}

// Sorts (key, index) entries by key, a byte at a time from the lowest (least significant digit radix sort,
// stable); bytes every key shares take no pass. Thousands of pairs a step: a comparison sort took a tenth of
// what the events cost.
void SortByKey(std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries,
               std::vector<std::pair<std::uint64_t, std::uint32_t>>& scratch) {
  std::array<std::array<std::uint32_t, 256>, 8> counts{};
  for (const auto& entry : entries)
    for (int byte = 0; byte < 8; ++byte) ++counts[byte][(entry.first >> (8 * byte)) & 0xff];
  scratch.resize(entries.size());
  for (int byte = 0; byte < 8; ++byte) {
    std::array<std::uint32_t, 256>& count = counts[byte];
    if (std::find(count.begin(), count.end(), entries.size()) != count.end()) continue;  // all the same
    std::uint32_t offset = 0;
    for (std::uint32_t& bucket : count) offset += std::exchange(bucket, offset);
    for (const auto& entry : entries) scratch[count[(entry.first >> (8 * byte)) & 0xff]++] = entry;
    entries.swap(scratch);
  }
}

bool InWorld(const BodyManager& bodies, BodyID id) {
  const Body& body = bodies.BodyAt(id.index);
  return body.in_world() && body.id() == id;
}

}  // namespace

void ContactEventTracker::Merge(const ReportedManifold& manifold, const ReportedGeometry& geometry,
                                Pair& pair) {
  const float impulse = SummedImpulse(manifold);
  // The solver pushed (the step's impulse), or the bodies overlapped as the step began: a speculative
  // contact that never closed its gap is not a touch.
  pair.touching = pair.touching || impulse > 0.0f || manifold.separation <= 0.0f;
  pair.normal_impulse += impulse;
  pair.approach_speed = std::max(pair.approach_speed, manifold.approach_speed);
  if (pair.deepest != nullptr && manifold.separation >= pair.separation) return;
  pair.deepest = &geometry;
  pair.separation = manifold.separation;
  pair.point_count = manifold.point_count;
}

void ContactEventTracker::WriteEvent(const Pair& pair, ContactEvent& event) {
  const ReportedGeometry& deepest = *pair.deepest;
  event.body_a = pair.low;
  event.body_b = pair.high;
  // Events name the lower index first; the normal turns with them.
  event.normal = pair.turned ? Vec3(-deepest.normal) : deepest.normal;
  event.point_count = pair.point_count;
  std::copy_n(deepest.points, pair.point_count, event.points);
  event.approach_speed = pair.approach_speed;
  event.normal_impulse = pair.normal_impulse;
}

void ContactEventTracker::Summarize(std::span<const JobReports> jobs) {
  pairs_.clear();
  for (const JobReports& job : jobs) {
    // One job handles all of a pair's manifolds, one after another.
    const std::span<const ReportedManifold> manifolds = job.manifolds;
    for (std::size_t k = 0; k < manifolds.size(); ++k) {
      // The impulses are where the solver left them, all over its cache: start loading what is next.
      if (k + 8 < manifolds.size()) __builtin_prefetch(manifolds[k + 8].impulses);
      const ReportedManifold& manifold = manifolds[k];
      if (k == 0 || manifolds[k - 1].a != manifold.a || manifolds[k - 1].b != manifold.b) {
        const bool turned = manifold.a.index > manifold.b.index;
        Pair& pair = pairs_.emplace_back();
        pair.key = PairKey(manifold.a, manifold.b);
        pair.low = turned ? manifold.b : manifold.a;
        pair.high = turned ? manifold.a : manifold.b;
        pair.deepest = nullptr;
        pair.approach_speed = 0.0f;
        pair.normal_impulse = 0.0f;
        pair.touching = false;
        pair.turned = turned;
      }
      Merge(manifold, job.geometry[k], pairs_.back());
    }
  }
  // Which job found a pair depends on the thread count; the order of the events must not. A world at rest
  // finds the same pairs in the same order step after step: then last step's order still holds.
  const bool same_as_last = pairs_.size() == found_keys_.size() &&
                            std::equal(pairs_.begin(), pairs_.end(), found_keys_.begin(),
                                       [](const Pair& pair, std::uint64_t key) { return pair.key == key; });
  if (same_as_last) return;
  found_keys_.clear();
  order_.clear();
  for (std::uint32_t i = 0; i < pairs_.size(); ++i) {
    found_keys_.push_back(pairs_[i].key);
    order_.push_back({pairs_[i].key, i});
  }
  SortByKey(order_, sort_scratch_);
}

void ContactEventTracker::Update(std::span<const JobReports> jobs, std::span<const std::uint8_t> active_flags,
                                 const BodyManager& bodies, StepEvents& events) {
  Summarize(jobs);
  next_touching_.clear();
  // Last step's touching pair that was not reported this step: over if a body left the world or the step
  // looked at its pairs (an active body whose contact ended); otherwise both sleep and it still touches.
  const auto carry_or_end = [&](const Touching& old) {
    const bool gone = !InWorld(bodies, old.a) || !InWorld(bodies, old.b);
    if (gone || active_flags[old.a.index] || active_flags[old.b.index])
      events.contact_end.push_back({old.a, old.b});
    else
      next_touching_.push_back(old);
  };
  std::size_t last = 0;
  for (std::size_t k = 0; k < order_.size(); ++k) {
    // The pairs come in key order, not the order they were found in: start loading what is next.
    if (k + 8 < order_.size()) __builtin_prefetch(pairs_[order_[k + 8].second].deepest);
    const Pair& pair = pairs_[order_[k].second];
    while (last < touching_.size() && touching_[last].key < pair.key) carry_or_end(touching_[last++]);
    const BodyID low = pair.low, high = pair.high;
    bool touched_before = false;
    if (last < touching_.size() && touching_[last].key == pair.key) {
      // The same slots may hold other bodies now (one destroyed, another created in its slot).
      const Touching& old = touching_[last++];
      touched_before = old.a == low && old.b == high;
      if (!touched_before) events.contact_end.push_back({old.a, old.b});
    }
    if (!pair.touching) {
      if (touched_before) events.contact_end.push_back({low, high});
      continue;
    }
    // Written in place: an event built apart and copied in is read back wider than it was written, and each
    // such read waits for its stores to drain.
    WriteEvent(pair, (touched_before ? events.contact_persist : events.contact_begin).emplace_back());
    next_touching_.push_back({pair.key, low, high});
  }
  while (last < touching_.size()) carry_or_end(touching_[last++]);
  touching_.swap(next_touching_);
}

}  // namespace strata
