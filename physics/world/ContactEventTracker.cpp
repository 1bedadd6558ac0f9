#include "physics/world/ContactEventTracker.h"

#include <algorithm>

namespace strata {

namespace {

std::uint64_t PairKey(BodyID a, BodyID b) {
  return (static_cast<std::uint64_t>(std::min(a.index, b.index)) << 32) | std::max(a.index, b.index);
}

float SummedImpulse(const ContactConstraint& constraint) {
  if (!constraint.reports) return 0.0f;
  const float* impulses = constraint.reported_impulses();
  float sum = 0.0f;
  for (int i = 0; i < constraint.point_count; ++i) sum += impulses[i];
  return sum;
}

bool InWorld(const BodyManager& bodies, BodyID id) {
  const Body& body = bodies.BodyAt(id.index);
  return body.in_world() && body.id() == id;
}

}  // namespace

void ContactEventTracker::Merge(const ReportedManifold& manifold, Pair& pair) {
  const float impulse = manifold.constraint ? SummedImpulse(*manifold.constraint) : 0.0f;
  // The solver pushed (the step's impulse), or the bodies overlapped as the step began: a speculative
  // contact that never closed its gap is not a touch.
  pair.touching = pair.touching || impulse > 0.0f || manifold.separation <= 0.0f;
  pair.event.normal_impulse += impulse;
  pair.event.approach_speed = std::max(pair.event.approach_speed, manifold.approach_speed);
  if (manifold.separation >= pair.deepest) return;
  pair.deepest = manifold.separation;
  // Events name the lower index first; the normal turns with them.
  const bool turned = manifold.a.index > manifold.b.index;
  pair.event.normal = turned ? Vec3(-manifold.normal) : manifold.normal;
  pair.event.point_count = manifold.point_count;
  std::copy_n(manifold.points, manifold.point_count, pair.event.points);
}

void ContactEventTracker::Summarize(std::span<const std::span<const ReportedManifold>> jobs) {
  pairs_.clear();
  for (const std::span<const ReportedManifold> job : jobs) {
    // One job handles all of a pair's manifolds, one after another.
    const ReportedManifold* previous = nullptr;
    for (const ReportedManifold& manifold : job) {
      if (previous == nullptr || previous->a != manifold.a || previous->b != manifold.b) {
        Pair pair;
        pair.key = PairKey(manifold.a, manifold.b);
        pair.touching = false;
        pair.deepest = kLargeFloat;
        const bool turned = manifold.a.index > manifold.b.index;
        pair.event.body_a = turned ? manifold.b : manifold.a;
        pair.event.body_b = turned ? manifold.a : manifold.b;
        pairs_.push_back(pair);
      }
      Merge(manifold, pairs_.back());
      previous = &manifold;
    }
  }
  // Which job found a pair depends on the thread count; the order of the events must not.
  std::sort(pairs_.begin(), pairs_.end(), [](const Pair& x, const Pair& y) { return x.key < y.key; });
}

void ContactEventTracker::Update(std::span<const std::span<const ReportedManifold>> jobs,
                                 std::span<const std::uint8_t> active_flags, const BodyManager& bodies,
                                 StepEvents& events) {
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
  for (const Pair& pair : pairs_) {
    while (last < touching_.size() && touching_[last].key < pair.key) carry_or_end(touching_[last++]);
    bool touched_before = false;
    if (last < touching_.size() && touching_[last].key == pair.key) {
      // The same slots may hold other bodies now (one destroyed, another created in its slot).
      const Touching& old = touching_[last++];
      touched_before = old.a == pair.event.body_a && old.b == pair.event.body_b;
      if (!touched_before) events.contact_end.push_back({old.a, old.b});
    }
    if (!pair.touching) {
      if (touched_before) events.contact_end.push_back({pair.event.body_a, pair.event.body_b});
      continue;
    }
    (touched_before ? events.contact_persist : events.contact_begin).push_back(pair.event);
    next_touching_.push_back({pair.key, pair.event.body_a, pair.event.body_b});
  }
  while (last < touching_.size()) carry_or_end(touching_[last++]);
  touching_.swap(next_touching_);
}

}  // namespace strata
