// Contact events, sensors and the contact validator: exact event counts for known scenes, the same arrays for
// any thread count, impulses against the weight they carry, and a one-way platform.
#include <random>

#include "TestWorld.h"
#include "physics/core/ThreadPoolJobSystem.h"

namespace strata::test {
namespace {

constexpr float kDt = 1.0f / 60.0f;

BodyCreationSettings Reporting(BodyCreationSettings settings) {
  settings.report_contacts = true;
  return settings;
}

BodyCreationSettings Sensor(ShapeRef shape, const Vec3& position, MotionType motion = MotionType::kStatic) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.position = position;
  settings.motion_type = motion;
  settings.is_sensor = true;
  return settings;
}

// Events of every step, for counting.
struct EventLog {
  int begins = 0, persists = 0, ends = 0, sensor_begins = 0, sensor_ends = 0;
  void Add(const StepEvents& events) {
    begins += static_cast<int>(events.contact_begin.size());
    persists += static_cast<int>(events.contact_persist.size());
    ends += static_cast<int>(events.contact_end.size());
    sensor_begins += static_cast<int>(events.sensor_begin.size());
    sensor_ends += static_cast<int>(events.sensor_end.size());
  }
};

TEST(ContactEvents, BoxDroppedOnFloorBeginsOncePersistsWhileRestingAndEndsWhenLifted) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;
  auto world = MakeWorld(settings);
  const BodyID floor = Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID box = Add(*world, Reporting(Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 2.5f, 0))));
  EventLog log;
  int landing_step = -1;
  float approach = 0.0f, landing_impulse = 0.0f;  // over the landing step and the nine after it
  for (int step = 0; step < 120; ++step) {
    StepFor(*world, 1);
    const StepEvents& events = world->events();
    log.Add(events);
    if (landing_step >= 0 && step < landing_step + 10 && events.contact_persist.size() == 1)
      landing_impulse += events.contact_persist[0].normal_impulse;
    if (events.contact_begin.empty()) continue;
    ASSERT_EQ(events.contact_begin.size(), 1u);
    const ContactEvent& begin = events.contact_begin[0];
    landing_step = step;
    // The lower index first: the floor, with the normal pointing from it to the box.
    EXPECT_EQ(begin.body_a, floor);
    EXPECT_EQ(begin.body_b, box);
    EXPECT_NEAR(begin.normal.y(), 1.0f, 1e-4f);
    EXPECT_EQ(begin.point_count, 4);
    // Midway between the surfaces as the step began: the gap it closed is at most one step of its fall.
    for (int i = 0; i < begin.point_count; ++i) EXPECT_NEAR(begin.points[i].y(), 0.0f, 0.5f * 6.3f * kDt);
    // Dropped 2 m: it meets the floor at about sqrt(2 g h) = 6.26 m/s.
    EXPECT_NEAR(begin.approach_speed, std::sqrt(2.0f * 9.81f * 2.0f), 0.3f);
    approach = begin.approach_speed;
    landing_impulse += begin.normal_impulse;
  }
  // The floor took the box's momentum and held its weight for those ten steps (restitution 0: no bounce).
  const float mass = 1000.0f;
  EXPECT_NEAR(landing_impulse, mass * approach + mass * 9.81f * 10 * kDt, 0.05f * mass * approach);
  EXPECT_EQ(log.begins, 1);
  EXPECT_EQ(log.ends, 0);
  EXPECT_EQ(log.persists, 119 - landing_step);
  // At rest the floor carries the box's weight over each step: m g dt.
  ASSERT_EQ(world->events().contact_persist.size(), 1u);
  EXPECT_NEAR(world->events().contact_persist[0].normal_impulse, 1000.0f * 9.81f * kDt,
              0.02f * 1000 * 9.81f * kDt);
  EXPECT_NEAR(world->events().contact_persist[0].approach_speed, 0.0f, 0.2f);

  ASSERT_TRUE(world->bodies().SetPosition(box, Vec3(0, 3, 0)).ok());
  StepFor(*world, 1);
  ASSERT_EQ(world->events().contact_end.size(), 1u);
  EXPECT_EQ(world->events().contact_end[0].body_a, floor);
  EXPECT_EQ(world->events().contact_end[0].body_b, box);
  log.Add(world->events());
  for (int step = 0; step < 10; ++step) {
    StepFor(*world, 1);
    log.Add(world->events());
  }
  EXPECT_EQ(log.ends, 1);
  EXPECT_EQ(log.begins, 1);  // still falling towards the floor
}

TEST(ContactEvents, SleepingPairStaysTouchingWithoutEventsAndRemovalEndsIt) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID box = Add(*world, Reporting(Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.6f, 0))));
  EventLog log;
  for (int step = 0; step < 120; ++step) {
    StepFor(*world, 1);
    log.Add(world->events());
  }
  ASSERT_FALSE(*world->bodies().IsActive(box));
  EXPECT_EQ(log.begins, 1);
  EXPECT_EQ(log.ends, 0);
  // Asleep: no events at all, and the pair still touches (no end).
  const int persists = log.persists;
  StepFor(*world, 30);
  EXPECT_TRUE(world->events().empty());
  ASSERT_TRUE(world->bodies().RemoveBody(box).ok());
  StepFor(*world, 1);
  ASSERT_EQ(world->events().contact_end.size(), 1u);
  EXPECT_EQ(world->events().contact_end[0].body_b, box);
  EXPECT_EQ(persists, log.persists);
}

TEST(ContactEvents, BodiesWithoutTheFlagReportNothing) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 2, 0)));
  for (int step = 0; step < 60; ++step) {
    StepFor(*world, 1);
    EXPECT_TRUE(world->events().empty());
  }
}

// A pile of 40 reporting boxes and spheres landing on a floor and on each other.
std::vector<StepEvents> PileEvents(std::shared_ptr<JobSystem> jobs) {
  PhysicsSystemConfig config;
  config.job_system = std::move(jobs);
  auto world = std::move(*PhysicsSystem::Create(config));
  Add(*world, Reporting(Static(Box(10, 1, 10), Vec3(0, -1, 0))));
  std::mt19937 random(7);
  std::uniform_real_distribution<float> spread(-1.5f, 1.5f);
  for (int i = 0; i < 40; ++i) {
    const Vec3 position(spread(random), 0.6f + 0.7f * static_cast<float>(i), spread(random));
    Add(*world, Reporting(Dynamic(i % 3 == 0 ? Sphere(0.35f) : Box(0.3f, 0.3f, 0.3f), position)));
  }
  std::vector<StepEvents> steps;
  for (int step = 0; step < 240; ++step) {
    EXPECT_TRUE(world->Step(kDt).ok());
    steps.push_back(world->events());
  }
  return steps;
}

bool SameEvent(const ContactEvent& x, const ContactEvent& y) {
  if (x.body_a != y.body_a || x.body_b != y.body_b || x.point_count != y.point_count) return false;
  if (x.normal != y.normal || x.approach_speed != y.approach_speed || x.normal_impulse != y.normal_impulse)
    return false;
  for (int i = 0; i < x.point_count; ++i)
    if (x.points[i] != y.points[i]) return false;
  return true;
}

TEST(ContactEventsThreads, SameEventArraysAtOneAndTwoThreads) {
  const std::vector<StepEvents> one = PileEvents(std::make_shared<SerialJobSystem>());
  const std::vector<StepEvents> two = PileEvents(std::make_shared<ThreadPoolJobSystem>(2));
  ASSERT_EQ(one.size(), two.size());
  std::size_t events = 0;
  for (std::size_t step = 0; step < one.size(); ++step) {
    const StepEvents& x = one[step];
    const StepEvents& y = two[step];
    ASSERT_EQ(x.contact_begin.size(), y.contact_begin.size()) << "step " << step;
    ASSERT_EQ(x.contact_persist.size(), y.contact_persist.size()) << "step " << step;
    ASSERT_EQ(x.contact_end.size(), y.contact_end.size()) << "step " << step;
    for (std::size_t i = 0; i < x.contact_begin.size(); ++i)
      EXPECT_TRUE(SameEvent(x.contact_begin[i], y.contact_begin[i])) << "step " << step;
    for (std::size_t i = 0; i < x.contact_persist.size(); ++i)
      EXPECT_TRUE(SameEvent(x.contact_persist[i], y.contact_persist[i])) << "step " << step;
    for (std::size_t i = 0; i < x.contact_end.size(); ++i) {
      EXPECT_EQ(x.contact_end[i].body_a, y.contact_end[i].body_a);
      EXPECT_EQ(x.contact_end[i].body_b, y.contact_end[i].body_b);
    }
    events += x.contact_begin.size() + x.contact_persist.size() + x.contact_end.size();
  }
  EXPECT_GT(events, 1000u);  // the pile did touch
}

// Spheres released one after another above a sensor slab fall through it onto a floor, spread out so that
// each comes to rest on its own.
EventLog StreamThroughSensor(bool sleeping) {
  PhysicsSettings settings;
  settings.allow_sleeping = sleeping;
  auto world = MakeWorld(settings);
  Add(*world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
  const BodyID sensor = Add(*world, Sensor(Box(12, 0.5f, 12), Vec3(0, 3, 0)));
  EventLog log;
  int released = 0;
  for (int step = 0; step < 600; ++step) {
    if (step % 3 == 0 && released < 100) {
      const float x = -9.0f + 2.0f * static_cast<float>(released % 10);
      const float z = -9.0f + 2.0f * static_cast<float>(released / 10);
      Add(*world, Dynamic(Sphere(0.3f), Vec3(x, 6.0f, z)));
      ++released;
    }
    StepFor(*world, 1);
    const StepEvents& events = world->events();
    for (const SensorEvent& event : events.sensor_begin) EXPECT_EQ(event.sensor, sensor);
    log.Add(events);
  }
  return log;
}

TEST(Sensors, CountsAStreamOfOneHundredBodiesExactlyWithSleepingOnAndOff) {
  for (const bool sleeping : {true, false}) {
    const EventLog log = StreamThroughSensor(sleeping);
    EXPECT_EQ(log.sensor_begins, 100) << "sleeping " << sleeping;
    EXPECT_EQ(log.sensor_ends, 100) << "sleeping " << sleeping;
    EXPECT_EQ(log.begins + log.persists + log.ends, 0);  // nobody asked for contact events
  }
}

TEST(Sensors, ASleepingBodyInsideStaysInside) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  const BodyID sensor = Add(*world, Sensor(Box(2, 2, 2), Vec3(0, 1, 0)));
  const BodyID box = Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 1.0f, 0)));
  EventLog log;
  for (int step = 0; step < 300; ++step) {
    StepFor(*world, 1);
    if (step == 0) {
      ASSERT_EQ(world->events().sensor_begin.size(), 1u);
      EXPECT_EQ(world->events().sensor_begin[0].sensor, sensor);
      EXPECT_EQ(world->events().sensor_begin[0].visitor, box);
    }
    log.Add(world->events());
  }
  EXPECT_FALSE(*world->bodies().IsActive(box));
  EXPECT_EQ(log.sensor_begins, 1);
  EXPECT_EQ(log.sensor_ends, 0);
  // The sensor takes no contact response: the box fell through its volume to the floor.
  EXPECT_NEAR(Position(*world, box).y(), 0.5f, 0.01f);
  // Taking the box out of the world ends its overlap.
  ASSERT_TRUE(world->bodies().RemoveBody(box).ok());
  StepFor(*world, 1);
  ASSERT_EQ(world->events().sensor_end.size(), 1u);
  EXPECT_EQ(world->events().sensor_end[0].visitor, box);
}

TEST(Sensors, MovingKinematicSensorSweepsOverSleepingBoxes) {
  auto world = MakeWorld();
  Add(*world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
  std::vector<BodyID> boxes;
  for (int i = 0; i < 5; ++i)
    boxes.push_back(Add(*world, Dynamic(Box(0.4f, 0.4f, 0.4f), Vec3(-4.0f + 2.0f * i, 0.4f, 0))));
  StepFor(*world, 60);
  for (const BodyID id : boxes) ASSERT_FALSE(*world->bodies().IsActive(id));
  BodyCreationSettings sweeper = Sensor(Box(0.5f, 1, 1), Vec3(-8, 0.5f, 0), MotionType::kKinematic);
  sweeper.linear_velocity = Vec3(4, 0, 0);
  const BodyID sensor = Add(*world, sweeper);
  std::vector<int> entered(boxes.size(), 0), left(boxes.size(), 0);
  for (int step = 0; step < 240; ++step) {  // 16 m at 4 m/s
    StepFor(*world, 1);
    for (const SensorEvent& event : world->events().sensor_begin)
      for (std::size_t i = 0; i < boxes.size(); ++i) entered[i] += event.visitor == boxes[i];
    for (const SensorEvent& event : world->events().sensor_end)
      for (std::size_t i = 0; i < boxes.size(); ++i) left[i] += event.visitor == boxes[i];
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_EQ(entered[i], 1) << "box " << i;
    EXPECT_EQ(left[i], 1) << "box " << i;
    // Passed through, never pushed or woken.
    EXPECT_FALSE(*world->bodies().IsActive(boxes[i]));
  }
  EXPECT_GT(Position(*world, sensor).x(), 7.0f);
}

TEST(Sensors, SeeStaticBodiesOnlyWhenAsked) {
  auto world = MakeWorld();
  const BodyID wall = Add(*world, Static(Box(1, 1, 1), Vec3(0, 1, 0)));
  Add(*world, Sensor(Box(2, 2, 2), Vec3(0, 1, 0)));
  BodyCreationSettings seeing = Sensor(Box(2, 2, 2), Vec3(0, 1, 0));
  seeing.sensor_detects_static = true;
  seeing.object_layer = layers::kMoving;  // the default pair filter never pairs two non-moving layers
  const BodyID sees = Add(*world, seeing);
  StepFor(*world, 1);
  ASSERT_EQ(world->events().sensor_begin.size(), 1u);
  EXPECT_EQ(world->events().sensor_begin[0].sensor, sees);
  EXPECT_EQ(world->events().sensor_begin[0].visitor, wall);
}

TEST(Sensors, BadSensorSettingsAreRefused) {
  auto world = MakeWorld();
  const std::vector<Vec3> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  const std::vector<TriangleMeshShape::Indices> triangles = {{0, 2, 1}};
  const ShapeRef mesh = *TriangleMeshShape::Create(vertices, triangles);
  EXPECT_FALSE(world->bodies().CreateBody(Sensor(mesh, Vec3::Zero())).ok());
  BodyCreationSettings reporting_sensor = Sensor(Box(1, 1, 1), Vec3::Zero());
  reporting_sensor.report_contacts = true;
  EXPECT_FALSE(world->bodies().CreateBody(reporting_sensor).ok());
  BodyCreationSettings not_a_sensor = Static(Box(1, 1, 1), Vec3::Zero());
  not_a_sensor.sensor_detects_static = true;
  EXPECT_FALSE(world->bodies().CreateBody(not_a_sensor).ok());
  EXPECT_EQ(world->BodiesInWorld().size(), 0u);
}

TEST(ContactValidator, OneWayPlatformLetsABodyUpThroughAndCatchesItComingDown) {
  auto world = MakeWorld();
  Add(*world, Static(Box(10, 1, 10), Vec3(0, -1, 0)));
  BodyCreationSettings platform_settings = Static(Box(2, 0.1f, 2), Vec3(0, 2, 0));
  platform_settings.validate_contacts = true;
  const BodyID platform = Add(*world, platform_settings);
  BodyCreationSettings jumper_settings = Dynamic(Box(0.3f, 0.3f, 0.3f), Vec3(0, 0.3f, 0));
  jumper_settings.linear_velocity = Vec3(0, 9, 0);  // tops out 4.1 m above its start
  const BodyID jumper = Add(*world, jumper_settings);
  std::atomic<int> rejected{0};
  world->SetContactValidator([&](const ContactCandidate& contact) {
    // The normal from the platform to the other body: it must point up, and that body must not be rising.
    const bool platform_is_a = contact.body_a.id() == platform;
    const Vec3 up_from_platform = platform_is_a ? contact.normal : Vec3(-contact.normal);
    const Body& other = platform_is_a ? contact.body_b : contact.body_a;
    const bool lands =
        up_from_platform.y() > 0.7f && other.linear_velocity().y() <= 0.5f && other.position().y() > 2.1f;
    if (!lands) ++rejected;
    return lands;
  });
  float highest = 0.0f;
  for (int step = 0; step < 240; ++step) {
    StepFor(*world, 1);
    highest = std::max(highest, Position(*world, jumper).y());
  }
  EXPECT_GT(rejected.load(), 0);
  EXPECT_GT(highest, 3.0f);                                       // went up through the platform
  EXPECT_NEAR(Position(*world, jumper).y(), 2.1f + 0.3f, 0.02f);  // and rests on it
  // Without the validator the platform stops the jump: the box stays under it.
  world->SetContactValidator(nullptr);
  ASSERT_TRUE(world->bodies().SetPosition(jumper, Vec3(0, 0.3f, 0)).ok());
  ASSERT_TRUE(world->bodies().SetLinearVelocity(jumper, Vec3(0, 9, 0)).ok());
  highest = 0.0f;
  for (int step = 0; step < 120; ++step) {
    StepFor(*world, 1);
    highest = std::max(highest, Position(*world, jumper).y());
  }
  EXPECT_LT(highest, 1.9f - 0.3f + 0.02f);
}

}  // namespace
}  // namespace strata::test
