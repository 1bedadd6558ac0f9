// Constraint: a joint between two bodies (or a body and the world) that the step solves with the
// contacts of their island: set up once a step, warm-started and solved in every substep's velocity
// (biased) and relax passes, its position drift corrected after the last substep, its impulses kept from
// step to step. Islands link through constraints, so a
// constrained group is solved, sleeps and wakes as one. Each kind of joint is one subclass built from the
// parts in this folder; see physics/README.md, "Extending". Threading: a constraint is owned by its
// world's ConstraintManager; the step's jobs solve it (one job at a time per constraint); read or change it
// between steps only (ConstraintManager's calls wait for a running step).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "physics/BodyID.h"
#include "physics/constraints/ConstraintBodies.h"
#include "physics/core/Result.h"
#include "physics/math/Math.h"
#include "physics/solver/IslandBuilder.h"

namespace strata {

enum class ConstraintType : std::uint8_t { kFixed, kPoint, kDistance, kHinge, kSlider, kSwingTwist };
/// "fixed", "point", "distance", "hinge", "slider", "swing_twist".
std::string_view ToString(ConstraintType type);

/// Where a body is and how it is held, as a constraint is made or stepped.
struct BodyFrame {
  Vec3 center_of_mass = Vec3::Zero();
  Quat rotation = Quat::Identity();
};

/// What a constraint pushed with over the last step: on B, world axes (A gets the opposite).
struct ConstraintForces {
  Vec3 force = Vec3::Zero();   ///< N
  Vec3 torque = Vec3::Zero();  ///< N m, the angular rows' (about the anchor)
};

/// What every joint's settings have. Anchors and axes are given in world space, where the bodies are when
/// the joint is added (the joint keeps them in each body's frame from then on).
struct JointSettingsBase {
  BodyID body_a;  ///< invalid: B is held to the world
  BodyID body_b;
  float max_force = 0.0f;   ///< N; the joint breaks past it (0 = never)
  float max_torque = 0.0f;  ///< N m; the joint breaks past it (0 = never)
  /// Off (the default), the two bodies do not collide with each other: a ragdoll's limbs overlap at their
  /// joints.
  bool collide_connected = false;

  /// Checks the limits and that the bodies differ; the message names the first bad field.
  Status ValidateBase() const;
};

/// A unit axis from `axis` (error if not finite or near zero), for messages named `what`.
Result<Vec3> UnitAxis(const Vec3& axis, const char* what);
/// A unit vector at right angles to `axis`: `normal` made perpendicular, or any if `normal` is zero.
Result<Vec3> PerpendicularAxis(const Vec3& axis, const Vec3& normal, const char* what);
/// Joint anchors farther from the origin than this (m) are refused: their arms would lose all precision.
inline constexpr float kMaxJointCoordinate = 1e7f;
/// Error unless `point` is finite and within kMaxJointCoordinate of the origin.
Status CheckPoint(const Vec3& point, const char* what);

/// One side of a constraint as a step sees it.
struct ConstraintSide {
  std::uint32_t solver_index = 0;  ///< 0: the side takes no impulse this step (static, kinematic, asleep)
  BodyFrame start;                 ///< where it was when the step began
  Vec3 linear_velocity = Vec3::Zero();  ///< a kinematic side's (constant over the step)
  Vec3 angular_velocity = Vec3::Zero();
};

/// A line for debug drawing: from, to, and what it shows.
struct ConstraintLine {
  enum class Kind : std::uint8_t { kAnchor, kAxis, kBroken };
  Vec3 from;
  Vec3 to;
  Kind kind;
};

/// Base of every joint.
class Constraint {
 public:
  virtual ~Constraint() = default;
  Constraint(const Constraint&) = delete;
  Constraint& operator=(const Constraint&) = delete;

  ConstraintType type() const { return type_; }
  BodyID body_a() const { return body_a_; }  ///< invalid: fixed to the world
  BodyID body_b() const { return body_b_; }
  /// A constraint breaks (and stops acting) in the step in which its force or torque passes these;
  /// 0 = unbreakable.
  float max_force() const { return max_force_; }
  float max_torque() const { return max_torque_; }
  bool broken() const { return broken_; }
  bool collide_connected() const { return collide_connected_; }
  bool enabled() const { return enabled_; }
  void set_enabled(bool enabled) { enabled_ = enabled; }
  /// Its force and torque over the last step it was solved in.
  const ConstraintForces& forces() const { return forces_; }
  /// One line, its kind and what it holds.
  virtual std::string Describe() const = 0;
  /// Lines for a debug view, from the bodies' poses.
  virtual void Draw(const BodyFrame& a, const BodyFrame& b, std::vector<ConstraintLine>& lines) const;

  // The step's side, in this order each step. BeginStep (one thread, every body lock held) binds the sides
  // and rescales the kept impulses to the new substep; the passes run on one job at a time.
  void BeginStep(const ConstraintSide& a, const ConstraintSide& b, float h);
  const ConstraintSide& side_a() const { return side_a_; }
  const ConstraintSide& side_b() const { return side_b_; }
  /// The pass's view of the two bodies; `scratch_a`/`scratch_b` stand in for a side that does not move.
  ConstraintBodies BodiesForPass(SolverBody* bodies, const SolverPose* poses, float elapsed,
                                 SolverBody& scratch_a, SolverBody& scratch_b) const;
  /// Applies the accumulated impulses (every substep, as contacts do).
  virtual void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) = 0;
  /// One Gauss-Seidel pass over the rows: with the drift bias in velocity passes, without in relax passes.
  /// Without `rigid_rows` it leaves the rows that always hold to ExactJointSolver.
  virtual void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass,
                             bool rigid_rows) = 0;
  /// The most rigid rows a joint has (a fixed joint's six).
  static constexpr int kMaxRigidRows = 6;
  /// How many rows always hold: the anchor point, the hinge axis, a fixed rotation, a rod's length.
  virtual int RigidRowCount() const = 0;
  /// Whether those are all its rows (no limit, motor, friction or spring): with them solved by
  /// ExactJointSolver, SolveVelocity has nothing left to do.
  virtual bool OnlyRigidRows() const { return false; }
  /// Sets those rows up from the pass's poses and writes them (RigidRowCount() of them).
  virtual void RigidRows(const ConstraintBodies& bodies, JointRow* rows) = 0;
  /// The most directions a joint's other rows (limits, motors, friction, springs) act along.
  static constexpr int kMaxFreeRows = 2;
  /// Sets the joint up from the pass's poses, as its passes would, and writes one row per direction its
  /// other rows act along (a hinge's limits and motor share its axis), in an order of its own; returns how
  /// many.
  virtual int FreeRows(const ConstraintBodies& /*bodies*/, const ConstraintPassContext& /*pass*/,
                       JointRow* /*rows*/) {
    return 0;
  }
  /// The most rows a joint solves along those directions.
  static constexpr int kMaxFreeRowPasses = 3;
  /// After FreeRows at the pass's poses: the rows the pass solves along those directions, in the order
  /// SolveVelocity solves them; returns how many. ExactJointSolver solves them against the island's rigid
  /// rows: against its two bodies alone, a limit between a heavy flap and a light block welded in place
  /// would move the flap a thousandth of the way per pass, the rest going to the block, which the rigid rows
  /// then hold still.
  virtual int FreeRowPasses(const ConstraintPassContext& /*pass*/, FreeRowPass* /*rows*/) { return 0; }
  /// What SolveVelocity has left when ExactJointSolver solves the rigid rows and FreeRowPasses (a
  /// swing-twist's friction, whose three rows share one 3 x 3 effective mass).
  virtual void SolveUnreducibleRows(ConstraintBodies& /*bodies*/, const ConstraintPassContext& /*pass*/) {}
  /// Joins the islands of its two sides when both move this step (after BeginStep), so they are solved,
  /// sleep and wake together.
  void LinkIslands(IslandBuilder& islands) const;
  /// The share of the rigid rows' position error one position step removes (Jolt's Baumgarte factor).
  static constexpr float kPositionFraction = 0.2f;
  /// After the step's last substep: moves the sides (poses and their motion since the step began, not
  /// their velocities) to take kPositionFraction of its rigid rows' position errors out, the rows solved
  /// together: integrating a link that turns fast moves its anchor off the circle it turns on, which
  /// velocity rows cannot see. Joints whose rows ExactJointSolver solves are corrected by it instead.
  void SolvePosition(SolverBody* bodies, SolverPose* poses, float elapsed);
  /// After the step (one thread): forces from the last substep's impulses; breaks past the limits.
  void EndStep();

 protected:
  /// `frame_a`/`frame_b`: the joint's frame (x = its axis) in each body's frame, anchors from each centre
  /// of mass in that frame.
  struct LocalFrames {
    Vec3 anchor_a = Vec3::Zero();
    Vec3 anchor_b = Vec3::Zero();
    Quat frame_a = Quat::Identity();
    Quat frame_b = Quat::Identity();
  };
  /// The arms from the centres of mass to the anchors now, world.
  struct WorldArms {
    Vec3 r_a;
    Vec3 r_b;
    Vec3 separation;  ///< B's anchor minus A's
  };
  /// The frames now: the arms and the joint axes, world.
  struct WorldFrames : WorldArms {
    Quat frame_a;  ///< the joint's frame on A, world
    Quat frame_b;
    Mat3 axes_a;  ///< frame_a's columns: the joint's x, y, z on A
    Mat3 axes_b;
  };
  struct Impulses {
    Vec3 linear = Vec3::Zero();  ///< on B, world
    Vec3 angular = Vec3::Zero();
  };

  Constraint(ConstraintType type, const JointSettingsBase& settings, const LocalFrames& frames);
  /// Frames from a world anchor and axes (x = `axis`, y = `normal`) and the bodies where they are now.
  static LocalFrames MakeLocalFrames(const BodyFrame& a, const BodyFrame& b, const Vec3& anchor_a,
                                     const Vec3& anchor_b, const Vec3& axis, const Vec3& normal);
  WorldArms Arms(const ConstraintBodies& bodies) const;
  WorldFrames Frames(const ConstraintBodies& bodies) const;
  /// Whether the pass must set the rows up: not when they were set up this step from the poses the pass
  /// sees (its pose version), as a substep's velocity passes see its warm start's. Every pass's rows are
  /// then the same as if set up anew, at a fraction of the cost (Jolt's budget runs ten velocity passes
  /// over one pose).
  bool NeedsSetUp(const ConstraintPassContext& pass) {
    if (pass.pose_version >= 0 && pass.pose_version == set_up_version_) return false;
    set_up_version_ = pass.pose_version;
    return true;
  }
  const LocalFrames& local() const { return local_; }
  /// B's frame relative to A's when the joint was made (the fixed joint's target).
  Quat RestRotation() const { return local_.frame_a * local_.frame_b.conjugate(); }

  /// Accumulated impulses of the substep, on B.
  virtual Impulses AccumulatedImpulses() const = 0;
  virtual void ScaleImpulses(float ratio) = 0;

 private:
  ConstraintType type_;
  BodyID body_a_;
  BodyID body_b_;
  LocalFrames local_;
  float max_force_;
  float max_torque_;
  bool collide_connected_ = false;
  bool broken_ = false;
  bool enabled_ = true;
  ConstraintSide side_a_;
  ConstraintSide side_b_;
  float substep_ = 0.0f;     // of the last step, to rescale kept impulses
  int set_up_version_ = -1;  // the pose version this step's rows were last set up at (-1: none)
  ConstraintForces forces_;
};

}  // namespace strata
