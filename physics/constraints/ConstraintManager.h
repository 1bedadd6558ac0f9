// ConstraintManager: the joints of one world. Add and remove them, read their forces, change their
// settings, from any thread: every call takes the manager's mutex, which the step holds from start to end,
// so a call made during a step waits for it to end (as body writes do). Joints are handed out as
// ConstraintIDs (slot index + generation): a removed joint's id goes stale and is refused.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <variant>
#include <vector>

#include "physics/body/BodyManager.h"
#include "physics/constraints/Constraint.h"
#include "physics/constraints/DistanceJoint.h"
#include "physics/constraints/FixedJoint.h"
#include "physics/constraints/HingeJoint.h"
#include "physics/constraints/PointJoint.h"
#include "physics/constraints/SliderJoint.h"
#include "physics/constraints/SwingTwistJoint.h"

namespace strata {

/// Slot index + generation. Default-constructed ids are invalid.
struct ConstraintID {
  static constexpr std::uint32_t kInvalidIndex = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;

  bool IsInvalid() const { return index == kInvalidIndex; }
  friend bool operator==(const ConstraintID&, const ConstraintID&) = default;
};

/// The settings of any joint.
using JointSettings = std::variant<FixedJointSettings, PointJointSettings, DistanceJointSettings,
                                   HingeJointSettings, SliderJointSettings, SwingTwistJointSettings>;

/// Checks settings as Add would, but for bodies where they are (no body is read): the settings alone.
Status ValidateJointSettings(const JointSettings& settings);
/// The joint `settings` describe, between bodies at `a` and `b` (not yet bound to a step); the settings'
/// error if they are bad. Add makes its joints so.
Result<std::unique_ptr<Constraint>> MakeJoint(const JointSettings& settings, const BodyFrame& a,
                                              const BodyFrame& b);

class ConstraintManager {
 public:
  /// At most this many joints at once.
  static constexpr std::uint32_t kMaxConstraints = 1u << 24;

  explicit ConstraintManager(BodyManager& bodies) : bodies_(bodies) {}

  /// Makes a joint from world-space settings and the bodies where they are now. Fails (nothing added) on
  /// bad settings, a stale body id, or two bodies that cannot move (static, or kinematic and static).
  Result<ConstraintID> Add(const JointSettings& settings);
  /// Removes the joint; its id goes stale.
  Status Remove(ConstraintID id);
  /// A joint acts while both its bodies are in the world, it is enabled and not broken.
  Status SetEnabled(ConstraintID id, bool enabled);
  Result<ConstraintForces> GetForces(ConstraintID id) const;
  Result<bool> IsBroken(ConstraintID id) const;
  /// Calls `function(const Constraint&)` on the joint.
  Status Read(ConstraintID id, const std::function<void(const Constraint&)>& function) const;
  /// Calls `function(Joint&)` (returning Status) if the joint is a `Joint`.
  template <class Joint, class Function>
  Status Modify(ConstraintID id, Function&& function);
  /// Ids of the joints, in slot order.
  std::vector<ConstraintID> Ids() const;
  std::size_t count() const;

  // For the step, which holds mutex() from its start to its end.
  std::mutex& mutex() { return mutex_; }
  /// Calls `function(Constraint&)` for every enabled joint that has not broken, in slot order (the same
  /// joints give the same order).
  template <class Function>
  void ForEachActive(Function&& function) {
    for (Slot& slot : slots_)
      if (slot.constraint && slot.constraint->enabled() && !slot.constraint->broken())
        function(*slot.constraint);
  }

 private:
  struct Slot {
    std::unique_ptr<Constraint> constraint;
    std::uint32_t generation = 0;
  };
  // The slot of a live id (mutex held), or an error naming it.
  Result<Slot*> Find(ConstraintID id);
  Result<const Slot*> Find(ConstraintID id) const;

  BodyManager& bodies_;
  mutable std::mutex mutex_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_slots_;
  std::size_t count_ = 0;
};

template <class Joint, class Function>
Status ConstraintManager::Modify(ConstraintID id, Function&& function) {
  std::lock_guard lock(mutex_);
  const Result<Slot*> slot = Find(id);
  if (!slot) return slot.error();
  auto* joint = dynamic_cast<Joint*>(slot.value()->constraint.get());
  if (joint == nullptr)
    return MakeError(ErrorCode::kInvalidArgument, "the constraint is not of the asked kind");
  return function(*joint);
}

}  // namespace strata
