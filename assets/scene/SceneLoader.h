// SceneLoader: reads the JSON scene format (assets/scenes/README.md) into validated body settings and
// builds a world from them. A bad file yields one error naming the file, the JSON path of the bad value
// and why; nothing is created. Stateless; safe from any thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "physics/body/BodyCreationSettings.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/world/PhysicsSystem.h"

namespace strata {

/// One named body of a scene.
struct SceneBody {
  std::string name;
  BodyCreationSettings settings;
};

/// One joint of a scene.
struct SceneConstraint {
  std::string name;
  std::string path;  ///< its JSON path, for errors found when the world is built
  int body_a = -1;   ///< index into Scene::bodies; -1: the world
  int body_b = 0;
  JointSettings settings;  ///< body ids are filled in by BuildSceneWorld
};

/// A parsed, validated scene.
struct Scene {
  PhysicsSettings physics;
  float dt = 1.0f / 60.0f;  ///< seconds per step
  std::vector<SceneBody> bodies;
  std::vector<SceneConstraint> constraints;
};

/// Body positions in a scene lie within this of the origin on every axis (m).
constexpr float kMaxScenePosition = 1.0e9f;
/// Scene files larger than this are refused before they are read (a scene lists bodies, not geometry).
constexpr std::uint64_t kMaxSceneFileBytes = std::uint64_t{64} << 20;

/// Reads and validates `path` (mesh `file` entries are resolved relative to it).
Result<Scene> LoadScene(const std::filesystem::path& path);
/// Parses scene JSON text; `source` names it in errors, `base_directory` resolves mesh files.
Result<Scene> ParseScene(const std::string& text, const std::string& source,
                         const std::filesystem::path& base_directory);

/// A world holding the scene's bodies and joints, and their ids in scene order.
struct SceneWorld {
  std::unique_ptr<PhysicsSystem> system;
  std::vector<BodyID> ids;
  std::vector<ConstraintID> constraint_ids;
};

/// Creates a world sized for the scene and adds every body and joint. `config` supplies threads and layers.
Result<SceneWorld> BuildSceneWorld(const Scene& scene, PhysicsSystemConfig config = {});

}  // namespace strata
