// StepEvents: what one step reports to game code, as arrays read after the step (Box2D v3's way): contacts
// that began, persisted or ended between bodies created with report_contacts, and bodies that entered or
// left sensors. Plain data; the arrays are ordered by body index, the same for any thread count. Read the
// world's copy on the thread that steps, between steps (PhysicsSystem::events()), or take a copy from any
// thread at any time (PhysicsSystem::CopyEvents).
#pragma once

#include <cstdint>
#include <vector>

#include "physics/BodyID.h"
#include "physics/math/Math.h"

namespace strata {

/// A pair of bodies touching in the step: body_a has the lower index. Two bodies touch when the solver
/// pushed them apart this step, or when they overlapped as the step began.
struct ContactEvent {
  static constexpr int kMaxPoints = 4;
  // Provided, so that an event made in its array is not zeroed whole before its members are set (the step
  // writes thousands of them in place).
  ContactEvent() {}
  BodyID body_a;
  BodyID body_b;
  Vec3 normal = Vec3::UnitY();  ///< unit, from A towards B, of the pair's deepest manifold
  int point_count = 0;
  Vec3 points[kMaxPoints] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                             Vec3::Zero()};  ///< world, midway between the two surfaces, as the step began
  float approach_speed = 0.0f;  ///< fastest closing speed along the normal of any point as it met (m/s)
  /// Normal impulse the contact applied over the whole step, every point and every substep (N s): a box of
  /// mass m resting on a floor carries m g dt.
  float normal_impulse = 0.0f;
};

/// A pair of bodies that touched last step and no longer do (or one of them left the world).
struct ContactEndEvent {
  BodyID body_a;  ///< the lower index
  BodyID body_b;
};

/// A body that entered or left a sensor.
struct SensorEvent {
  BodyID sensor;
  BodyID visitor;
};

/// One step's events, sorted by (body_a, body_b) index and by (sensor, visitor) index.
struct StepEvents {
  std::vector<ContactEvent> contact_begin;    ///< pairs touching now that did not touch last step
  std::vector<ContactEvent> contact_persist;  ///< pairs touching now and last step (awake ones only)
  std::vector<ContactEndEvent> contact_end;   ///< pairs that stopped touching
  std::vector<SensorEvent> sensor_begin;      ///< bodies that began to overlap a sensor
  std::vector<SensorEvent> sensor_end;        ///< bodies that stopped overlapping one (or left the world)

  bool empty() const {
    return contact_begin.empty() && contact_persist.empty() && contact_end.empty() && sensor_begin.empty() &&
           sensor_end.empty();
  }
  void clear() {
    contact_begin.clear();
    contact_persist.clear();
    contact_end.clear();
    sensor_begin.clear();
    sensor_end.clear();
  }
};

}  // namespace strata
