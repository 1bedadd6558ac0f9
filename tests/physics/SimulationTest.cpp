// Physical behaviour of the step: resting, stacking, bouncing, friction on inclines, momentum.
#include <cmath>
#include <span>
#include <vector>

#include "TestWorld.h"
#include "physics/core/ThreadPoolJobSystem.h"

namespace strata::test {
namespace {

BodyID Floor(PhysicsSystem& world, float friction = 0.5f, const Quat& rotation = Quat::Identity()) {
  BodyCreationSettings floor = Static(Box(50, 1, 50), Vec3(0, -1, 0), rotation);
  floor.friction = friction;
  return Add(world, floor);
}

// Sharp boxes meet face to face by separating axes, whose face contacts the pair cache can slide.
BodyID SharpFloor(PhysicsSystem& world) {
  return Add(world, Static(SharpBox(50, 1, 50), Vec3(0, -1, 0)));
}

// Appends each body's position and rotation (x y z, then w x y z) to `out`, for comparing runs exactly.
void AppendPoses(PhysicsSystem& world, std::span<const BodyID> ids, std::vector<float>& out) {
  for (const BodyID id : ids) {
    const Vec3 p = Position(world, id);
    const Quat q = *world.bodies().GetRotation(id);
    out.insert(out.end(), {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()});
  }
}

TEST(Simulation, StageTimingsCanBeLeftOutWithoutChangingTheStep) {
  Vec3 positions[2];
  for (const bool timed : {true, false}) {
    PhysicsSystemConfig config;
    config.max_bodies = 64;
    config.job_system = std::make_shared<SerialJobSystem>();
    config.stage_timings = timed;
    auto world = std::move(*PhysicsSystem::Create(config));
    Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
    const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 2, 0)));
    StepFor(*world, 60);
    positions[timed ? 0 : 1] = Position(*world, box);
    const StepProfile& profile = world->last_step_profile();
    if (timed) {
      EXPECT_GT(profile.stage_count, 5u);
      // The whole step holds every stage (an order between figures, no speed).
      EXPECT_GE(profile.total_ms, profile.stages[profile.stage_count - 1].end_ms);
    } else {
      EXPECT_EQ(profile.stage_count, 0u);
      EXPECT_EQ(profile.total_ms, 0.0);
    }
  }
  EXPECT_EQ(positions[0], positions[1]);
}

TEST(Simulation, RestingBoxPenetratesLessThanOneCentimetre) {
  auto world = MakeWorld();
  Floor(*world);
  const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
  StepFor(*world, 120);
  const float bottom = Position(*world, box).y() - 0.5f;
  EXPECT_GT(bottom, -0.01f);
  EXPECT_LT(bottom, 0.01f);
  EXPECT_LT(world->last_step_stats().max_penetration, 0.01f);
}

TEST(Simulation, StackOfTenBoxesStaysWithinFiveCentimetres) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;  // the solver, not sleeping, must hold the stack
  auto world = MakeWorld(settings);
  Floor(*world);
  std::vector<BodyID> boxes;
  std::vector<Vec3> starts;
  for (int i = 0; i < 10; ++i) {
    starts.emplace_back(0.0f, 0.5f + 1.0f * static_cast<float>(i), 0.0f);
    boxes.push_back(Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), starts.back())));
  }
  StepFor(*world, 600);
  for (int i = 0; i < 10; ++i)
    EXPECT_LT((Position(*world, boxes[i]) - starts[i]).norm(), 0.05f) << "box " << i;
}

TEST(Simulation, SphereReboundApexMatchesRestitution) {
  auto world = MakeWorld();
  BodyCreationSettings floor = Static(Box(50, 1, 50), Vec3(0, -1, 0));
  Add(*world, floor);
  BodyCreationSettings ball = Dynamic(Sphere(0.5f), Vec3(0, 2.5f, 0));  // bottom 2 m above the floor
  ball.restitution = 0.5f;
  ball.linear_damping = 0.0f;
  const BodyID sphere = Add(*world, ball);
  bool bounced = false;
  float apex = 0.0f;
  for (int step = 0; step < 240; ++step) {
    ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
    const float velocity = Velocity(*world, sphere).y();
    const float bottom = Position(*world, sphere).y() - 0.5f;
    if (!bounced && velocity > 0.0f) bounced = true;
    if (bounced) apex = std::max(apex, bottom);
    if (bounced && velocity < 0.0f) break;
  }
  ASSERT_TRUE(bounced);
  // e^2 * drop height.
  EXPECT_NEAR(apex, 0.5f, 0.025f);
}

struct InclineResult {
  float displacement;
  float acceleration;
};

InclineResult SlideOnIncline(float degrees, float yaw_degrees = 0.0f) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  const float angle = degrees * kPi / 180.0f;
  const Quat tilt = Quat(Eigen::AngleAxisf(yaw_degrees * kPi / 180.0f, Vec3::UnitY())) *
                    Quat(Eigen::AngleAxisf(angle, Vec3::UnitZ()));
  BodyCreationSettings ramp = Static(Box(20, 0.5f, 5), Vec3::Zero(), tilt);
  ramp.friction = 0.6f;
  Add(*world, ramp);
  BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), tilt * Vec3(0, 1.0f, 0), tilt);
  box.friction = 0.6f;
  box.linear_damping = 0.0f;
  box.angular_damping = 0.0f;
  const BodyID id = Add(*world, box);
  const Vec3 downhill = tilt * Vec3(-1, 0, 0);
  StepFor(*world, 30);  // settle onto the ramp
  const Vec3 start = Position(*world, id);
  const float v0 = Velocity(*world, id).dot(downhill);
  const float seconds = 1.0f;
  StepFor(*world, 60);
  const float v1 = Velocity(*world, id).dot(downhill);
  return {(Position(*world, id) - start).dot(downhill), (v1 - v0) / seconds};
}

TEST(Simulation, BoxSticksOnTwentyFiveDegreeInclineWithFrictionPointSix) {
  const InclineResult result = SlideOnIncline(25.0f);
  EXPECT_LT(std::abs(result.displacement), 0.01f);
}

TEST(Simulation, BoxSlidesOnThirtyFiveDegreeInclineWithCoulombAcceleration) {
  const InclineResult result = SlideOnIncline(35.0f);
  const float angle = 35.0f * kPi / 180.0f;
  const float expected = 9.81f * (std::sin(angle) - 0.6f * std::cos(angle));
  EXPECT_NEAR(result.acceleration, expected, 0.05f * expected);
}

TEST(Simulation, FrictionIsTheSameInEveryDirection) {
  // Yawing the ramp turns the sliding direction relative to the solver's tangent axes.
  const float angle = 35.0f * kPi / 180.0f;
  const float expected = 9.81f * (std::sin(angle) - 0.6f * std::cos(angle));
  for (float yaw : {30.0f, 45.0f, 110.0f}) {
    const InclineResult result = SlideOnIncline(35.0f, yaw);
    EXPECT_NEAR(result.acceleration, expected, 0.05f * expected) << "yaw " << yaw;
  }
}

// A frictionless contact has no friction rows at all (they would only clamp zero to zero): the box must still
// slide at its speed, upright, over dt and substeps, and frictionless boxes stacked on each other (solved
// together, with the friction patches the exact solve builds) must still stand.
TEST(Simulation, FrictionlessContactsSlideWithoutLosingSpeedAndStacksStillStand) {
  for (const float dt : {1.0f / 30.0f, 1.0f / 60.0f})
    for (const int substeps : {1, 4}) {
      PhysicsSettings settings;
      settings.substeps = substeps;
      settings.allow_sleeping = false;  // the stack is to be solved every step, not put to sleep
      auto world = MakeWorld(settings);
      BodyCreationSettings floor = Static(Box(50, 1, 50), Vec3(0, -1, 0));
      floor.friction = 0.0f;
      Add(*world, floor);
      BodyCreationSettings slider = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0));
      slider.friction = 0.0f;
      slider.linear_damping = 0.0f;
      slider.linear_velocity = Vec3(3, 0, 1);
      const BodyID sliding = Add(*world, slider);
      std::vector<BodyID> stack;
      for (int level = 0; level < 3; ++level) {
        BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(-20, 0.5f + level, 0));
        box.friction = 0.0f;
        stack.push_back(Add(*world, box));
      }
      StepFor(*world, static_cast<int>(2.0f / dt), dt);
      const std::string label = "dt " + std::to_string(dt) + ", substeps " + std::to_string(substeps);
      const Vec3 velocity = Velocity(*world, sliding);
      EXPECT_NEAR(velocity.x(), 3.0f, 1e-3f) << label;
      EXPECT_NEAR(velocity.z(), 1.0f, 1e-3f) << label;
      EXPECT_NEAR(Position(*world, sliding).y(), 0.5f, 0.01f) << label;
      EXPECT_LT(world->bodies().GetAngularVelocity(sliding)->norm(), 1e-3f) << label;
      EXPECT_GT(world->last_step_stats().exact_islands, 0u) << label;
      for (int level = 0; level < 3; ++level)
        EXPECT_LT((Position(*world, stack[level]) - Vec3(-20, 0.5f + level, 0)).norm(), 0.01f)
            << label << ", box " << level;
    }
}

TEST(Simulation, HeadOnSphereCollisionConservesMomentum) {
  PhysicsSettings settings;
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  BodyCreationSettings left = Dynamic(Sphere(0.5f), Vec3(-2, 0, 0));
  left.linear_velocity = Vec3(3, 0, 0);
  left.mass = 2.0f;
  left.restitution = 0.8f;
  left.linear_damping = 0.0f;
  BodyCreationSettings right = Dynamic(Sphere(0.5f), Vec3(2, 0, 0));
  right.linear_velocity = Vec3(-1, 0, 0);
  right.mass = 1.0f;
  right.linear_damping = 0.0f;
  const BodyID a = Add(*world, left);
  const BodyID b = Add(*world, right);
  const Vec3 before = 2.0f * Velocity(*world, a) + 1.0f * Velocity(*world, b);
  StepFor(*world, 120);
  const Vec3 after = 2.0f * Velocity(*world, a) + 1.0f * Velocity(*world, b);
  // They did collide: the light sphere now moves right.
  EXPECT_GT(Velocity(*world, b).x(), 0.0f);
  EXPECT_LT((after - before).norm(), 0.001f * before.norm());
}

std::vector<float> SimulatePile(std::shared_ptr<JobSystem> jobs) {
  PhysicsSystemConfig config;
  config.max_bodies = 256;
  config.job_system = std::move(jobs);
  auto world = std::move(*PhysicsSystem::Create(config));
  Add(*world, Static(Box(50, 1, 50), Vec3(0, -1, 0)));
  std::vector<BodyID> ids;
  for (int i = 0; i < 60; ++i)
    ids.push_back(Add(*world, Dynamic(i % 2 ? Box(0.4f, 0.3f, 0.5f) : Sphere(0.4f),
                                      Vec3(0.3f * (i % 5), 1.0f + 0.9f * i, 0.2f * (i % 3)))));
  StepFor(*world, 200);
  return Positions(*world, ids);
}

TEST(Simulation, SameInputsGiveSameResult) {
  EXPECT_EQ(SimulatePile(MakeDefaultJobSystem(2)), SimulatePile(MakeDefaultJobSystem(2)));
}

// Parallel stages write per-index results, so even the thread count does not change the outcome.
TEST(SimulationThreads, ResultDoesNotDependOnThreadCount) {
  const std::vector<float> serial = SimulatePile(std::make_shared<SerialJobSystem>());
  EXPECT_EQ(SimulatePile(std::make_shared<ThreadPoolJobSystem>(3)), serial);
  EXPECT_EQ(SimulatePile(MakeDefaultJobSystem(2)), serial);
}

// A pyramid of boxes (one island, large enough to be split and solved in bundles) beside a mesh with
// spheres, boxes and capsules on it (small islands solved together): positions and rotations after a
// second and a half are bit-identical whatever job system and thread count ran them.
std::vector<float> SimulateSplitIsland(std::shared_ptr<JobSystem> jobs) {
  PhysicsSystemConfig config;
  config.max_bodies = 512;
  config.job_system = std::move(jobs);
  PhysicsSettings settings;
  settings.allow_sleeping = false;  // every body stays in the solve until the end
  auto world = std::move(*PhysicsSystem::Create(config, settings));
  Add(*world, Static(Box(30, 1, 30), Vec3(0, -1, 0)));
  std::vector<BodyID> ids;
  for (int level = 0; level < 6; ++level)
    for (int x = 0; x < 6 - level; ++x)
      for (int z = 0; z < 6 - level; ++z)
        ids.push_back(Add(
            *world, Dynamic(Box(0.5f, 0.5f, 0.5f),
                            Vec3(-3.0f + x + 0.5f * level, 0.5f + 1.01f * level, -3.0f + z + 0.5f * level))));
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  for (int z = 0; z <= 8; ++z)
    for (int x = 0; x <= 8; ++x)
      vertices.emplace_back(2.0f * x, 0.4f * std::sin(0.9f * x) * std::cos(0.7f * z), 2.0f * z);
  for (std::uint32_t z = 0; z < 8; ++z)
    for (std::uint32_t x = 0; x < 8; ++x) {
      const std::uint32_t i = z * 9 + x;
      triangles.push_back({i, i + 9, i + 1});
      triangles.push_back({i + 1, i + 9, i + 10});
    }
  Add(*world, Static(*TriangleMeshShape::Create(vertices, triangles), Vec3(40, 0, 0)));
  for (int i = 0; i < 24; ++i) {
    const ShapeRef shape = i % 3 == 0   ? Sphere(0.4f)
                           : i % 3 == 1 ? Box(0.3f, 0.4f, 0.5f)
                                        : Capsule(0.4f, 0.3f);
    ids.push_back(
        Add(*world, Dynamic(shape, Vec3(41.0f + 1.9f * (i % 8), 1.0f + 0.9f * (i / 8), 2.0f + 1.7f * (i % 5)),
                            Quat(Eigen::AngleAxisf(0.3f * i, Vec3(1, 1, 0).normalized())))));
  }
  StepFor(*world, 90);
  EXPECT_GE(world->last_step_stats().max_splits, 4u);  // the pyramid really was split
  std::vector<float> state;
  AppendPoses(*world, ids, state);
  return state;
}

TEST(SimulationThreads, SplitIslandsGiveTheSameResultOnEveryThreadCount) {
  const std::vector<float> serial = SimulateSplitIsland(std::make_shared<SerialJobSystem>());
  EXPECT_EQ(SimulateSplitIsland(std::make_shared<ThreadPoolJobSystem>(2)), serial);
  EXPECT_EQ(SimulateSplitIsland(std::make_shared<ThreadPoolJobSystem>(4)), serial);
  EXPECT_EQ(SimulateSplitIsland(MakeDefaultJobSystem(3)), serial);
}

TEST(Simulation, RestingPairsReplayTheirManifoldsAndMovedPairsAreTestedAgain) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  SharpFloor(*world);
  const BodyID box = Add(*world, Dynamic(SharpBox(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
  StepFor(*world, 60);
  EXPECT_EQ(world->last_step_stats().pairs, 1u);
  EXPECT_EQ(world->last_step_stats().pairs_replayed, 1u);  // at rest: last step's manifold moved along
  // Two millimetres sideways is more than the pair may drift and still replay. The box's face still lies on
  // the floor's, so its corners are carried along the slide; with slides off, the shapes are tested anew.
  for (const bool slides : {true, false}) {
    settings.body_pair_cache_slides = slides;
    ASSERT_TRUE(world->SetSettings(settings).ok());
    ASSERT_TRUE(world->bodies().SetPosition(box, Position(*world, box) + Vec3(0.002f, 0, 0)).ok());
    StepFor(*world, 1);
    EXPECT_EQ(world->last_step_stats().pairs_replayed, 0u);
    EXPECT_EQ(world->last_step_stats().pairs_slid, slides ? 1u : 0u);
    StepFor(*world, 1);
    EXPECT_EQ(world->last_step_stats().pairs_replayed, 1u);
    EXPECT_EQ(world->last_step_stats().pairs_slid, 0u);
    EXPECT_NEAR(Position(*world, box).y(), 0.5f, 0.01f);
  }
}

TEST(Simulation, PairsStillApartAlongLastStepsSeparatingAxisAreNotTestedAgainUntilTheyCloseIn) {
  // Two rounded boxes turned 45 degrees about z, side by side along the diagonal with parallel faces 0.84 m
  // apart: their bounds overlap, their shapes do not. B drifts towards A, too fast for the pair to replay.
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  const Quat turned(Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitZ()));
  const BodyID a = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3::Zero(), turned));
  const BodyID b = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(1.3f, 1.3f, 0), turned));
  const Vec3 towards_a = Vec3(-1, -1, 0).normalized();
  ASSERT_TRUE(world->bodies().SetLinearVelocity(b, 1.5f * towards_a).ok());
  auto gap = [&] { return (Position(*world, b) - Position(*world, a)).dot(-towards_a) - 1.0f; };
  int kept_apart = 0, tested = 0;
  bool touched = false;
  for (int step = 0; step < 60 && !touched; ++step) {
    const float before = gap();
    ASSERT_TRUE(world->Step(1.0f / 60.0f).ok());
    const StepStats& stats = world->last_step_stats();
    ASSERT_EQ(stats.pairs, 1u);
    EXPECT_EQ(stats.pairs_replayed, 0u);
    kept_apart += static_cast<int>(stats.pairs_kept_apart);
    tested += static_cast<int>(stats.pairs_kept_apart == 0);
    // Held apart only while a contact could not be near; once it is, the shapes are tested and it is found.
    if (before < 0.04f) {  // the reach is 2 cm + 2.5 cm
      EXPECT_EQ(stats.pairs_kept_apart, 0u) << step;
    }
    touched = stats.manifolds > 0;
    if (!touched) {
      EXPECT_GT(gap(), 0.0f) << step;
    }
  }
  EXPECT_TRUE(touched);
  EXPECT_GT(kept_apart, 20);  // 0.84 m at 1.5 m/s is 33 steps
  EXPECT_GE(tested, 2);       // the first step (no axis yet) and the one that found the contact
  // The contact then stops B at A's face: nothing was passed over.
  StepFor(*world, 60);
  EXPECT_GT(gap(), -0.02f);
}

// A heap of boxes, capsules, spheres and hulls tumbling onto a floor, with or without separating axes kept;
// returns every body's position and rotation after each step and counts the pairs held apart.
std::vector<float> TumblingHeap(bool separating_axis, std::size_t& kept_apart, std::size_t& replayed) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  settings.body_pair_cache_separating_axis = separating_axis;
  auto world = MakeWorld(settings);
  Floor(*world);
  const std::vector<Vec3> wedge = {{-0.3f, 0, -0.2f}, {0.3f, 0, -0.2f}, {0, 0.35f, -0.2f},
                                   {-0.3f, 0, 0.2f},  {0.3f, 0, 0.2f},  {0, 0.35f, 0.2f}};
  const ShapeRef shapes[] = {Box(0.3f, 0.2f, 0.25f), Capsule(0.25f, 0.15f), Sphere(0.2f),
                             *ConvexHullShape::Create(wedge)};
  std::vector<BodyID> ids;
  for (int i = 0; i < 32; ++i)
    ids.push_back(
        Add(*world, Dynamic(shapes[i % 4], Vec3(0.45f * (i % 4), 0.5f + 0.55f * (i / 4), 0.3f * (i % 3)),
                            Quat(Eigen::AngleAxisf(0.7f * i, Vec3(1, 2, 0.5f).normalized())))));
  std::vector<float> path;
  kept_apart = replayed = 0;
  for (int step = 0; step < 150; ++step) {
    EXPECT_TRUE(world->Step(1.0f / 60.0f).ok());
    kept_apart += world->last_step_stats().pairs_kept_apart;
    replayed += world->last_step_stats().pairs_replayed;
    AppendPoses(*world, ids, path);
  }
  return path;
}

TEST(Simulation, PassingPairsOverOnTheirSeparatingAxisChangesNoResult) {
  // The axis only passes over pairs a test would find apart: the same heap, bit for bit, while the other
  // reuse (replayed resting pairs) goes on as before.
  std::size_t kept_apart = 0, never = 0, replayed = 0, replayed_without = 0;
  const std::vector<float> passed_over = TumblingHeap(true, kept_apart, replayed);
  const std::vector<float> tested = TumblingHeap(false, never, replayed_without);
  EXPECT_EQ(never, 0u);
  EXPECT_GT(kept_apart, 1000u);
  EXPECT_GT(replayed, 100u);
  EXPECT_EQ(replayed, replayed_without);
  EXPECT_EQ(passed_over, tested);
}

// A frictionless box sent sliding across a floor box, over its edge and off. Returns the box's position and
// rotation every step; counts the steps whose contact was carried along the slide.
std::vector<float> SlideOffAnEdge(bool slides, float yaw, float speed, int& slid_steps) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  settings.body_pair_cache_slides = slides;
  auto world = MakeWorld(settings);
  BodyCreationSettings floor = Static(SharpBox(4, 1, 4), Vec3(0, -1, 0));
  floor.friction = 0.0f;
  Add(*world, floor);
  BodyCreationSettings box =
      Dynamic(SharpBox(0.5f, 0.3f, 0.4f), Vec3(0, 0.3f, 0), Quat(Eigen::AngleAxisf(yaw, Vec3::UnitY())));
  box.friction = 0.0f;
  const BodyID id = Add(*world, box);
  StepFor(*world, 30);  // settle
  EXPECT_TRUE(world->bodies().SetLinearVelocity(id, Vec3(speed, 0, 0.3f * speed)).ok());
  std::vector<float> path;
  slid_steps = 0;
  for (int step = 0; step < 250; ++step) {
    EXPECT_TRUE(world->Step(1.0f / 60.0f).ok());
    slid_steps += static_cast<int>(world->last_step_stats().pairs_slid);
    AppendPoses(*world, std::span(&id, 1), path);
  }
  return path;
}

TEST(Simulation, ABoxSlidingOffAnEdgeMovesAsWhenEveryStepTestsTheShapes) {
  // Carried along while its corners are on the floor's face, then tested as it tips over the edge: the same
  // path as with a shape test every step until it tips (from there on, rounding grows as it tumbles), for a
  // sweep of turns and speeds.
  for (const float yaw : {0.0f, 0.4f, 1.1f})
    for (const float speed : {2.0f, 4.0f, 8.0f}) {
      int slid = 0, never = 0;
      const std::vector<float> carried = SlideOffAnEdge(true, yaw, speed, slid);
      const std::vector<float> tested = SlideOffAnEdge(false, yaw, speed, never);
      EXPECT_EQ(never, 0);
      ASSERT_EQ(carried.size(), tested.size());
      int level_steps = 0;
      float worst = 0.0f;
      for (std::size_t step = 0; step < carried.size() / 7; ++step) {
        if (tested[7 * step + 1] < 0.295f) break;  // tipping over the edge
        ++level_steps;
        for (std::size_t i = 7 * step; i < 7 * step + 7; ++i)
          worst = std::max(worst, std::abs(carried[i] - tested[i]));
      }
      EXPECT_LT(worst, 1e-4f) << yaw << " " << speed;
      // It slid most of the way to the edge without a shape test, and was tested again once it left the face.
      EXPECT_GT(slid, level_steps / 2) << yaw << " " << speed;
      EXPECT_LT(slid, level_steps) << yaw << " " << speed;
      // And both went over: the box ends well below the floor's top.
      EXPECT_LT(carried[carried.size() - 6], -1.0f) << yaw << " " << speed;
      EXPECT_LT(tested[tested.size() - 6], -1.0f) << yaw << " " << speed;
    }
}

TEST(Simulation, PairCacheLimitsOfZeroTestEveryPairEveryStep) {
  for (const bool zero_distance : {true, false}) {
    PhysicsSettings settings;
    settings.allow_sleeping = false;
    (zero_distance ? settings.body_pair_cache_max_distance : settings.body_pair_cache_max_angle) = 0.0f;
    auto world = MakeWorld(settings);
    Floor(*world);
    const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f, 0)));
    StepFor(*world, 60);
    EXPECT_EQ(world->last_step_stats().pairs, 1u);
    EXPECT_EQ(world->last_step_stats().pairs_replayed, 0u);
    EXPECT_NEAR(Position(*world, box).y(), 0.5f, 0.01f);
    // Two boxes falling side by side, turned so that their bounds overlap and their shapes do not: a distance
    // limit of 0 keeps no separating axis either.
    const Quat turned(Eigen::AngleAxisf(0.25f * kPi, Vec3::UnitZ()));
    Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(5, 3, 0), turned));
    Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(6.3f, 4.3f, 0), turned));
    std::size_t kept_apart = 0;
    for (int step = 0; step < 20; ++step) {
      StepFor(*world, 1);
      kept_apart += world->last_step_stats().pairs_kept_apart;
    }
    EXPECT_EQ(kept_apart > 0, !zero_distance);
  }
}

TEST(Simulation, BadSettingsAreRejectedAndTheOldOnesKept) {
  auto world = MakeWorld();
  const PhysicsSettings before = world->settings();
  auto bad = [&](auto&& spoil, const char* field) {
    PhysicsSettings settings;
    spoil(settings);
    const Status status = world->SetSettings(settings);
    ASSERT_FALSE(status.ok()) << field;
    EXPECT_NE(status.message().find(field), std::string::npos) << status.message();
    PhysicsSystemConfig config;
    EXPECT_FALSE(PhysicsSystem::Create(config, settings).ok()) << field;
  };
  bad([](PhysicsSettings& s) { s.body_pair_cache_max_distance = -1e-3f; }, "body_pair_cache_max_distance");
  bad([](PhysicsSettings& s) { s.body_pair_cache_max_distance = std::nanf(""); },
      "body_pair_cache_max_distance");
  bad([](PhysicsSettings& s) { s.body_pair_cache_max_angle = 181.0f; }, "body_pair_cache_max_angle");
  bad([](PhysicsSettings& s) { s.body_pair_cache_max_angle = std::nanf(""); }, "body_pair_cache_max_angle");
  bad([](PhysicsSettings& s) { s.velocity_iterations = 0; }, "velocity_iterations");
  bad([](PhysicsSettings& s) { s.gravity.x() = INFINITY; }, "gravity");
  EXPECT_EQ(world->settings().body_pair_cache_max_distance, before.body_pair_cache_max_distance);
  EXPECT_EQ(world->settings().body_pair_cache_max_angle, before.body_pair_cache_max_angle);
  EXPECT_EQ(world->settings().velocity_iterations, before.velocity_iterations);
  EXPECT_EQ(world->settings().gravity, before.gravity);
}

TEST(Simulation, WarmStartedImpulsesHoldABoxOnASlopeWithOneVelocityPass) {
  // One pass solves friction before non-penetration, bounded by the normal impulse accumulated so far. From
  // a cold start that bound is zero and the box slides; with last step's impulses, carried in the body-pair
  // cache (replayed, or matched by position on the body), friction holds it on a slope it grips.
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  settings.velocity_iterations = 1;
  auto world = MakeWorld(settings);
  const Quat tilt(Eigen::AngleAxisf(20.0f * kPi / 180.0f, Vec3::UnitZ()));  // tan 20 degrees = 0.36 < 0.6
  BodyCreationSettings ramp = Static(Box(20, 0.5f, 5), Vec3::Zero(), tilt);
  ramp.friction = 0.6f;
  Add(*world, ramp);
  BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), tilt * Vec3(0, 1.0f, 0), tilt);
  box.friction = 0.6f;
  const BodyID id = Add(*world, box);
  StepFor(*world, 30);
  const Vec3 start = Position(*world, id);
  StepFor(*world, 120);
  EXPECT_LT((Position(*world, id) - start).norm(), 0.01f);
  EXPECT_EQ(world->last_step_stats().pairs_replayed, 1u);
}

TEST(Simulation, KinematicBodyFollowsItsVelocityAndPushesDynamicBodies) {
  PhysicsSettings settings;
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  BodyCreationSettings paddle = Dynamic(Box(0.5f, 1, 1), Vec3(-3, 0, 0));
  paddle.motion_type = MotionType::kKinematic;
  paddle.linear_velocity = Vec3(2, 0, 0);
  const BodyID kinematic = Add(*world, paddle);
  const BodyID ball = Add(*world, Dynamic(Sphere(0.5f), Vec3(0, 0, 0)));
  StepFor(*world, 90);  // the ball falls asleep waiting; the paddle's touch must wake it
  // The kinematic body moved exactly as told, whatever it hit.
  EXPECT_NEAR(Position(*world, kinematic).x(), 0.0f, 1e-4f);
  EXPECT_TRUE(Velocity(*world, kinematic).isApprox(Vec3(2, 0, 0)));
  // The ball was pushed ahead of it.
  EXPECT_GT(Position(*world, ball).x(), 0.95f);
  EXPECT_GT(Velocity(*world, ball).x(), 1.9f);
}

TEST(Simulation, GravityFactorDampingAndVelocityLimits) {
  auto world = MakeWorld();
  BodyCreationSettings floating = Dynamic(Sphere(0.5f), Vec3(0, 10, 0));
  floating.gravity_factor = 0.0f;
  BodyCreationSettings damped = Dynamic(Sphere(0.5f), Vec3(5, 10, 0));
  damped.gravity_factor = 0.0f;
  damped.linear_damping = 1.0f;
  damped.linear_velocity = Vec3(4, 0, 0);
  BodyCreationSettings limited = Dynamic(Sphere(0.5f), Vec3(-5, 10, 0));
  limited.max_linear_velocity = 3.0f;
  limited.linear_damping = 0.0f;
  const BodyID a = Add(*world, floating), b = Add(*world, damped), c = Add(*world, limited);
  StepFor(*world, 60);
  EXPECT_NEAR(Position(*world, a).y(), 10.0f, 1e-5f);
  EXPECT_NEAR(Velocity(*world, b).x(), 4.0f * std::pow(1.0f - 1.0f / 60.0f, 60.0f), 1e-3f);
  EXPECT_NEAR(Velocity(*world, c).norm(), 3.0f, 1e-4f);
}

TEST(Simulation, ForcesAndTorquesActForOneStep) {
  PhysicsSettings settings;
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  BodyCreationSettings body = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3::Zero());
  body.linear_damping = 0.0f;
  body.angular_damping = 0.0f;
  const BodyID id = Add(*world, body);  // 1000 kg, inertia 1000/6 kg m^2
  ASSERT_TRUE(world->bodies().AddForce(id, Vec3(600, 0, 0)).ok());
  ASSERT_TRUE(world->bodies().AddTorque(id, Vec3(0, 1000.0f / 6.0f * 60.0f, 0)).ok());
  StepFor(*world, 1);
  EXPECT_NEAR(Velocity(*world, id).x(), 600.0f / 1000.0f / 60.0f, 1e-6f);
  EXPECT_NEAR(world->bodies().GetAngularVelocity(id)->y(), 1.0f, 1e-4f);
  StepFor(*world, 1);  // accumulators were cleared
  EXPECT_NEAR(Velocity(*world, id).x(), 600.0f / 1000.0f / 60.0f, 1e-6f);
}

// Layer 2 ("ghost") collides with nothing but the floor.
class GhostLayers final : public LayerSetup {
 public:
  ObjectLayer ObjectLayerCount() const override { return 3; }
  BroadPhaseLayer BroadPhaseLayerCount() const override { return 2; }
  BroadPhaseLayer ToBroadPhaseLayer(ObjectLayer layer) const override { return layer == 0 ? 0 : 1; }
  bool ShouldCollide(ObjectLayer a, ObjectLayer b) const override {
    if (a == 0 && b == 0) return false;
    if (a == 2 || b == 2) return a == 0 || b == 0;
    return true;
  }
};

TEST(Simulation, LayerPairFilterDecidesWhoCollides) {
  PhysicsSystemConfig config;
  config.max_bodies = 16;
  config.job_system = std::make_shared<SerialJobSystem>();
  config.layers = std::make_shared<GhostLayers>();
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = std::move(*PhysicsSystem::Create(config, settings));
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  Add(*world, Static(Box(1, 1, 1), Vec3(0, 0.5f, 0)));  // overlaps the floor: static pairs are never made
  const BodyID resting = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(5, 0.5f, 0)));
  BodyCreationSettings ghost = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(5, 1.5f, 0));
  ghost.object_layer = 2;
  const BodyID passes = Add(*world, ghost);
  StepFor(*world, 60);
  // The ghost fell through the box below it onto the floor; the box stayed where it was.
  EXPECT_NEAR(Position(*world, passes).y(), 0.5f, 0.02f);
  EXPECT_NEAR(Position(*world, resting).y(), 0.5f, 0.02f);
  EXPECT_EQ(world->last_step_stats().pairs, 2u);  // each dynamic box with the floor only
}

}  // namespace
}  // namespace strata::test
