#include "assets/level/LevelLoader.h"

#include <cmath>
#include <future>
#include <map>
#include <unordered_map>

#include "physics/shapes/HeightFieldShape.h"
#include "physics/world/PhysicsSystem.h"

namespace strata {

namespace {

Error LevelError(const std::filesystem::path& path, const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, path.string() + ": " + why);
}

void DestroyAll(PhysicsSystem& world, std::span<const BodyID> ids) {
  for (const BodyID id : ids) (void)world.bodies().DestroyBody(id);
}

}  // namespace

Status LevelLoadOptions::Validate() const {
  if (!std::isfinite(world_tile_size) || world_tile_size <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "level: world_tile_size must be a positive number");
  if (!std::isfinite(friction) || friction < 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "level: friction must be >= 0");
  return height_map.Validate();
}

std::vector<LevelChunk> ChunkLevel(const ImportedMesh& mesh, float world_tile_size) {
  std::map<std::pair<int, int>, std::vector<std::uint32_t>> triangles_by_tile;  // (z, x): row order
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& corners = mesh.triangles[t];
    const Vec3 centroid =
        (mesh.vertices[corners[0]] + mesh.vertices[corners[1]] + mesh.vertices[corners[2]]) / 3.0f;
    triangles_by_tile[{static_cast<int>(std::floor(centroid.z() / world_tile_size)),
                       static_cast<int>(std::floor(centroid.x() / world_tile_size))}]
        .push_back(t);
  }
  std::vector<LevelChunk> chunks;
  for (const auto& [tile, triangles] : triangles_by_tile) {
    LevelChunk chunk{tile.second, tile.first, {}};
    std::unordered_map<std::uint32_t, std::uint32_t> local;
    for (const std::uint32_t t : triangles) {
      TriangleMeshShape::Indices indices;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t vertex = mesh.triangles[t][k];
        const auto [it, inserted] =
            local.try_emplace(vertex, static_cast<std::uint32_t>(chunk.mesh.vertices.size()));
        if (inserted) chunk.mesh.vertices.push_back(mesh.vertices[vertex]);
        indices[k] = it->second;
      }
      chunk.mesh.triangles.push_back(indices);
    }
    chunks.push_back(std::move(chunk));
  }
  return chunks;
}

bool LooksZUp(const ImportedMesh& mesh) {
  // Twice each triangle's area along each axis: floors face Y in a Y-up level. Walls face X and Z in
  // either, so Z must clearly outweigh Y before the level is called Z-up.
  double facing_y = 0.0, facing_z = 0.0;
  for (const TriangleMeshShape::Indices& t : mesh.triangles) {
    const Vec3 normal =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    facing_y += std::abs(static_cast<double>(normal.y()));
    facing_z += std::abs(static_cast<double>(normal.z()));
  }
  return facing_z > 2.0 * facing_y;
}

namespace {

BodyCreationSettings LevelBody(ShapeRef shape, const LevelLoadOptions& options) {
  BodyCreationSettings settings;
  settings.shape = std::move(shape);
  settings.motion_type = MotionType::kStatic;
  settings.object_layer = options.layer;
  settings.friction = options.friction;
  return settings;
}

// The bodies go into the world as one batch (nothing is in it until FinalizeLevel).
Status BatchLevel(PhysicsSystem& world, const std::filesystem::path& path, std::vector<BodyID>& created,
                  PreparedLevel& level) {
  Result<BodyAddBatch> batch = world.bodies().AddBodiesPrepare(created, Activation::kDontActivate);
  if (!batch) {
    DestroyAll(world, created);
    return LevelError(path, batch.error().message);
  }
  level.batch = std::move(*batch);
  return Status::Ok();
}

Result<PreparedLevel> PrepareTerrain(PhysicsSystem& world, const std::filesystem::path& path,
                                     const LevelLoadOptions& options) {
  const HeightMapImportOptions& terrain = options.height_map;
  Result<HeightMap> map = ImportHeightMapPicture(path, terrain.low, terrain.high);
  if (!map) return map.error();
  Result<ShapeRef> shape = HeightFieldShape::Create(map->columns, map->rows, terrain.cell_size, map->heights);
  if (!shape) return LevelError(path, shape.error().message);
  Result<BodyID> id = world.bodies().CreateBody(LevelBody(*shape, options));
  if (!id) return LevelError(path, id.error().message);
  PreparedLevel level;
  level.path = path;
  level.bounds = (*shape)->LocalBounds();
  level.triangles = static_cast<const HeightFieldShape&>(**shape).triangle_count();
  level.chunks = 1;
  std::vector<BodyID> created{*id};
  if (Status batched = BatchLevel(world, path, created, level); !batched) return batched.error();
  return level;
}

}  // namespace

Result<PreparedLevel> PrepareLevel(PhysicsSystem& world, const std::filesystem::path& path,
                                   const LevelLoadOptions& options) {
  if (Status status = options.Validate(); !status.ok()) return LevelError(path, status.message());
  if (options.layer >= world.layers().ObjectLayerCount())
    return LevelError(path, "object layer out of range");
  if (IsHeightMapPicture(path)) return PrepareTerrain(world, path, options);
  Result<ImportedMesh> mesh = ImportMesh(path, options.import);
  if (!mesh) return mesh.error();

  PreparedLevel level;
  level.path = path;
  if (LooksZUp(*mesh))
    level.warnings.push_back(path.string() + ": most of the level's surface faces along Z, not Y: it looks " +
                             (options.import.z_up ? "Y-up already; drop --z-up" : "Z-up; pass --z-up") +
                             " if its floors should be walkable");
  std::vector<BodyID> created;
  for (LevelChunk& chunk : ChunkLevel(*mesh, options.world_tile_size)) {
    Result<ShapeRef> shape = TriangleMeshShape::Create(chunk.mesh.vertices, chunk.mesh.triangles);
    if (!shape) {
      DestroyAll(world, created);
      return LevelError(path, "chunk (" + std::to_string(chunk.tile_x) + ", " + std::to_string(chunk.tile_z) +
                                  "): " + shape.error().message);
    }
    Result<BodyID> id = world.bodies().CreateBody(LevelBody(*shape, options));
    if (!id) {
      DestroyAll(world, created);
      return LevelError(path, id.error().message);
    }
    created.push_back(*id);
    level.bounds.Encapsulate((*shape)->LocalBounds());
    level.triangles += static_cast<const TriangleMeshShape&>(**shape).triangle_count();
    ++level.chunks;
  }
  if (Status batched = BatchLevel(world, path, created, level); !batched) return batched.error();
  return level;
}

Result<LoadedLevel> FinalizeLevel(PhysicsSystem& world, PreparedLevel&& level) {
  const std::vector<BodyID> ids = level.batch.ids;
  if (Status status = world.bodies().AddBodiesFinalize(level.batch); !status.ok()) {
    level.batch = {};  // gives the bodies back to the world (created, not added) so they can be destroyed
    DestroyAll(world, ids);
    return LevelError(level.path, status.message());
  }
  return LoadedLevel{ids, level.bounds, level.triangles, level.chunks, std::move(level.warnings)};
}

Result<LoadedLevel> LoadLevel(PhysicsSystem& world, const std::filesystem::path& path,
                              const LevelLoadOptions& options) {
  std::future<Result<PreparedLevel>> loading =
      std::async(std::launch::async, [&] { return PrepareLevel(world, path, options); });
  Result<PreparedLevel> prepared = loading.get();
  if (!prepared) return prepared.error();
  return FinalizeLevel(world, std::move(*prepared));
}

}  // namespace strata
