// SceneLoader: reads the JSON scene format (assets/scenes/README.md) into a validated SceneDescription and
// builds a world from it. A bad file yields one error naming the file, the JSON path of the bad value
// and why; nothing is created. Stateless; safe from any thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "assets/scene/SceneDescription.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/shapes/Shape.h"
#include "physics/world/PhysicsSystem.h"

namespace strata {

/// A parsed, validated scene: what the file describes, engine-neutral, and each body's shape, made (and
/// checked) as the file was read. BuildSceneWorld turns it into a world through SceneBuilder.
struct Scene {
  SceneDescription description;
  std::vector<ShapeRef> shapes;  ///< one per description body, in order
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
