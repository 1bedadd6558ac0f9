#include "physics/world/SensorTracker.h"

#include <algorithm>

#include "physics/core/ForEachChunk.h"

namespace strata {

namespace {

bool EventOrder(const SensorEvent& x, const SensorEvent& y) {
  return x.sensor.index != y.sensor.index ? x.sensor.index < y.sensor.index
                                          : x.visitor.index < y.visitor.index;
}

}  // namespace

void SensorTracker::BeginStep(const Input& input, std::span<const BodyID> sensors, std::uint32_t job_count) {
  input_ = input;
  // Last step's states by id: kept for sensors still in the world, the rest end their overlaps.
  std::vector<Sensor>& last = previous_;
  last.clear();
  last.swap(sensors_);
  for (Sensor& gone : removed_) spare_.push_back(std::move(gone));
  removed_.clear();
  std::size_t old = 0;
  for (const BodyID id : sensors) {
    while (old < last.size() && last[old].id.index < id.index) removed_.push_back(std::move(last[old++]));
    if (old < last.size() && last[old].id == id) {
      sensors_.push_back(std::move(last[old++]));
      continue;
    }
    if (old < last.size() && last[old].id.index == id.index) removed_.push_back(std::move(last[old++]));
    Sensor fresh;
    if (!spare_.empty()) {
      fresh = std::move(spare_.back());
      spare_.pop_back();
    }
    fresh.id = id;
    fresh.inside.clear();
    sensors_.push_back(std::move(fresh));
  }
  while (old < last.size()) removed_.push_back(std::move(last[old++]));
  last.clear();
  if (jobs_.size() < job_count) jobs_.resize(job_count);
  next_sensor_.store(0, std::memory_order_relaxed);
}

void SensorTracker::RunJob(std::uint32_t job, std::uint32_t width) {
  ForEachChunkItem(next_sensor_, sensor_count(), kSensorsPerBatch, width,
                   [&](std::uint32_t i) { Test(sensors_[i], jobs_[job]); });
}

bool SensorTracker::Overlaps(const Body& sensor, const Body& visitor, Job& job) {
  job.manifolds.clear();
  CollideShapes(*sensor.shape(), sensor.pose(), *visitor.shape(), visitor.pose(), 0.0f, ContactManifold{},
                job.manifolds, job.scratch);
  for (const ContactManifold& manifold : job.manifolds)
    if (manifold.MinSeparation() < 0.0f) return true;
  return false;
}

void SensorTracker::Test(Sensor& sensor, Job& job) const {
  sensor.next.clear();
  const BodyManager& bodies = *input_.bodies;
  const Body& body = bodies.BodyAt(sensor.id.index);
  job.candidates.clear();
  input_.broad_phase->CollideAABB(body.world_bounds(), QueryFilter{}, job.candidates);
  // The tree's order depends on its generation; the list's must not.
  std::sort(job.candidates.begin(), job.candidates.end());
  const bool sensor_moved = input_.active_flags[sensor.id.index] != 0;
  for (const BodyID id : job.candidates) {
    if (id == sensor.id) continue;
    const Body& visitor = bodies.BodyAt(id.index);
    // The broad phase may briefly hold a body another thread is adding or removing.
    if (!visitor.in_world() || visitor.id() != id || visitor.is_sensor()) continue;
    if (!visitor.IsDynamic() && !body.sensor_detects_static()) continue;
    if (!input_.layers->ShouldCollide(body.object_layer(), visitor.object_layer())) continue;
    // Neither moved since last step: the answer cannot have changed (a sleeper inside stays inside).
    const bool still = !sensor_moved && input_.active_flags[id.index] == 0;
    if (still && std::binary_search(sensor.inside.begin(), sensor.inside.end(), id)) {
      sensor.next.push_back(id);
      continue;
    }
    if (Overlaps(body, visitor, job)) sensor.next.push_back(id);
  }
}

void SensorTracker::EndStep(StepEvents& events) {
  const std::size_t end_start = events.sensor_end.size();
  for (Sensor& sensor : sensors_) {
    // Both lists ascend: one merge finds who came and who left.
    std::size_t i = 0, k = 0;
    while (i < sensor.inside.size() || k < sensor.next.size()) {
      if (k == sensor.next.size() || (i < sensor.inside.size() && sensor.inside[i] < sensor.next[k])) {
        events.sensor_end.push_back({sensor.id, sensor.inside[i++]});
      } else if (i == sensor.inside.size() || sensor.next[k] < sensor.inside[i]) {
        events.sensor_begin.push_back({sensor.id, sensor.next[k++]});
      } else {
        ++i, ++k;
      }
    }
    sensor.inside.swap(sensor.next);
  }
  for (const Sensor& gone : removed_)
    for (const BodyID visitor : gone.inside) events.sensor_end.push_back({gone.id, visitor});
  if (!removed_.empty())
    std::sort(events.sensor_end.begin() + static_cast<std::ptrdiff_t>(end_start), events.sensor_end.end(),
              EventOrder);
}

}  // namespace strata
