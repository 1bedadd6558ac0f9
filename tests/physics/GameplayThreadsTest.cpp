// Game code on a live world: threads cast shapes, read the step's events and move a character while another
// thread adds, removes and moves reporting bodies next to a sensor and the test's thread steps the world; a
// fixed amount of work each. Each thread
// checks its own results against what it knows must hold (the floor under every downward cast, its own body
// found where it just put it and gone once removed, every events copy whole and in order).
#include <random>
#include <thread>

#include "TestWorld.h"
#include "physics/character/Character.h"

namespace strata::test {
namespace {

constexpr float kFloorTop = 0.0f;

// Every copy of the events is one step's: ordered, lower index first, the sensor's own.
bool EventsAreWhole(const StepEvents& events, BodyID sensor) {
  const auto ordered = [](const auto& list) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (list[i].body_a.index >= list[i].body_b.index) return false;
      if (i > 0 && std::pair(list[i - 1].body_a.index, list[i - 1].body_b.index) >=
                       std::pair(list[i].body_a.index, list[i].body_b.index))
        return false;
    }
    return true;
  };
  if (!ordered(events.contact_begin) || !ordered(events.contact_persist) || !ordered(events.contact_end))
    return false;
  for (const auto* list : {&events.sensor_begin, &events.sensor_end})
    for (const SensorEvent& event : *list)
      if (event.sensor != sensor) return false;
  return true;
}

// What the threads count, checked at the end.
struct Tally {
  std::atomic<int> failures{0}, casts{0}, copies{0}, moves{0};
};

// Adds reporting bodies, teleports them and takes them out again, checking each against a cast.
void AddMoveAndRemove(PhysicsSystem& world, int bodies, Tally& tally) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> spread(-40.0f, 40.0f);
  const ShapeRef ball = Sphere(0.4f);
  std::vector<BodyID> mine;
  for (int i = 0; i < bodies; ++i) {
    BodyCreationSettings settings = Dynamic(ball, Vec3(spread(random), 2.0f + i % 5, spread(random)));
    settings.report_contacts = true;
    const Result<BodyID> id = world.bodies().CreateAndAddBody(settings);
    if (!id) {
      ++tally.failures;
      continue;
    }
    mine.push_back(*id);
    // Teleported well above everything, to a column of its own: however far it has fallen since (the step
    // runs meanwhile), a cast down that column meets it before anything else.
    const Vec3 high(-38.0f + 4.0f * static_cast<float>(i % 20), 40.0f,
                    -38.0f + 4.0f * static_cast<float>(i / 20 % 20));
    if (!world.bodies().SetPosition(*id, high)) ++tally.failures;
    const auto hit = world.query().CastShape(*Sphere(0.2f), Pose{high + Vec3(0, 20, 0), Quat::Identity()},
                                             Vec3(0, -70, 0));
    if (!hit || !hit->has_value() || (*hit)->body != *id) ++tally.failures;
    ++tally.moves;
    if (i % 3 != 2) continue;
    const BodyID gone = mine.front();
    mine.erase(mine.begin());
    const Vec3 last = *world.bodies().GetPosition(gone);
    if (!world.bodies().RemoveAndDestroyBody(gone)) ++tally.failures;
    const auto after = world.query().CastShapeAll(*Sphere(0.5f), Pose{last + Vec3(0, 3, 0), Quat::Identity()},
                                                  Vec3(0, -6, 0));
    for (const ShapeCastResult& result : *after)
      if (result.body == gone) ++tally.failures;
  }
}

// Casts down onto the floor and copies the events, over and over.
void CastAndReadEvents(PhysicsSystem& world, int caster, int casts, BodyID floor, BodyID sensor,
                       Tally& tally) {
  std::mt19937 random(100 + caster);
  std::uniform_real_distribution<float> spread(-50.0f, 50.0f);
  const ShapeRef probe = caster % 2 == 0 ? Sphere(0.3f) : Capsule(0.4f, 0.25f);
  StepEvents events;
  for (int k = 0; k < casts; ++k) {
    const Vec3 from(spread(random), 30.0f, spread(random));
    const auto hit = world.query().CastShape(*probe, Pose{from, Quat::Identity()}, Vec3(0, -40, 0));
    // The floor is always there; whatever is hit lies on the way to it.
    const float bottom = from.y() - probe->LocalBounds().HalfExtents().y();
    const float floor_fraction = (bottom - kFloorTop) / 40.0f;
    if (!hit || !hit->has_value() || (*hit)->fraction > floor_fraction + 1e-3f) ++tally.failures;
    if (hit && hit->has_value() && (*hit)->body == floor &&
        std::abs((*hit)->fraction - floor_fraction) > 1e-3f)
      ++tally.failures;
    ++tally.casts;
    world.CopyEvents(events);
    if (!EventsAreWhole(events, sensor)) ++tally.failures;
    ++tally.copies;
  }
}

// A character walking in circles on the same floor.
void WalkInCircles(PhysicsSystem& world, int frames, Tally& tally) {
  auto character = std::move(*Character::Create(world, {}, Vec3(20, 0.05f, 20)));
  for (int frame = 0; frame < frames; ++frame) {
    const float angle = 0.02f * static_cast<float>(frame);
    if (!character->Update(1.0f / 60.0f, Vec3(3 * std::cos(angle), 0, 3 * std::sin(angle)),
                           Vec3(0, -9.81f, 0)))
      ++tally.failures;
    if (character->feet().y() < kFloorTop - 0.01f) ++tally.failures;
  }
}

void CastReadMoveAndStep(int casters, int casts_each, int steps, int bodies) {
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(bodies + 64);
  config.thread_count = 2;
  auto world = std::move(*PhysicsSystem::Create(config));
  const BodyID floor = Add(*world, Static(Box(60, 1, 60), Vec3(0, kFloorTop - 1, 0)));
  BodyCreationSettings trigger = Static(Box(10, 3, 10), Vec3(0, 3, 0));
  trigger.is_sensor = true;
  trigger.object_layer = layers::kMoving;
  const BodyID sensor = Add(*world, trigger);
  Tally tally;
  std::thread mover([&] { AddMoveAndRemove(*world, bodies, tally); });
  std::vector<std::thread> readers;
  for (int c = 0; c < casters; ++c)
    readers.emplace_back([&, c] { CastAndReadEvents(*world, c, casts_each, floor, sensor, tally); });
  std::thread walker([&] { WalkInCircles(*world, casts_each, tally); });
  for (int step = 0; step < steps; ++step)
    if (!world->Step(1.0f / 60.0f)) ++tally.failures;
  mover.join();
  for (std::thread& reader : readers) reader.join();
  walker.join();
  EXPECT_EQ(tally.failures.load(), 0);
  EXPECT_EQ(tally.casts.load(), casters * casts_each);
  EXPECT_EQ(tally.copies.load(), casters * casts_each);
  EXPECT_EQ(tally.moves.load(), bodies);
}

TEST(GameplayThreads, CastsEventReadsAndACharacterWhileBodiesChangeAndTheWorldSteps) {
  CastReadMoveAndStep(4, 300, 90, 120);
}

TEST(GameplayThreadsStress, CastsEventReadsAndACharacterWhileBodiesChangeAndTheWorldStepsLong) {
  for (int repeat = 0; repeat < 100; ++repeat) CastReadMoveAndStep(8, 500, 120, 300);
}

}  // namespace
}  // namespace strata::test
