// BodyInterface: the thread-safe front door to bodies: create, add, remove, destroy, and read or change
// their state. Every call validates its input and returns an error (world unchanged) for stale ids,
// NaN/Inf values or wrong states. Calls from many threads run at once with no global lock; reads go on
// while a step runs, changes wait for it to end. AddBodiesPrepare may run on a loading thread at any time.
// A move holds its body's lock only to write the pose; the broad phase gets the bounds right after.
#pragma once

#include <optional>
#include <span>

#include "physics/body/Body.h"
#include "physics/body/BodyManager.h"
#include "physics/body/BodySnapshotTable.h"
#include "physics/body/BroadPhaseMoveOrder.h"
#include "physics/body/SpeculativeBounds.h"
#include "physics/body/WakeQueue.h"
#include "physics/broadphase/BroadPhase.h"
#include "physics/broadphase/Layers.h"

namespace strata {

/// Whether a body added to the world starts awake.
enum class Activation { kActivate, kDontActivate };

/// Bodies prepared by AddBodiesPrepare, to be put in the world by AddBodiesFinalize. Move-only; dropping
/// it unfinalized gives the bodies back (still created, not in the world).
struct BodyAddBatch {
  std::vector<BodyID> ids;
  std::vector<AABB> bounds;
  Activation activation = Activation::kActivate;
  AddBatch broad_phase;
};

/// Thread-safe access to the bodies of one PhysicsSystem.
class BodyInterface {
 public:
  /// The parts of a world the interface works on; the world owns them and outlives the interface.
  struct Parts {
    BodyManager* bodies = nullptr;
    BroadPhase* broad_phase = nullptr;
    BroadPhaseMoveOrder* move_order = nullptr;
    BodySnapshotTable* snapshots = nullptr;
    const LayerSetup* layers = nullptr;
    WakeQueue* wakes = nullptr;
    const SpeculativeBounds* bounds = nullptr;
  };
  explicit BodyInterface(const Parts& parts) : parts_(parts) {}

  /// Creates a body outside the world.
  Result<BodyID> CreateBody(const BodyCreationSettings& settings);
  /// Creates a body and adds it to the world.
  Result<BodyID> CreateAndAddBody(const BodyCreationSettings& settings,
                                  Activation activation = Activation::kActivate);
  /// Puts a created body into the world (broad phase and step).
  Status AddBody(BodyID id, Activation activation = Activation::kActivate);
  /// Adds several bodies; all ids are checked first, so either all are added or none.
  Status AddBodies(std::span<const BodyID> ids, Activation activation = Activation::kActivate);
  /// First half of AddBodies, for a loading thread: checks the bodies and builds their broad-phase
  /// sub-tree without touching anything shared. Fails (nothing claimed) like AddBodies.
  Result<BodyAddBatch> AddBodiesPrepare(std::span<const BodyID> ids,
                                        Activation activation = Activation::kActivate);
  /// Second half: links the sub-tree in O(1) and marks the bodies in the world. Fails, adding none, if the
  /// batch was finalized before or a body was destroyed or added meanwhile.
  Status AddBodiesFinalize(BodyAddBatch& batch);
  /// Takes a body out of the world; it keeps its state and can be added again.
  Status RemoveBody(BodyID id);
  /// Frees a body that is not in the world; its id goes stale.
  Status DestroyBody(BodyID id);
  /// Removes (if needed) and destroys.
  Status RemoveAndDestroyBody(BodyID id);

  bool IsValid(BodyID id) const;
  Result<bool> IsInWorld(BodyID id) const;
  Result<bool> IsActive(BodyID id) const;

  Result<Vec3> GetPosition(BodyID id) const;
  /// The position with the part a float cannot hold far from the origin (see Body::precise_position).
  Result<Vec3d> GetPrecisePosition(BodyID id) const;
  Result<Quat> GetRotation(BodyID id) const;
  Result<Vec3> GetCenterOfMass(BodyID id) const;
  Result<Vec3> GetLinearVelocity(BodyID id) const;
  Result<Vec3> GetAngularVelocity(BodyID id) const;
  Result<AABB> GetWorldBounds(BodyID id) const;
  Result<ShapeRef> GetShape(BodyID id) const;
  Result<MotionType> GetMotionType(BodyID id) const;
  /// Whether the body is a sensor (a trigger volume).
  Result<bool> IsSensor(BodyID id) const;

  /// Teleports the body (waking it when in the world).
  Status SetPosition(BodyID id, const Vec3& position);
  Status SetRotation(BodyID id, const Quat& rotation);
  Status SetPositionAndRotation(BodyID id, const Vec3& position, const Quat& rotation);
  Status SetLinearVelocity(BodyID id, const Vec3& velocity);
  Status SetAngularVelocity(BodyID id, const Vec3& velocity);
  /// Force (N) at the centre of mass for the next step.
  Status AddForce(BodyID id, const Vec3& force);
  /// Force (N) at a world point for the next step.
  Status AddForce(BodyID id, const Vec3& force, const Vec3& point);
  Status AddTorque(BodyID id, const Vec3& torque);
  /// Instant change of momentum (N s) at the centre of mass.
  Status AddImpulse(BodyID id, const Vec3& impulse);
  /// Instant change of momentum (N s) at a world point.
  Status AddImpulse(BodyID id, const Vec3& impulse, const Vec3& point);
  /// Wakes the body and its sleeping island.
  Status ActivateBody(BodyID id);
  /// Wakes every sleeping body whose bounds overlap `box`. Removing or teleporting a body does this for
  /// the space it left, so nothing stays asleep in mid-air.
  Status ActivateBodiesInBox(const AABB& box);

 private:
  template <class Function>
  auto Read(BodyID id, Function&& function) const -> Result<decltype(function(std::declval<const Body&>()))>;
  template <class Function>
  Status Write(BodyID id, Function&& function);
  /// Moves a body to `pose` and wakes what rested on it where it was.
  Status Teleport(BodyID id, const std::optional<Vec3>& position, const std::optional<Quat>& rotation);
  void WakeLocked(Body& body);
  /// Puts batch body `i` in the world (finalize's per-body part).
  Status MarkAdded(const BodyAddBatch& batch, std::size_t i);
  /// Takes bodies added by a failed finalize back out again.
  void UndoAdd(std::span<const BodyID> flagged, std::span<const BodyID> all);

  Parts parts_;
};

}  // namespace strata
