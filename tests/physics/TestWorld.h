// Helpers shared by the physics tests: a world with a floor, shape shorthands, stepping.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/body/BodyInterface.h"
#include "physics/core/JobSystem.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"
#include "physics/world/PhysicsSystem.h"
#include "physics/world/WorldQuery.h"

namespace strata::test {

/// A box rounded by the default convex radius, as BoxShape::Create makes it.
inline ShapeRef Box(float x, float y, float z) {
  return *BoxShape::Create({x, y, z});
}
/// A box with sharp edges (convex radius 0): separating axes, and face contacts the pair cache can slide.
inline ShapeRef SharpBox(float x, float y, float z) {
  return *BoxShape::Create({x, y, z}, 0.0f);
}
inline ShapeRef Sphere(float r) {
  return *SphereShape::Create(r);
}
inline ShapeRef Capsule(float half_height, float r) {
  return *CapsuleShape::Create(half_height, r);
}

/// Rolling terrain: `columns` x `rows` samples `cell` apart, bumps on a slope that falls along +x everywhere.
inline std::vector<float> RollingHeights(std::uint32_t columns, std::uint32_t rows, float cell) {
  std::vector<float> heights;
  for (std::uint32_t r = 0; r < rows; ++r)
    for (std::uint32_t c = 0; c < columns; ++c) {
      const float x = static_cast<float>(c) * cell, z = static_cast<float>(r) * cell;
      heights.push_back(1.0f - 0.08f * x + 0.1f * std::sin(0.7f * x) * std::cos(0.5f * z));
    }
  return heights;
}

inline ShapeRef HeightField(std::uint32_t columns, std::uint32_t rows, float cell,
                            const std::vector<float>& heights) {
  auto shape = HeightFieldShape::Create(columns, rows, cell, heights);
  EXPECT_TRUE(shape.ok()) << (shape.ok() ? "" : shape.error().message);
  return *shape;
}

/// The triangle mesh of a height field without holes: the same corners, computed the same way, and the
/// same triangle numbers.
inline ShapeRef MeshOf(const HeightFieldShape& field) {
  std::vector<Vec3> vertices;
  for (std::uint32_t r = 0; r < field.rows(); ++r)
    for (std::uint32_t c = 0; c < field.columns(); ++c)
      vertices.emplace_back(static_cast<float>(c) * field.cell_size(), field.Height(c, r),
                            static_cast<float>(r) * field.cell_size());
  std::vector<TriangleMeshShape::Indices> triangles;
  for (std::uint32_t r = 0; r + 1 < field.rows(); ++r)
    for (std::uint32_t c = 0; c + 1 < field.columns(); ++c) {
      const std::uint32_t i0 = r * field.columns() + c, i1 = i0 + 1, i2 = i0 + field.columns(), i3 = i2 + 1;
      triangles.push_back({i0, i2, i1});
      triangles.push_back({i1, i2, i3});
    }
  return *TriangleMeshShape::Create(vertices, triangles);
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
/// The positions of `ids`, x y z after each other: what determinism tests compare bit for bit.
inline std::vector<float> Positions(PhysicsSystem& world, const std::vector<BodyID>& ids) {
  std::vector<float> state;
  state.reserve(3 * ids.size());
  for (const BodyID id : ids) {
    const Vec3 p = Position(world, id);
    state.insert(state.end(), {p.x(), p.y(), p.z()});
  }
  return state;
}
inline Vec3 Velocity(PhysicsSystem& world, BodyID id) {
  return *world.bodies().GetLinearVelocity(id);
}

}  // namespace strata::test
