// SensorTracker: the step's sensor stage. After the bodies have moved, each sensor in the world asks the
// broad phase for the bodies around it and keeps those its shape overlaps (dynamic ones; static and kinematic
// ones too for a sensor created with sensor_detects_static); the difference from last step's list gives the
// sensor begin / end events. A sleeping body inside a sensor that did not move either keeps its place without
// a test, so it stays inside however long it sleeps. Sensors never see sensors. Threading: BeginStep and
// EndStep on the step's thread; RunJob from the stage's jobs, each sensor handled by one job.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "physics/body/BodyManager.h"
#include "physics/broadphase/BroadPhase.h"
#include "physics/narrowphase/CollideShapes.h"
#include "physics/world/StepEvents.h"

namespace strata {

/// Which bodies overlap which sensor, step to step.
class SensorTracker {
 public:
  /// Sensors a job claims at a time: a sensor's test is a broad-phase query and a few shape tests.
  static constexpr std::uint32_t kSensorsPerBatch = 4;

  /// What one step's sensor stage reads (owned by the caller).
  struct Input {
    const BodyManager* bodies = nullptr;
    const BroadPhase* broad_phase = nullptr;
    const LayerSetup* layers = nullptr;
    std::span<const std::uint8_t> active_flags;  ///< by body index: the body moved this step
  };

  /// Starts a step over `sensors` (the sensors in the world, ascending index) with `job_count` jobs. Sensors
  /// that left the world since last step end their visitors' overlaps in EndStep.
  void BeginStep(const Input& input, std::span<const BodyID> sensors, std::uint32_t job_count);
  /// True when there was no sensor last step and there is none now: the stage has nothing to do.
  bool idle() const { return sensors_.empty() && removed_.empty(); }
  std::uint32_t sensor_count() const { return static_cast<std::uint32_t>(sensors_.size()); }
  /// Tests the sensors this job claims; one of `width` jobs (see ForEachChunk).
  void RunJob(std::uint32_t job, std::uint32_t width);
  /// Appends the step's sensor events to `events`, ordered by (sensor, visitor) index.
  void EndStep(StepEvents& events);

 private:
  struct Sensor {
    BodyID id;
    std::vector<BodyID> inside;  // last step's visitors, ascending
    std::vector<BodyID> next;    // this step's
  };
  struct alignas(64) Job {
    std::vector<BodyID> candidates;
    std::vector<ContactManifold> manifolds;
    CollisionScratch scratch;
  };

  /// Fills `sensor.next` with the bodies its shape overlaps now.
  void Test(Sensor& sensor, Job& job) const;
  /// Whether the two shapes overlap (not merely touch).
  static bool Overlaps(const Body& sensor, const Body& visitor, Job& job);

  Input input_{};
  std::vector<Sensor> sensors_;   // this step's, by index
  std::vector<Sensor> previous_;  // last step's, while BeginStep matches them (kept for its capacity)
  std::vector<Sensor> removed_;   // sensors that left the world since last step
  std::vector<Sensor> spare_;     // states kept for their capacity
  std::vector<Job> jobs_;
  std::atomic<std::uint32_t> next_sensor_{0};
};

}  // namespace strata
