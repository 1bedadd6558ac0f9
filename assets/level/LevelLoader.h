// LevelLoader: brings a level mesh file into a physics world as static TriangleMesh bodies, one per world
// tile (default 256 m), or a height-map picture (.png) as one static HeightField body, streamed in as a
// batch: PrepareLevel runs on a loading thread (import, chunking, shape BVHs, body creation, broad-phase
// sub-trees) and FinalizeLevel links it in on the caller in O(1) per tree. Either the whole level goes in or
// nothing does: on any error the world is left as it was.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "assets/import/HeightMapImporter.h"
#include "assets/import/MeshImporter.h"
#include "physics/body/BodyInterface.h"

namespace strata {
class PhysicsSystem;

/// How a level file becomes bodies.
struct LevelLoadOptions {
  MeshImportOptions import;
  HeightMapImportOptions height_map;  ///< for a .png level: its cell size and the heights of black and white
  float world_tile_size = 256.0f;     ///< side of the square chunks the level is cut into (m)
  ObjectLayer layer = layers::kNonMoving;
  float friction = 0.6f;
  Status Validate() const;
};

/// The triangles of one world tile, indexed into their own vertex list.
struct LevelChunk {
  int tile_x = 0;
  int tile_z = 0;
  ImportedMesh mesh;
};

/// Cuts a mesh into chunks by the world tile each triangle's centroid falls in, ordered by tile.
std::vector<LevelChunk> ChunkLevel(const ImportedMesh& mesh, float world_tile_size);

/// A level ready to be finalized.
struct PreparedLevel {
  std::filesystem::path path;
  BodyAddBatch batch;
  AABB bounds;
  std::size_t triangles = 0;
  std::size_t chunks = 0;
  std::vector<std::string> warnings;  ///< valid but suspicious input (a level that looks Z-up), for people
};

/// What a finalized level put in the world.
struct LoadedLevel {
  std::vector<BodyID> bodies;
  AABB bounds;
  std::size_t triangles = 0;
  std::size_t chunks = 0;
  std::vector<std::string> warnings;
};

/// Whether most of a mesh's surface faces along Z rather than Y: a level whose floors face Z was most
/// likely made Z-up and imported without the conversion (or converted when it was Y-up already).
bool LooksZUp(const ImportedMesh& mesh);

/// Loading-thread half: imports, chunks and prepares the bodies; nothing is in the world yet. A .png file is
/// terrain: one height field with its first pixel at the origin (no chunks: a chunk border would be an edge
/// that sliding bodies catch on). Fails, with the file and the reason, for a missing, unsupported or corrupt
/// file, an empty mesh or NaN vertices.
Result<PreparedLevel> PrepareLevel(PhysicsSystem& world, const std::filesystem::path& path,
                                   const LevelLoadOptions& options = {});
/// Caller half: puts the prepared bodies in the world. On failure the bodies are destroyed.
Result<LoadedLevel> FinalizeLevel(PhysicsSystem& world, PreparedLevel&& level);
/// Both halves: PrepareLevel on a loading thread while the caller waits, FinalizeLevel on the caller.
Result<LoadedLevel> LoadLevel(PhysicsSystem& world, const std::filesystem::path& path,
                              const LevelLoadOptions& options = {});

}  // namespace strata
