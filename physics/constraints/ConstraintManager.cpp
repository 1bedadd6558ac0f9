#include "physics/constraints/ConstraintManager.h"

#include <string>

namespace strata {

namespace {

// Where a body is now, for a joint's frames; the world (an invalid id) is the identity.
struct SideInfo {
  BodyFrame frame;
  bool moves = false;  // dynamic
};

Result<SideInfo> ReadSide(const BodyManager& bodies, BodyID id, const char* name) {
  if (id.IsInvalid()) return SideInfo{};
  const BodyLockRead lock(bodies, id);
  if (!lock.Succeeded())
    return MakeError(ErrorCode::kStaleBodyId, std::string(name) + ": " + lock.status().message());
  const Body& body = lock.body();
  return SideInfo{{body.CenterOfMass(), body.rotation()}, body.IsDynamic()};
}

template <class Settings, class Joint>
Result<std::unique_ptr<Constraint>> Make(const Settings& settings, const BodyFrame& a, const BodyFrame& b) {
  Result<std::unique_ptr<Joint>> joint = Joint::Create(settings, a, b);
  if (!joint) return joint.error();
  return std::unique_ptr<Constraint>(std::move(joint.value()));
}

}  // namespace

Result<std::unique_ptr<Constraint>> MakeJoint(const JointSettings& settings, const BodyFrame& a,
                                              const BodyFrame& b) {
  struct Visitor {
    const BodyFrame& a;
    const BodyFrame& b;
    auto operator()(const FixedJointSettings& s) { return Make<FixedJointSettings, FixedJoint>(s, a, b); }
    auto operator()(const PointJointSettings& s) { return Make<PointJointSettings, PointJoint>(s, a, b); }
    auto operator()(const DistanceJointSettings& s) {
      return Make<DistanceJointSettings, DistanceJoint>(s, a, b);
    }
    auto operator()(const HingeJointSettings& s) { return Make<HingeJointSettings, HingeJoint>(s, a, b); }
    auto operator()(const SliderJointSettings& s) { return Make<SliderJointSettings, SliderJoint>(s, a, b); }
    auto operator()(const SwingTwistJointSettings& s) {
      return Make<SwingTwistJointSettings, SwingTwistJoint>(s, a, b);
    }
  };
  return std::visit(Visitor{a, b}, settings);
}

Status ValidateJointSettings(const JointSettings& settings) {
  const Result<std::unique_ptr<Constraint>> joint = MakeJoint(settings, BodyFrame{}, BodyFrame{});
  if (!joint) return joint.error();
  return Status::Ok();
}

Result<ConstraintID> ConstraintManager::Add(const JointSettings& settings) {
  const JointSettingsBase& base =
      std::visit([](const auto& s) -> const JointSettingsBase& { return s; }, settings);
  if (Status valid = base.ValidateBase(); !valid) return valid.error();
  // The bodies' poses are read before the manager's mutex is taken: a step holds that mutex and, at its
  // start and end, every body lock.
  const Result<SideInfo> a = ReadSide(bodies_, base.body_a, "body_a");
  if (!a) return a.error();
  const Result<SideInfo> b = ReadSide(bodies_, base.body_b, "body_b");
  if (!b) return b.error();
  if (!a.value().moves && !b.value().moves)
    return MakeError(ErrorCode::kInvalidArgument, "a joint needs at least one dynamic body");
  Result<std::unique_ptr<Constraint>> joint = MakeJoint(settings, a.value().frame, b.value().frame);
  if (!joint) return joint.error();
  std::lock_guard lock(mutex_);
  if (count_ >= kMaxConstraints)
    return MakeError(ErrorCode::kCapacityExceeded,
                     "a world holds at most " + std::to_string(kMaxConstraints) + " constraints");
  std::uint32_t index = 0;
  if (!free_slots_.empty()) {
    index = free_slots_.back();
    free_slots_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  Slot& slot = slots_[index];
  slot.constraint = std::move(joint.value());
  ++count_;
  return ConstraintID{index, slot.generation};
}

Result<ConstraintManager::Slot*> ConstraintManager::Find(ConstraintID id) {
  if (id.index >= slots_.size() || slots_[id.index].generation != id.generation ||
      !slots_[id.index].constraint)
    return MakeError(ErrorCode::kStaleBodyId, "constraint id " + std::to_string(id.index) + "/" +
                                                  std::to_string(id.generation) + " is stale or unknown");
  return &slots_[id.index];
}

Result<const ConstraintManager::Slot*> ConstraintManager::Find(ConstraintID id) const {
  Result<Slot*> slot = const_cast<ConstraintManager*>(this)->Find(id);
  if (!slot) return slot.error();
  return static_cast<const Slot*>(slot.value());
}

Status ConstraintManager::Remove(ConstraintID id) {
  std::lock_guard lock(mutex_);
  const Result<Slot*> slot = Find(id);
  if (!slot) return slot.error();
  slot.value()->constraint.reset();
  ++slot.value()->generation;
  free_slots_.push_back(id.index);
  --count_;
  return Status::Ok();
}

Status ConstraintManager::SetEnabled(ConstraintID id, bool enabled) {
  std::lock_guard lock(mutex_);
  const Result<Slot*> slot = Find(id);
  if (!slot) return slot.error();
  slot.value()->constraint->set_enabled(enabled);
  return Status::Ok();
}

Result<ConstraintForces> ConstraintManager::GetForces(ConstraintID id) const {
  std::lock_guard lock(mutex_);
  const Result<const Slot*> slot = Find(id);
  if (!slot) return slot.error();
  return slot.value()->constraint->forces();
}

Result<bool> ConstraintManager::IsBroken(ConstraintID id) const {
  std::lock_guard lock(mutex_);
  const Result<const Slot*> slot = Find(id);
  if (!slot) return slot.error();
  return slot.value()->constraint->broken();
}

Status ConstraintManager::Read(ConstraintID id,
                               const std::function<void(const Constraint&)>& function) const {
  std::lock_guard lock(mutex_);
  const Result<const Slot*> slot = Find(id);
  if (!slot) return slot.error();
  function(*slot.value()->constraint);
  return Status::Ok();
}

std::vector<ConstraintID> ConstraintManager::Ids() const {
  std::lock_guard lock(mutex_);
  std::vector<ConstraintID> ids;
  for (std::uint32_t index = 0; index < slots_.size(); ++index)
    if (slots_[index].constraint) ids.push_back({index, slots_[index].generation});
  return ids;
}

std::size_t ConstraintManager::count() const {
  std::lock_guard lock(mutex_);
  return count_;
}

}  // namespace strata
