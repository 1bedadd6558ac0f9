// A warmed-up world steps without touching the heap: every global operator new is counted while a scene
// with every kind of work the step does (a large split island, runs of small islands, convex vs mesh,
// replayed and freshly computed pairs, a kinematic body, contact events, a sensor) steps, on each job system
// Strata ships. Its own
// executable, because it replaces the global allocation functions. (oneTBB takes its task memory from its
// own pools, not from operator new; every allocation of Strata's own goes through operator new.)
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "physics/body/BodyInterface.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/core/ThreadPoolJobSystem.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"
#include "physics/world/PhysicsSystem.h"

namespace {
std::atomic<bool> counting{false};
std::atomic<std::size_t> allocations{0};

void* Allocate(std::size_t size, std::size_t alignment) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t rounded = (std::max<std::size_t>(size, 1) + alignment - 1) / alignment * alignment;
  void* memory =
      alignment <= alignof(std::max_align_t) ? std::malloc(rounded) : std::aligned_alloc(alignment, rounded);
  if (memory == nullptr) throw std::bad_alloc();
  return memory;
}
}  // namespace

void* operator new(std::size_t size) {
  return Allocate(size, alignof(std::max_align_t));
}
void* operator new[](std::size_t size) {
  return Allocate(size, alignof(std::max_align_t));
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  return Allocate(size, static_cast<std::size_t>(alignment));
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  return Allocate(size, static_cast<std::size_t>(alignment));
}
void operator delete(void* memory) noexcept {
  std::free(memory);
}
void operator delete[](void* memory) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::size_t) noexcept {
  std::free(memory);
}
void operator delete[](void* memory, std::size_t) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::align_val_t) noexcept {
  std::free(memory);
}
void operator delete[](void* memory, std::align_val_t) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::size_t, std::align_val_t) noexcept {
  std::free(memory);
}
void operator delete[](void* memory, std::size_t, std::align_val_t) noexcept {
  std::free(memory);
}

namespace strata {
namespace {

BodyID Add(PhysicsSystem& world, ShapeRef shape, const Vec3& position, MotionType motion,
           const Quat& rotation = Quat::Identity(), bool report_contacts = false) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.position = position;
  settings.rotation = rotation;
  settings.motion_type = motion;
  settings.report_contacts = report_contacts;
  settings.object_layer = motion == MotionType::kStatic ? layers::kNonMoving : layers::kMoving;
  return *world.bodies().CreateAndAddBody(settings);
}

// A pyramid of boxes on a floor: one large island, split and solved in bundles; its boxes report contact
// events, and a sensor holds its lower levels.
void AddPyramidInASensor(PhysicsSystem* world, const ShapeRef& box) {
  Add(*world, *BoxShape::Create(Vec3(30, 1, 30)), Vec3(0, -1, 0), MotionType::kStatic);
  for (int level = 0; level < 6; ++level)
    for (int x = 0; x < 6 - level; ++x)
      for (int z = 0; z < 6 - level; ++z)
        Add(*world, box, Vec3(-3.0f + x + 0.5f * level, 0.5f + level, -3.0f + z + 0.5f * level),
            MotionType::kDynamic, Quat::Identity(), true);
  BodyCreationSettings sensor;
  sensor.shape = *BoxShape::Create(Vec3(3, 1, 3));
  sensor.position = Vec3(0, 1, 0);
  sensor.motion_type = MotionType::kStatic;
  sensor.is_sensor = true;
  (void)world->bodies().CreateAndAddBody(sensor);
}

// A wavy mesh with each convex kind resting on it: small islands, convex vs triangles.
void AddConvexesOnAMesh(PhysicsSystem* world) {
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
  for (int z = 0; z <= 10; ++z)
    for (int x = 0; x <= 10; ++x)
      vertices.emplace_back(2.0f * x, 0.3f * std::sin(0.7f * x) * std::cos(0.5f * z), 2.0f * z);
  for (std::uint32_t z = 0; z < 10; ++z)
    for (std::uint32_t x = 0; x < 10; ++x) {
      const std::uint32_t i = z * 11 + x;
      triangles.push_back({i, i + 11, i + 1});
      triangles.push_back({i + 1, i + 11, i + 12});
    }
  Add(*world, *TriangleMeshShape::Create(vertices, triangles), Vec3(40, 0, 0), MotionType::kStatic);
  const ShapeRef shapes[] = {*SphereShape::Create(0.4f), *BoxShape::Create(Vec3(0.4f, 0.3f, 0.5f)),
                             *ConvexHullShape::Create(std::vector<Vec3>{
                                 {0, 0.8f, 0}, {0.8f, 0, 0}, {-0.8f, 0, 0}, {0, 0, 0.8f}, {0, 0, -0.8f}})};
  for (int i = 0; i < 9; ++i)
    Add(*world, shapes[i % 3], Vec3(43.0f + 2.0f * (i % 3), 1.0f, 3.0f + 5.0f * (i / 3)),
        MotionType::kDynamic);
}

// A ball and a capsule rolling down a long ramp (pairs that never replay), and a kinematic body gliding past,
// touching nothing.
void AddRollersAndAGlider(PhysicsSystem* world, const ShapeRef& box) {
  const Quat tilt(Eigen::AngleAxisf(0.15f, Vec3::UnitZ()));
  Add(*world, *BoxShape::Create(Vec3(150, 0.5f, 3)), Vec3(0, -30, 60), MotionType::kStatic, tilt);
  Add(*world, *SphereShape::Create(0.5f), tilt * Vec3(120, 1.0f, 0) + Vec3(0, -30, 59), MotionType::kDynamic);
  Add(*world, *CapsuleShape::Create(0.5f, 0.3f), tilt * Vec3(120, 0.8f, 0) + Vec3(0, -30, 61),
      MotionType::kDynamic, Quat(Eigen::AngleAxisf(1.5708f, Vec3::UnitX())));
  BodyCreationSettings glider;
  glider.shape = box;
  glider.position = Vec3(-40, 5, -40);
  glider.motion_type = MotionType::kKinematic;
  glider.linear_velocity = Vec3(0.5f, 0, 0);
  (void)world->bodies().CreateAndAddBody(glider);
}

// Joints: a swinging chain of ten links with a 20 kg end (solved exactly: ExactJointSolver) and a wheel its
// motor keeps turning (solved by passes).
void AddChainAndWheel(PhysicsSystem* world, const ShapeRef& box) {
  const ShapeRef link = *CapsuleShape::Create(0.1f, 0.03f);
  BodyID previous;
  for (int i = 0; i <= 10; ++i) {
    BodyCreationSettings part;
    part.shape = i < 10 ? link : *SphereShape::Create(0.2f);
    part.position = Vec3(-60.0f + 0.2f * i + 0.1f, 20.0f, 0.0f);
    part.rotation = Quat(Eigen::AngleAxisf(1.5708f, Vec3::UnitZ()));
    part.mass = i < 10 ? 1.0f : 20.0f;
    part.allow_sleeping = false;
    const BodyID id = *world->bodies().CreateAndAddBody(part);
    PointJointSettings joint;
    joint.body_a = previous;
    joint.body_b = id;
    joint.anchor = Vec3(-60.0f + 0.2f * i, 20.0f, 0.0f);
    (void)world->constraints().Add(joint);
    previous = id;
  }
  BodyCreationSettings wheel;
  wheel.shape = box;
  wheel.position = Vec3(-60, 5, 20);
  wheel.allow_sleeping = false;
  HingeJointSettings axle;
  axle.body_b = *world->bodies().CreateAndAddBody(wheel);
  axle.anchor = wheel.position;
  axle.axis = Vec3::UnitY();
  axle.motor = {true, 2.0f, 100.0f};
  (void)world->constraints().Add(axle);
}

std::unique_ptr<PhysicsSystem> MakeScene(std::shared_ptr<JobSystem> jobs) {
  PhysicsSystemConfig config;
  config.max_bodies = 512;
  config.job_system = std::move(jobs);
  PhysicsSettings settings;
  settings.allow_sleeping = false;  // keep every body in the step
  auto world = std::move(*PhysicsSystem::Create(config, settings));
  const ShapeRef box = *BoxShape::Create(Vec3(0.5f, 0.5f, 0.5f));
  AddPyramidInASensor(world.get(), box);
  AddConvexesOnAMesh(world.get());
  AddRollersAndAGlider(world.get(), box);
  AddChainAndWheel(world.get(), box);
  return world;
}

std::size_t AllocationsWhileStepping(std::shared_ptr<JobSystem> jobs) {
  auto world = MakeScene(std::move(jobs));
  // Eight seconds: the last piles come to rest after five and switch to the exact solver, whose memory the
  // pool keeps from then on.
  for (int i = 0; i < 480; ++i) EXPECT_TRUE(world->Step(1.0f / 60.0f).ok());
  EXPECT_EQ(world->last_step_stats().constraints, 12u);
  EXPECT_GT(world->last_step_stats().pairs_replayed, 0u);
  EXPECT_LT(world->last_step_stats().pairs_replayed, world->last_step_stats().pairs);
  EXPECT_GT(world->events().contact_persist.size(), 100u);
  allocations.store(0);
  counting.store(true);
  for (int i = 0; i < 60; ++i) EXPECT_TRUE(world->Step(1.0f / 60.0f).ok());
  counting.store(false);
  return allocations.load();
}

TEST(StepAllocation, SteadyStepsAllocateNothingOnTheSerialJobSystem) {
  EXPECT_EQ(AllocationsWhileStepping(std::make_shared<SerialJobSystem>()), 0u);
}

TEST(StepAllocationThreads, SteadyStepsAllocateNothingOnTheThreadPool) {
  EXPECT_EQ(AllocationsWhileStepping(std::make_shared<ThreadPoolJobSystem>(3)), 0u);
}

TEST(StepAllocationThreads, SteadyStepsAllocateNothingOnTheDefaultJobSystem) {
  EXPECT_EQ(AllocationsWhileStepping(MakeDefaultJobSystem(2)), 0u);
}

}  // namespace
}  // namespace strata
