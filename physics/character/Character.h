// Character: a player or NPC as game code moves it: a virtual capsule (not a body: the solver never moves it
// and bodies do not collide with it) that walks over the world by shape casts, after Jolt's CharacterVirtual.
// It walks slopes up to a max angle and slides down steeper ones, steps up stairs, sticks to the ground going
// down slopes and stairs, rides moving platforms, pushes dynamic bodies with a bounded force and is never
// moved into static geometry. Threading: a Character belongs to the thread that updates it; its queries run
// like any WorldQuery (a body's read lock only to copy its shape and pose), so characters update on any
// threads while bodies change and the world steps. Update it after each world step.
#pragma once

#include <memory>
#include <vector>

#include "physics/broadphase/Layers.h"
#include "physics/core/Result.h"
#include "physics/shapes/Shape.h"
#include "physics/world/WorldQuery.h"

namespace strata {

class PhysicsSystem;

/// A character's size, limits and strength. Units: metres, kilograms, seconds, degrees. Up is +Y.
struct CharacterSettings {
  float radius = 0.3f;                   ///< of the capsule
  float height = 1.8f;                   ///< feet to head, at least twice the radius
  float max_slope_degrees = 45.0f;       ///< steeper ground is a wall it slides down, in (0, 90)
  float max_step_height = 0.35f;         ///< steps up to this high are climbed while walking, >= 0
  float stick_to_floor_distance = 0.5f;  ///< walking on, it follows the ground down this far in a frame, >= 0
  float skin = 0.02f;                    ///< gap it keeps from every surface, in (0, radius / 2]
  float mass = 70.0f;             ///< kg: the momentum it pushes bodies with and its weight on them, > 0
  float max_push_force = 300.0f;  ///< N: the most it pushes one dynamic body with, >= 0
  QueryFilter filter;             ///< what it collides with (sensors never stop it)

  /// Checks every field; the message names the first bad one.
  Status Validate() const;
};

/// What the character stands on after its last update.
enum class GroundState : std::uint8_t {
  kOnGround,       ///< walkable ground (no steeper than max_slope_degrees)
  kOnSteepGround,  ///< ground too steep to stand on: it slides
  kInAir,
};

/// A body the character met in its last update.
struct CharacterContact {
  BodyID body;
  Vec3 point = Vec3::Zero();    ///< on the body, world
  Vec3 normal = Vec3::UnitY();  ///< from the body towards the character
  Vec3 impulse = Vec3::Zero();  ///< what the character gave a dynamic body (N s)
};

/// A virtual capsule character in a world.
class Character {
 public:
  /// A character standing with its feet at `feet`. Fails on bad settings or a non-finite position.
  static Result<std::unique_ptr<Character>> Create(PhysicsSystem& world, const CharacterSettings& settings,
                                                   const Vec3& feet);

  /// Moves the character through `dt` seconds: `desired_velocity` is the walking velocity game code asks for
  /// (its horizontal part; an upward part is a jump, taken only on the ground), `gravity` pulls it while it
  /// is not on walkable ground. Fails (nothing changes) on a non-positive dt or non-finite input.
  Status Update(float dt, const Vec3& desired_velocity, const Vec3& gravity);
  /// Puts the feet at `feet` (no collision on the way) and forgets the ground and the velocity.
  Status Teleport(const Vec3& feet);

  /// The bottom of the capsule.
  const Vec3& feet() const { return feet_; }
  /// The centre of the capsule.
  Vec3 center() const { return feet_ + Vec3(0.0f, half_height_, 0.0f); }
  /// Its own velocity in the last update (m/s): walking, falling, sliding; without the ground's motion.
  Vec3 velocity() const { return walking_ + velocity_; }
  GroundState ground_state() const { return ground_state_; }
  /// The body it stands on (invalid in the air), its surface normal there and that point's velocity.
  BodyID ground_body() const { return ground_.body; }
  const Vec3& ground_normal() const { return ground_.normal; }
  const Vec3& ground_velocity() const { return ground_velocity_; }
  /// Every body it touched in its last update, in the order met.
  const std::vector<CharacterContact>& contacts() const { return contacts_; }
  const CharacterSettings& settings() const { return settings_; }
  const ShapeRef& shape() const { return shape_; }

 private:
  struct Ground {
    BodyID body;
    Vec3 normal = Vec3::UnitY();
    float gap = 0.0f;  // how far straight down it is (m)
    Pose pose;         // of a moving ground body when found, to follow it as it moves
  };
  /// Result of one collide-and-slide move.
  struct MoveResult {
    Vec3 moved = Vec3::Zero();
    bool hit_wall = false;  // met something too steep to walk up while going sideways
  };

  Character(PhysicsSystem& world, const CharacterSettings& settings, ShapeRef shape, const Vec3& feet);

  /// Follows the ground body's motion since the last update (a moving platform carries the character).
  void RideGround(float dt);
  /// Moves out of bodies that moved into the capsule since the last update.
  void Depenetrate();
  /// Collide and slide: moves by `displacement`, sliding along what it meets; with `push` it pushes the
  /// dynamic bodies it meets.
  MoveResult Move(const Vec3& displacement, float dt, bool on_ground, bool push);
  /// Climbs a step in the way of `horizontal` from `start_feet`; true if it did.
  bool StepUp(const Vec3& start_feet, const Vec3& horizontal, const Vec3& reached);
  /// Walking on, it follows the ground down (stairs, slopes); true if it found walkable ground.
  bool StickToFloor(float dt);
  /// Looks under the feet for ground and sets the ground state.
  void FindGround();
  /// The first thing the capsule meets moved from `center` by `displacement`.
  std::optional<ShapeCastResult> Cast(const Vec3& center, const Vec3& displacement) const;
  /// Gives a dynamic body the push of the character moving at `velocity` into it.
  Vec3 Push(const ShapeCastResult& hit, const Vec3& velocity, float dt);
  /// The normal of the surface that bears the character at a contact: the contact's own, or at an edge the
  /// face beside it that the round bottom of the capsule rests on.
  Vec3 SupportNormal(const ShapeCastResult& hit) const;
  bool Walkable(const Vec3& normal) const { return normal.y() >= cos_max_slope_; }

  PhysicsSystem& world_;
  CharacterSettings settings_;
  ShapeRef shape_;
  float half_height_;
  float cos_max_slope_;
  Vec3 feet_;
  Vec3 walking_ = Vec3::Zero();   // asked anew each update
  Vec3 velocity_ = Vec3::Zero();  // what gravity and jumps gave it (falling, sliding), kept between updates
  Vec3 ground_velocity_ = Vec3::Zero();
  GroundState ground_state_ = GroundState::kInAir;
  Ground ground_;
  bool ground_moves_ = false;  // the ground body is not static: RideGround follows it
  std::vector<CharacterContact> contacts_;
};

}  // namespace strata
