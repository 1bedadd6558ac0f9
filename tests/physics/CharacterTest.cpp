// The virtual character: steps, slopes, stairs, moving platforms, pushing bodies, and 1,000 random walks
// through the bundled levels that never end inside them.
#include <random>

#include "TestWorld.h"
#include "assets/level/LevelLoader.h"
#include "physics/character/Character.h"

namespace strata::test {
namespace {

constexpr float kDt = 1.0f / 60.0f;
const Vec3 kGravity(0, -9.81f, 0);

std::unique_ptr<Character> MakeCharacter(PhysicsSystem& world, const Vec3& feet,
                                         const CharacterSettings& settings = {}) {
  auto character = Character::Create(world, settings, feet);
  EXPECT_TRUE(character.ok()) << (character.ok() ? "" : character.error().message);
  return std::move(*character);
}

// Updates the character `frames` times (the world stands still).
void Walk(Character& character, const Vec3& velocity, int frames) {
  for (int frame = 0; frame < frames; ++frame) ASSERT_TRUE(character.Update(kDt, velocity, kGravity).ok());
}

// How deep the capsule sits inside anything (m).
float Penetration(PhysicsSystem& world, const Character& character) {
  const auto overlaps =
      world.query().CollideShape(*character.shape(), Pose{character.center(), Quat::Identity()});
  float deepest = 0.0f;
  for (const ShapeOverlap& overlap : *overlaps) deepest = std::max(deepest, overlap.penetration);
  return deepest;
}

// A floor with a box step of `height` from x = 2 on.
std::unique_ptr<PhysicsSystem> StepWorld(float height) {
  auto world = MakeWorld();
  Add(*world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
  Add(*world, Static(Box(5, height / 2, 5), Vec3(7, height / 2, 0)));
  return world;
}

TEST(Character, ClimbsAThirtyCentimetreStepButNotASixtyCentimetreOne) {
  auto low = StepWorld(0.3f);
  auto climber = MakeCharacter(*low, Vec3(0, 0.02f, 0));
  EXPECT_EQ(climber->ground_state(), GroundState::kOnGround);
  Walk(*climber, Vec3(2, 0, 0), 120);
  EXPECT_GT(climber->feet().x(), 3.0f);
  EXPECT_NEAR(climber->feet().y(), 0.3f + climber->settings().skin, 0.01f);
  EXPECT_EQ(climber->ground_state(), GroundState::kOnGround);

  auto high = StepWorld(0.6f);
  auto blocked = MakeCharacter(*high, Vec3(0, 0.02f, 0));
  Walk(*blocked, Vec3(2, 0, 0), 120);
  EXPECT_LT(blocked->feet().x(), 2.0f - blocked->settings().radius + 0.01f);
  EXPECT_NEAR(blocked->feet().y(), blocked->settings().skin, 0.01f);
  EXPECT_LT(Penetration(*high, *blocked), 1e-3f);
}

// A 40 m plane through the origin tilted `degrees` about z (rising towards -x).
std::unique_ptr<PhysicsSystem> SlopeWorld(float degrees) {
  auto world = MakeWorld();
  const Quat tilt(Eigen::AngleAxisf(-degrees * kPi / 180.0f, Vec3::UnitZ()));
  Add(*world, Static(Box(20, 1, 20), tilt * Vec3(0, -1, 0), tilt));
  return world;
}

TEST(Character, HoldsOnAFortyDegreeSlopeAndSlidesOnFiftyWithMaxFortyFive) {
  CharacterSettings settings;
  settings.max_slope_degrees = 45.0f;
  for (const float degrees : {40.0f, 50.0f}) {
    auto world = SlopeWorld(degrees);
    // Dropped onto the slope above the origin, then left alone for a second.
    auto character = MakeCharacter(*world, Vec3(0, 1, 0), settings);
    Walk(*character, Vec3::Zero(), 60);
    const Vec3 settled = character->feet();
    Walk(*character, Vec3::Zero(), 60);
    const float slid = (character->feet() - settled).norm();
    if (degrees < 45.0f) {
      EXPECT_EQ(character->ground_state(), GroundState::kOnGround);
      EXPECT_LT(slid, 0.01f);
    } else {
      EXPECT_EQ(character->ground_state(), GroundState::kOnSteepGround);
      EXPECT_GT(slid, 3.0f);                          // a second of g sin 50 degrees: 3.8 m
      EXPECT_GT(character->feet().x(), settled.x());  // down the slope
    }
    EXPECT_LT(Penetration(*world, *character), 1e-3f);
  }
}

TEST(Character, WalkingIntoASteepSlopeNeverClimbsIt) {
  auto world = SlopeWorld(60.0f);
  Add(*world, Static(Box(20, 1, 20), Vec3(0, -4, 0)));
  auto character = MakeCharacter(*world, Vec3(4, -2.98f, 0));
  Walk(*character, Vec3(-3, 0, 0), 180);
  EXPECT_LT(character->feet().y(), -2.5f);
}

TEST(Character, StaysGroundedWalkingDownThirtyCentimetreStairs) {
  auto world = MakeWorld();
  Add(*world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
  // Ten 0.3 m steps, 0.6 m deep, falling towards +x from 3 m.
  for (int i = 0; i < 10; ++i) {
    const float top = 3.0f - 0.3f * static_cast<float>(i);
    Add(*world, Static(Box(0.3f, top / 2, 2), Vec3(0.3f + 0.6f * static_cast<float>(i), top / 2, 0)));
  }
  auto character = MakeCharacter(*world, Vec3(0.3f, 3.02f, 0));
  ASSERT_EQ(character->ground_state(), GroundState::kOnGround);
  float lowest = 10.0f;
  for (int frame = 0; frame < 240; ++frame) {
    ASSERT_TRUE(character->Update(kDt, Vec3(2, 0, 0), kGravity).ok());
    EXPECT_EQ(character->ground_state(), GroundState::kOnGround) << "frame " << frame;
    lowest = std::min(lowest, character->feet().y());
  }
  EXPECT_GT(character->feet().x(), 7.0f);
  EXPECT_LT(lowest, 0.05f);
  EXPECT_LT(Penetration(*world, *character), 1e-3f);
}

TEST(Character, RidesAMovingPlatformForFiveSecondsWithinACentimetre) {
  auto world = MakeWorld();
  BodyCreationSettings platform = Static(Box(3, 0.2f, 3), Vec3(0, 1, 0));
  platform.motion_type = MotionType::kKinematic;
  platform.object_layer = layers::kMoving;
  platform.linear_velocity = Vec3(1.0f, 0.2f, 0.5f);
  platform.angular_velocity = Vec3(0, 0.6f, 0);
  const BodyID id = Add(*world, platform);
  auto character = MakeCharacter(*world, Vec3(1, 1.22f, 0.5f));
  ASSERT_EQ(character->ground_body(), id);
  const Pose start_pose{Position(*world, id), *world->bodies().GetRotation(id)};
  const Vec3 on_platform = start_pose.ToLocal(character->feet());
  float farthest = 0.0f;
  for (int frame = 0; frame < 300; ++frame) {
    ASSERT_TRUE(world->Step(kDt).ok());
    ASSERT_TRUE(character->Update(kDt, Vec3::Zero(), kGravity).ok());
    const Pose pose{Position(*world, id), *world->bodies().GetRotation(id)};
    farthest = std::max(farthest, (pose.ToLocal(character->feet()) - on_platform).norm());
  }
  EXPECT_LT(farthest, 0.01f);
  // It went places: the platform's centre 5.7 m, and a turn of 3 radians.
  EXPECT_GT((character->feet() - Vec3(1, 1.22f, 0.5f)).norm(), 3.0f);
  EXPECT_EQ(character->ground_body(), id);
}

TEST(Character, PushesATenKilogramCrateButNotATonne) {
  for (const float mass : {10.0f, 1000.0f}) {
    auto world = MakeWorld();
    Add(*world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
    BodyCreationSettings crate = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(2, 0.5f, 0));
    crate.mass = mass;
    const BodyID id = Add(*world, crate);
    StepFor(*world, 30);
    auto character = MakeCharacter(*world, Vec3(0, 0.02f, 0));
    float deepest = 0.0f;
    for (int frame = 0; frame < 240; ++frame) {
      ASSERT_TRUE(world->Step(kDt).ok());
      ASSERT_TRUE(character->Update(kDt, Vec3(1.5f, 0, 0), kGravity).ok());
      deepest = std::max(deepest, Penetration(*world, *character));
    }
    const float moved = Position(*world, id).x() - 2.0f;
    if (mass < 100.0f) {
      EXPECT_GT(moved, 3.0f);  // 4 s at 1.5 m/s, less the start
    } else {
      EXPECT_LT(moved, 0.05f);  // friction holds a tonne against 300 N
    }
    EXPECT_LT(deepest, 1e-3f);
    // The character never passed through the crate.
    EXPECT_LT(character->feet().x(), Position(*world, id).x() - 0.5f - character->settings().radius + 0.01f);
  }
}

TEST(Character, BadSettingsAndInputAreRefused) {
  auto world = MakeWorld();
  CharacterSettings settings;
  settings.height = 0.5f;  // less than two radii
  EXPECT_FALSE(Character::Create(*world, settings, Vec3::Zero()).ok());
  settings = {};
  settings.max_slope_degrees = 95.0f;
  EXPECT_FALSE(Character::Create(*world, settings, Vec3::Zero()).ok());
  EXPECT_FALSE(Character::Create(*world, {}, Vec3(NAN, 0, 0)).ok());
  auto character = MakeCharacter(*world, Vec3(0, 1, 0));
  EXPECT_FALSE(character->Update(0.0f, Vec3::Zero(), kGravity).ok());
  EXPECT_FALSE(character->Update(kDt, Vec3(INFINITY, 0, 0), kGravity).ok());
  EXPECT_EQ(character->feet(), Vec3(0, 1, 0));
}

// Random walks through a bundled level: each starts on a random floor point, changes direction and speed
// every half second and jumps now and then; after every update the capsule must be out of the level.
void RandomWalks(const char* level_file, int walks, int frames, std::uint32_t seed) {
  PhysicsSystemConfig config;
  config.job_system = std::make_shared<SerialJobSystem>();
  auto world = std::move(*PhysicsSystem::Create(config));
  const auto level = LoadLevel(*world, std::string(STRATA_LEVELS_DIR) + "/" + level_file);
  ASSERT_TRUE(level.ok()) << level.error().message;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> x(level->bounds.min.x(), level->bounds.max.x());
  std::uniform_real_distribution<float> z(level->bounds.min.z(), level->bounds.max.z());
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int started = 0;
  double walked = 0;
  for (int attempt = 0; attempt < 10 * walks && started < walks; ++attempt) {
    const int walk = started;
    // A floor under a random point, with room for the capsule above it.
    const Vec3 above(x(random), level->bounds.max.y() + 2.0f, z(random));
    const auto floor = world->query().CastRay(above, Vec3(0, -100, 0));
    if (!floor.ok() || !floor->has_value() || (*floor)->normal.y() < 0.7f) continue;
    auto character = MakeCharacter(*world, (*floor)->position + Vec3(0, 0.05f, 0));
    if (Penetration(*world, *character) > 0.0f) continue;  // under a ledge
    ++started;
    Vec3 velocity = Vec3::Zero();
    for (int frame = 0; frame < frames; ++frame) {
      if (frame % 30 == 0) {
        const float angle = 6.2832f * unit(random), speed = 6.0f * unit(random);
        velocity = Vec3(speed * std::cos(angle), unit(random) < 0.15f ? 5.0f : 0.0f, speed * std::sin(angle));
      }
      const Vec3 before = character->feet();
      ASSERT_TRUE(character->Update(kDt, velocity, kGravity).ok());
      walked += (character->feet() - before).norm();
      // The skin keeps it clear of everything: not even a rounding's worth inside.
      ASSERT_EQ(Penetration(*world, *character), 0.0f)
          << level_file << " walk " << walk << " frame " << frame << " at " << character->feet().transpose();
      // Off the level's edge (it may walk off the top of a perimeter wall) nothing is under it: the walk ends
      // there. Anywhere else there is, and it must never get below the level.
      const Vec3& feet = character->feet();
      const auto below = world->query().CastRay(feet + Vec3(0, 0.1f, 0),
                                                Vec3(0, level->bounds.min.y() - feet.y() - 1.0f, 0));
      if (feet.y() > level->bounds.min.y() && !below->has_value()) break;
      ASSERT_GT(feet.y(), level->bounds.min.y() - 0.1f)
          << "fell through " << level_file << " at " << feet.transpose();
    }
  }
  EXPECT_EQ(started, walks);
  EXPECT_GT(walked, 2.0 * walks);  // they did walk: about 4 m each
}

TEST(Character, NeverEndsInsideGeometryOnAThousandRandomWalksThroughTheBundledLevels) {
  RandomWalks("courtyard.obj", 700, 120, 11);
  RandomWalks("arena.glb", 300, 120, 12);
}

}  // namespace
}  // namespace strata::test
