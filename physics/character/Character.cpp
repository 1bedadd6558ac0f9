#include "physics/character/Character.h"

#include <cmath>

#include "physics/body/BodyInterface.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/world/PhysicsSystem.h"

namespace strata {

namespace {

// Slides along at most this many surfaces a move: a corner of two walls and a floor, and one more.
constexpr int kMaxSlides = 4;
// Depenetration passes an update: each moves out of the deepest overlap left.
constexpr int kMaxDepenetrations = 4;
// Lengths below this are no move at all (m).
constexpr float kNoMove = 1e-6f;
// A contact on the capsule's round bottom within 60 degrees of straight down bears it like the face beside
// the edge it is on (walking off a step); one higher up the side does not (a riser it must not climb).
constexpr float kEdgeSupport = 0.5f;

const Vec3 kUp = Vec3::UnitY();

Vec3 Horizontal(const Vec3& v) {
  return {v.x(), 0.0f, v.z()};
}

Status Invalid(const std::string& message) {
  return MakeError(ErrorCode::kInvalidArgument, "character: " + message);
}

// Takes out of `motion` the part going into a surface of normal `normal` (unit, out of the surface).
Vec3 AlongSurface(const Vec3& motion, const Vec3& normal) {
  const float into = motion.dot(normal);
  return into < 0.0f ? Vec3(motion - into * normal) : motion;
}

}  // namespace

Status CharacterSettings::Validate() const {
  if (!IsFinite(radius) || radius <= 0.0f) return Invalid("radius must be a positive finite number");
  if (!IsFinite(height) || height < 2.0f * radius) return Invalid("height must be at least twice the radius");
  if (!(max_slope_degrees > 0.0f && max_slope_degrees < 90.0f))
    return Invalid("max_slope_degrees must be in (0, 90)");
  if (!IsFinite(max_step_height) || max_step_height < 0.0f) return Invalid("max_step_height must be >= 0");
  if (!IsFinite(stick_to_floor_distance) || stick_to_floor_distance < 0.0f)
    return Invalid("stick_to_floor_distance must be >= 0");
  if (!(skin > 0.0f && skin <= 0.5f * radius)) return Invalid("skin must be in (0, radius / 2]");
  if (!IsFinite(mass) || mass <= 0.0f) return Invalid("mass must be a positive finite number");
  if (!IsFinite(max_push_force) || max_push_force < 0.0f) return Invalid("max_push_force must be >= 0");
  return Status::Ok();
}

Result<std::unique_ptr<Character>> Character::Create(PhysicsSystem& world, const CharacterSettings& settings,
                                                     const Vec3& feet) {
  if (Status valid = settings.Validate(); !valid) return valid.error();
  if (!IsFinite(feet)) return Invalid("position must be finite").error();
  Result<ShapeRef> shape = CapsuleShape::Create(0.5f * settings.height - settings.radius, settings.radius);
  if (!shape) return shape.error();
  auto character = std::unique_ptr<Character>(new Character(world, settings, std::move(*shape), feet));
  character->FindGround();
  return character;
}

Character::Character(PhysicsSystem& world, const CharacterSettings& settings, ShapeRef shape,
                     const Vec3& feet)
    : world_(world),
      settings_(settings),
      shape_(std::move(shape)),
      half_height_(0.5f * settings.height),
      cos_max_slope_(std::cos(settings.max_slope_degrees * kPi / 180.0f)),
      feet_(feet) {
  settings_.filter.sensors = false;  // a trigger volume never stops anyone
}

Status Character::Teleport(const Vec3& feet) {
  if (!IsFinite(feet)) return Invalid("position must be finite");
  feet_ = feet;
  velocity_.setZero();
  walking_.setZero();
  ground_velocity_.setZero();
  ground_ = {};
  FindGround();
  return Status::Ok();
}

std::optional<ShapeCastResult> Character::Cast(const Vec3& center, const Vec3& displacement) const {
  ShapeCastSettings cast;
  // It keeps a skin's gap but may end up a hair inside a surface (rounding, a body that moved): it can always
  // leave one.
  cast.ignore_overlaps_moving_out = true;
  const Result<std::optional<ShapeCastResult>> hit =
      world_.query().CastShape(*shape_, Pose{center, Quat::Identity()}, displacement, cast, settings_.filter);
  return hit ? *hit : std::nullopt;
}

Status Character::Update(float dt, const Vec3& desired_velocity, const Vec3& gravity) {
  if (!IsFinite(dt) || dt <= 0.0f) return Invalid("update dt must be a positive finite number");
  if (!IsFinite(desired_velocity) || !IsFinite(gravity)) return Invalid("velocities must be finite");
  contacts_.clear();
  RideGround(dt);
  Depenetrate();
  const bool was_on_ground = ground_state_ == GroundState::kOnGround;
  const bool jumps = was_on_ground && desired_velocity.y() > 0.0f;
  const Vec3 walk = Horizontal(desired_velocity);
  Vec3 walking = walk;
  if (jumps) {
    // Off a moving platform it keeps the platform's motion.
    velocity_ = desired_velocity.y() * kUp + ground_velocity_;
  } else if (was_on_ground) {
    // Along the ground at the asked speed: up and down slopes, never into them.
    velocity_.setZero();
    const Vec3 along = walk - ground_.normal * ground_.normal.dot(walk);
    walking = along.squaredNorm() > kNoMove * kNoMove ? Vec3(along.normalized() * walk.norm()) : Vec3::Zero();
  } else {
    velocity_ += gravity * dt;
  }
  const Vec3 start_feet = feet_;
  const bool walks_on = was_on_ground && !jumps;
  const MoveResult moved = Move((walking + velocity_) * dt, dt, walks_on, true);
  if (walks_on && moved.hit_wall) StepUp(start_feet, Horizontal(walking * dt), feet_);
  FindGround();
  if (walks_on && ground_state_ != GroundState::kOnGround) StickToFloor(dt);
  if (ground_state_ == GroundState::kOnGround) {
    // Down to a skin above it: a step's edge or a landing may have left it hovering a little higher.
    feet_ -= kUp * std::max(0.0f, ground_.gap - settings_.skin);
    ground_.gap = std::min(ground_.gap, settings_.skin);
    velocity_.setZero();
    // Its weight on a body that can move.
    const Result<MotionType> motion = world_.bodies().GetMotionType(ground_.body);
    if (motion && *motion == MotionType::kDynamic)
      (void)world_.bodies().AddImpulse(ground_.body, settings_.mass * dt * gravity, feet_);
  } else if (walks_on && ground_state_ == GroundState::kInAir) {
    velocity_ += ground_velocity_;  // walked off a moving platform: it goes on with the platform's motion
  }
  walking_ = walking;
  return Status::Ok();
}

void Character::RideGround(float dt) {
  ground_velocity_.setZero();
  if (ground_state_ == GroundState::kInAir || ground_.body == BodyID{} || !ground_moves_) return;
  const Result<Vec3> position = world_.bodies().GetPosition(ground_.body);
  const Result<Quat> rotation = world_.bodies().GetRotation(ground_.body);
  if (!position || !rotation) return;  // the ground left the world
  // Where the feet were on the body as the last update ended, with the body where it is now.
  const Vec3 carry = Pose{*position, *rotation}.ToWorld(ground_.pose.ToLocal(feet_)) - feet_;
  ground_velocity_ = carry / dt;
  Move(carry, dt, false, false);
}

void Character::Depenetrate() {
  for (int pass = 0; pass < kMaxDepenetrations; ++pass) {
    const Result<std::vector<ShapeOverlap>> overlaps =
        world_.query().CollideShape(*shape_, Pose{center(), Quat::Identity()}, settings_.filter);
    if (!overlaps) return;
    const ShapeOverlap* deepest = nullptr;
    for (const ShapeOverlap& overlap : *overlaps)
      if (!deepest || overlap.penetration > deepest->penetration) deepest = &overlap;
    // The skin leaves room for rounding: a hair of overlap is no reason to move.
    if (deepest == nullptr || deepest->penetration < 0.25f * settings_.skin) return;
    // Out along the body's normal, by a cast so that the way out never leads into something else.
    const Vec3 out = -deepest->normal * (deepest->penetration + 0.5f * settings_.skin);
    const std::optional<ShapeCastResult> hit = Cast(center(), out);
    const float length = out.norm();
    const float travel = hit ? std::max(0.0f, hit->fraction * length - settings_.skin) : length;
    if (travel <= kNoMove) return;
    feet_ += out * (travel / length);
  }
}

Character::MoveResult Character::Move(const Vec3& displacement, float dt, bool on_ground, bool push) {
  MoveResult result;
  const Vec3 velocity = displacement / dt;
  Vec3 remaining = displacement;
  Vec3 planes[kMaxSlides];
  int plane_count = 0;
  for (int slide = 0; slide < kMaxSlides && remaining.norm() > kNoMove; ++slide) {
    const std::optional<ShapeCastResult> hit = Cast(center(), remaining);
    if (!hit) {
      feet_ += remaining;
      result.moved += remaining;
      return result;
    }
    const float length = remaining.norm();
    const Vec3 direction = remaining / length;
    // Stop a skin short of the surface, measured along its normal.
    const float approach = std::max(-direction.dot(hit->normal), 1e-3f);
    const float travel = std::max(0.0f, hit->fraction * length - settings_.skin / approach);
    feet_ += direction * travel;
    result.moved += direction * travel;
    contacts_.push_back({hit->body, hit->point, hit->normal, push ? Push(*hit, velocity, dt) : Vec3::Zero()});
    remaining = direction * (length - travel);
    // A surface too steep to stand on is a wall to whatever moves sideways (walking never climbs it), and a
    // slope that falling slides down.
    Vec3 plane = hit->normal;
    if (!Walkable(hit->normal)) {
      const Vec3 wall = Horizontal(hit->normal);
      const Vec3 sideways = Horizontal(remaining), upright = remaining - sideways;
      const Vec3 sideways_left = wall.squaredNorm() > 1e-8f ? AlongSurface(sideways, wall.normalized())
                                                            : AlongSurface(sideways, plane);
      remaining = sideways_left + AlongSurface(upright, plane);
      result.hit_wall = result.hit_wall || (on_ground && std::abs(hit->normal.y()) < cos_max_slope_);
      if (wall.squaredNorm() > 1e-8f) plane = wall.normalized();
    } else {
      remaining = AlongSurface(remaining, plane);
    }
    // What gravity gave it slides along the surface as it is (down a steep slope, faster and faster).
    velocity_ = AlongSurface(velocity_, hit->normal);
    // Into a surface met before: along the crease of the two, or not at all in a corner of three.
    for (int k = 0; k < plane_count; ++k) {
      if (remaining.dot(planes[k]) >= -kNoMove) continue;
      const Vec3 crease = planes[k].cross(plane);
      if (crease.squaredNorm() < 1e-8f) {
        remaining.setZero();
        break;
      }
      const Vec3 along = crease.normalized();
      remaining = along * along.dot(remaining);
      for (int j = 0; j < plane_count; ++j)
        if (j != k && remaining.dot(planes[j]) < -kNoMove) remaining.setZero();
      break;
    }
    planes[plane_count++] = plane;
  }
  return result;
}

bool Character::StepUp(const Vec3& start_feet, const Vec3& horizontal, const Vec3& reached) {
  const float across = horizontal.norm();
  if (across <= kNoMove || settings_.max_step_height <= 0.0f) return false;
  const Vec3 start = start_feet + Vec3(0.0f, half_height_, 0.0f);
  // Up by the step height, as far as the headroom lets it.
  const Vec3 up = kUp * settings_.max_step_height;
  const std::optional<ShapeCastResult> ceiling = Cast(start, up);
  const float rise = ceiling ? std::max(0.0f, ceiling->fraction * settings_.max_step_height - settings_.skin)
                             : settings_.max_step_height;
  if (rise <= settings_.skin) return false;
  const Vec3 raised = start + kUp * rise;
  // Across, where the step's riser stopped it below: at least far enough that the round bottom comes down on
  // the step's edge at a walkable slant (a frame's walk may be less than that).
  const Vec3 direction = horizontal / across;
  const float sin_max_slope = std::sqrt(1.0f - cos_max_slope_ * cos_max_slope_);
  const float least = settings_.radius * (1.0f - sin_max_slope) + 2.0f * settings_.skin;
  const float reach = std::max(across, least);
  const std::optional<ShapeCastResult> wall = Cast(raised, direction * reach);
  const float forward =
      wall ? std::max(0.0f,
                      wall->fraction * reach - settings_.skin / std::max(-direction.dot(wall->normal), 1e-3f))
           : reach;
  const Vec3 over = raised + direction * forward;
  // Down onto the step: walkable ground no lower than where it started.
  const std::optional<ShapeCastResult> tread = Cast(over, -kUp * rise);
  if (!tread || tread->penetration > 0.0f || !Walkable(tread->normal)) return false;
  const Vec3 landed = over - kUp * std::max(0.0f, tread->fraction * rise - settings_.skin);
  // Worth it only if it got farther than the walk did.
  if (Horizontal(landed - start).norm() <= Horizontal(reached - start_feet).norm() + kNoMove) return false;
  feet_ = landed - Vec3(0.0f, half_height_, 0.0f);
  return true;
}

bool Character::StickToFloor(float dt) {
  if (settings_.stick_to_floor_distance <= 0.0f) return false;
  // Down, sliding off the edge it may still hang on, onto walkable ground; or back where it was, to fall.
  const Vec3 feet = feet_, velocity = velocity_;
  Move(-kUp * settings_.stick_to_floor_distance, dt, false, false);
  velocity_ = velocity;
  FindGround();
  if (ground_state_ == GroundState::kOnGround) return true;
  feet_ = feet;
  FindGround();
  return false;
}

void Character::FindGround() {
  ground_ = {};
  ground_moves_ = false;
  ground_state_ = GroundState::kInAir;
  // What lies within two skins under the capsule; the most upward-facing of it is what it stands on.
  ShapeCastSettings cast;
  cast.ignore_overlaps_moving_out = true;
  const Result<std::vector<ShapeCastResult>> hits = world_.query().CastShapeAll(
      *shape_, Pose{center(), Quat::Identity()}, -kUp * (2.0f * settings_.skin), cast, settings_.filter);
  if (!hits) return;
  const ShapeCastResult* support = nullptr;
  Vec3 support_normal = Vec3::Zero();
  for (const ShapeCastResult& hit : *hits) {
    const Vec3 normal = SupportNormal(hit);
    if (normal.y() > 0.0f && (!support || normal.y() > support_normal.y()))
      support = &hit, support_normal = normal;
  }
  if (support == nullptr) return;
  ground_.body = support->body;
  ground_.normal = support_normal;
  ground_.gap = support->fraction * 2.0f * settings_.skin;
  ground_state_ = Walkable(support_normal) ? GroundState::kOnGround : GroundState::kOnSteepGround;
  // Remember where a body that can move was, to go with it.
  const Result<MotionType> motion = world_.bodies().GetMotionType(support->body);
  if (!motion || *motion == MotionType::kStatic) return;
  const Result<Vec3> position = world_.bodies().GetPosition(support->body);
  const Result<Quat> rotation = world_.bodies().GetRotation(support->body);
  if (!position || !rotation) return;
  ground_.pose = Pose{*position, *rotation};
  ground_moves_ = true;
}

Vec3 Character::SupportNormal(const ShapeCastResult& hit) const {
  if (Walkable(hit.normal) || hit.normal.y() < kEdgeSupport) return hit.normal;
  // The capsule's round bottom meets the edge of a step or a ledge at a slant; what it stands on there is the
  // surface beside the edge, found by a short ray straight down just inside it (from high enough to start
  // above a slope of up to 60 degrees, where the contact is on a slope and not an edge).
  const Vec3 inward = -Horizontal(hit.normal).normalized();
  const float reach = 0.5f * settings_.skin;
  const Vec3 origin = hit.point + inward * reach + kUp * (3.0f * reach);
  const Result<std::optional<RayCastHit>> surface =
      world_.query().CastRay(origin, -kUp * (6.0f * reach), settings_.filter);
  if (!surface || !surface->has_value()) return hit.normal;
  return (*surface)->normal;
}

Vec3 Character::Push(const ShapeCastResult& hit, const Vec3& velocity, float dt) {
  const Result<MotionType> motion = world_.bodies().GetMotionType(hit.body);
  if (!motion || *motion != MotionType::kDynamic || settings_.max_push_force <= 0.0f) return Vec3::Zero();
  const Vec3 into = -hit.normal;
  const float speed = velocity.dot(into);
  if (speed <= 0.0f) return Vec3::Zero();
  // The body's own speed at the contact, away from the character.
  const Result<Vec3> linear = world_.bodies().GetLinearVelocity(hit.body);
  const Result<Vec3> angular = world_.bodies().GetAngularVelocity(hit.body);
  const Result<Vec3> center_of_mass = world_.bodies().GetCenterOfMass(hit.body);
  if (!linear || !angular || !center_of_mass) return Vec3::Zero();
  const float body_speed = (*linear + angular->cross(hit.point - *center_of_mass)).dot(into);
  if (body_speed >= speed) return Vec3::Zero();
  // Its momentum's worth of the difference, at most its strength for the frame.
  const float impulse = std::min(settings_.mass * (speed - body_speed), settings_.max_push_force * dt);
  const Vec3 push = into * impulse;
  if (!world_.bodies().AddImpulse(hit.body, push, hit.point)) return Vec3::Zero();
  return push;
}

}  // namespace strata
