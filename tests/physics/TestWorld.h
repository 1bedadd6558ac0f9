// Helpers shared by the physics tests: a world with a floor, shape shorthands, stepping.
#pragma once

#include <gtest/gtest.h>

#include "physics/body/BodyInterface.h"
#include "physics/core/JobSystem.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"
#include "physics/world/PhysicsSystem.h"
#include "physics/world/WorldQuery.h"

namespace strata::test {

inline ShapeRef Box(float x, float y, float z) {
  return *BoxShape::Create({x, y, z});
}
inline ShapeRef Sphere(float r) {
  return *SphereShape::Create(r);
}
inline ShapeRef Capsule(float half_height, float r) {
  return *CapsuleShape::Create(half_height, r);
}

inline std::unique_ptr<PhysicsSystem> MakeWorld(PhysicsSettings settings = {},
                                                std::uint32_t max_bodies = 4096) {
  PhysicsSystemConfig config;
  config.max_bodies = max_bodies;
  config.job_system = std::make_shared<SerialJobSystem>();
  auto world = PhysicsSystem::Create(config, settings);
  EXPECT_TRUE(world.ok());
  return std::move(*world);
}

inline BodyCreationSettings Static(ShapeRef shape, const Vec3& position,
                                   const Quat& rotation = Quat::Identity()) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.position = position;
  settings.rotation = rotation;
  settings.motion_type = MotionType::kStatic;
  settings.object_layer = layers::kNonMoving;
  return settings;
}

inline BodyCreationSettings Dynamic(ShapeRef shape, const Vec3& position,
                                    const Quat& rotation = Quat::Identity()) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.position = position;
  settings.rotation = rotation;
  return settings;
}

inline BodyID Add(PhysicsSystem& world, const BodyCreationSettings& settings) {
  auto id = world.bodies().CreateAndAddBody(settings);
  EXPECT_TRUE(id.ok()) << (id.ok() ? "" : id.error().message);
  return id.ok() ? *id : BodyID{};
}

inline void StepFor(PhysicsSystem& world, int steps, float dt = 1.0f / 60.0f) {
  for (int i = 0; i < steps; ++i) ASSERT_TRUE(world.Step(dt).ok());
}

inline Vec3 Position(PhysicsSystem& world, BodyID id) {
  return *world.bodies().GetPosition(id);
}
inline Vec3 Velocity(PhysicsSystem& world, BodyID id) {
  return *world.bodies().GetLinearVelocity(id);
}

}  // namespace strata::test
