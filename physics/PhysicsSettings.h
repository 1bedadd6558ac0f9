// PhysicsSettings: the tunables of the step, with units, validated in one place. Value type; change
// them between steps through PhysicsSystem::SetSettings.
#pragma once

#include <cstdint>

#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata {

/// When a body counts as resting (and its island may sleep once all of it has rested time_before_sleep).
enum class SleepRule : std::uint8_t {
  /// Its linear and angular speeds stay under sleep_linear_velocity and sleep_angular_velocity.
  kVelocity,
  /// Three points of it (its centre of mass, and the centre of mass moved out along its two longest bounds
  /// axes by their half extents) each stay within a sphere of sleep_point_velocity x time_before_sleep,
  /// however they jitter inside it: Jolt's rule (mPointVelocitySleepThreshold). Costs 48 bytes a body,
  /// taken only while this rule is in use.
  kPointMovement,
};

/// Step tunables. Units: metres, seconds.
/// The largest gravity PhysicsSettings accepts (m/s^2).
constexpr float kMaxGravity = 1.0e4f;

struct PhysicsSettings {
  Vec3 gravity = Vec3(0.0f, -9.81f, 0.0f);  ///< m/s^2
  /// The step is solved as this many substeps (Box2D v3's soft step): per substep gravity, warm start,
  /// velocity passes with a soft bias, integration, relax passes. More substeps make tall stacks and large
  /// mass ratios stiffer at about the cost of more iterations. Default chosen by `strata accuracy`.
  int substeps = 4;
  int velocity_iterations = 1;  ///< biased sequential-impulse passes per substep, >= 1
  int relax_iterations = 1;     ///< passes per substep without the bias (remove the push's energy), >= 0
  /// Passes of the bounce after the last substep (only in groups where something bounces). One pass gives
  /// the first point of a face hitting a wall most of the bounce and sets the body spinning: a box between
  /// walls with restitution 1 changes its energy by 154% in 60 s with one pass, 5.9% with two, 0.26% with
  /// four.
  int restitution_iterations = 4;
  /// Contacts are springs of this stiffness (Hz) with this damping ratio while they push overlap out; the
  /// stiffness is capped at a quarter of the substep rate, and contacts with a static body use twice it.
  float contact_hertz = 30.0f;
  float contact_damping_ratio = 10.0f;
  float contact_push_max_velocity = 3.0f;  ///< fastest speed at which overlap is pushed out (m/s)
  /// Joints' rigid rows are springs of this stiffness (Hz, capped at a quarter of the substep rate) and
  /// damping ratio while they push drift out (Box2D v3's joint softness); relax passes hold them rigid.
  float joint_hertz = 60.0f;
  float joint_damping_ratio = 2.0f;
  /// The rows of joints that always hold (anchor points, hinge axes, fixed rotations, rods) are solved
  /// exactly per group (ExactJointSolver) instead of joint after joint, in groups where a joint joins two
  /// moving bodies whose masses differ by `exact_joint_mass_ratio` or more: a 100-link chain of 1 kg links
  /// with a 100 kg end then stays within 0.1 mm where the passes let it stretch by 5 cm. Elsewhere the
  /// passes are enough and cheaper (a ragdoll's parts differ by less).
  bool exact_joints = true;
  float exact_joint_mass_ratio = 10.0f;
  /// Small resting islands of bodies on bodies (stacks, a heavy box on a light one) are solved exactly
  /// (ExactContactSolver) with springs scaled to the load each contact carries, instead of by the passes
  /// above: a 30-box tower then stands within 1 cm and a 1000 kg box on a 1 kg box sinks 0.3 mm, where
  /// the passes give 14 cm and slide off.
  bool exact_small_islands = true;
  bool allow_sleeping = true;                 ///< world-wide switch; bodies also have their own flag
  float speculative_distance = 0.02f;         ///< contacts are made this far before touching (m)
  float min_velocity_for_restitution = 1.0f;  ///< slower approaches do not bounce (m/s)
  /// Spin about a non-principal axis turns the angular velocity (Euler's equations, solved implicitly);
  /// off, angular velocity stays constant in free flight and angular momentum drifts.
  bool gyroscopic_torque = true;
  float contact_match_distance = 0.02f;  ///< points closer than this between steps share impulses (m)
  /// A touching pair reuses last step's contacts instead of a new shape test while, relative to each other,
  /// its bodies moved less than this since the contacts were made (m); 0 turns reuse off. Jolt allows 1 mm
  /// and 2 degrees; there a stack of eight boxes at ten velocity passes sways 2 cm in ten seconds against
  /// 0.9 cm at these defaults (0.7 cm without reuse), while a resting pyramid still reuses 97% of its pairs.
  float body_pair_cache_max_distance = 0.25e-3f;
  float body_pair_cache_max_angle = 1.0f;  ///< ...and turned less than this (degrees, [0, 180]; 0: no reuse)
  /// A box's face lying on another box's face (all four corners on it, none cut by its sides) is carried
  /// along however far it slides, while the pair turned less than the angle above and every corner stays
  /// on the face: the corners are then the contact a new test would find. A distance limit of 0 turns this
  /// off as well.
  bool body_pair_cache_slides = true;
  /// Two convex shapes a test found apart are passed over while their extents along the axis it found them
  /// apart along still leave a gap beyond the reach: a test would find them apart too, so no result changes.
  /// A distance limit of 0 turns this off as well, so that every pair is tested every step.
  bool body_pair_cache_separating_axis = true;
  float time_before_sleep = 0.5f;        ///< seconds a body must rest before its island sleeps
  float sleep_linear_velocity = 0.05f;   ///< m/s
  float sleep_angular_velocity = 0.05f;  ///< rad/s
  SleepRule sleep_rule = SleepRule::kVelocity;
  float sleep_point_velocity = 0.03f;  ///< m/s, for SleepRule::kPointMovement (Jolt's default)

  /// Checks every field; the message names the first bad one.
  Status Validate() const;
};

}  // namespace strata
