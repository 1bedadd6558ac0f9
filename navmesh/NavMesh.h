// NavMesh: the Detour navigation mesh that readers query while tiles are published into it. Owns one
// dtNavMesh behind a reader/writer lock: queries share it, publishing a tile takes it exclusively for the
// short time Detour needs to link the tile. Thread-safe. Saves and loads RecastDemo's tiled "MSET" format.
#pragma once

#include <DetourNavMesh.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

#include "navmesh/SetChecksums.h"
#include "navmesh/TileData.h"
#include "navmesh/TileGrid.h"
#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata::navmesh {

/// Polygon flags a query filter may test: ground an agent walks on, and an off-mesh link down a ledge.
inline constexpr unsigned short kGroundPolyFlag = 1;
inline constexpr unsigned short kDropLinkFlag = 2;

/// A Detour tiled navmesh shared between the threads that publish tiles and the threads that query it.
class NavMesh {
 public:
  /// A navmesh of square tiles `tile_size` metres wide, at most `max_tiles` of them (rounded up to a power of
  /// two; the rest of Detour's 22 reference bits go to polygons per tile).
  /// Detour works relative to the lower corner of `origin_tile` (see NavMeshSettings::origin_tile).
  /// `profile` names the agent profile it is built for (saved with it; empty: not named).
  static Result<std::unique_ptr<NavMesh>> Create(float tile_size, int max_tiles = 1024,
                                                 TileCoord origin_tile = {}, std::string profile = {});
  /// Reads a file in RecastDemo's tiled navmesh set format ("MSET", version 1). Fails, naming the file and
  /// the reason, for a missing, truncated or corrupt file, or one whose checksums (SetChecksums, which Save
  /// appends) do not match; a file without checksums (RecastDemo's own) loads unchecked.
  static Result<std::unique_ptr<NavMesh>> Load(const std::filesystem::path& path);
  ~NavMesh();
  NavMesh(const NavMesh&) = delete;
  NavMesh& operator=(const NavMesh&) = delete;

  /// Publishes `data` as tile `tile`, replacing what was there; empty data just removes the old tile.
  Status ReplaceTile(TileCoord tile, TileData data);
  void RemoveTile(TileCoord tile);

  /// Runs `function(const dtNavMesh&)` with publishing held off; keep it short.
  template <class Function>
  decltype(auto) Read(Function&& function) const {
    const std::shared_lock lock(mutex_);
    return function(static_cast<const dtNavMesh&>(*mesh_));
  }
  /// The raw Detour mesh for DetourCrowd and other Detour users. Reading it while tiles are being published
  /// is the caller's to avoid (hold Read, or publish nothing meanwhile). Its coordinates and tile
  /// coordinates are relative to origin() and origin_tile() (ToLocal / ToWorld convert).
  dtNavMesh& detour() { return *mesh_; }

  /// Counts the tiles published and removed: a reader holding polygon references (a crowd's corridors)
  /// checks them again when it changes.
  std::uint64_t version() const { return version_.load(std::memory_order_acquire); }

  float tile_size() const { return tile_size_; }
  TileCoord origin_tile() const { return origin_tile_; }
  /// World position of Detour's (0, 0, 0).
  const Vec3d& origin() const { return origin_; }
  Vec3 ToLocal(const Vec3& world) const { return (world.cast<double>() - origin_).cast<float>(); }
  Vec3 ToWorld(const Vec3& local) const { return (local.cast<double>() + origin_).cast<float>(); }
  int tile_count() const;
  std::vector<TileCoord> Tiles() const;
  /// Ground polygons over all tiles.
  int polygon_count() const;
  /// Drop links (one-way off-mesh connections) over all tiles.
  int link_count() const;
  /// Sum of the walkable polygons' areas projected on the x-z plane (m^2).
  double WalkableArea() const;

  /// Writes RecastDemo's tiled navmesh set format with a checksum per tile after the last one (RecastDemo
  /// stops reading before it); the set header's origin is origin() (zero for a navmesh at the world origin,
  /// where RecastDemo reads the file as its own).
  /// `coverage`: which share of a level the file holds (coverage() when not given).
  Status Save(const std::filesystem::path& path, std::optional<SetCoverage> coverage = std::nullopt) const;
  /// CRC-32 of the tiles' bytes as Save writes them, in coordinate order: navmeshes that hold the same tiles
  /// give the same value, whatever order they were published in.
  std::uint32_t TilesCrc() const;
  /// The share of a level this navmesh was loaded with (not known for one built here or a RecastDemo file).
  const SetCoverage& coverage() const { return coverage_; }
  /// The agent profile it was built for (AgentProfile::name), given at Create or read by Load; empty when
  /// not named (a RecastDemo file, an older Strata file).
  const std::string& profile() const { return profile_; }
  /// Writes the polygons as a Wavefront OBJ (one face per polygon).
  Status WriteObj(const std::filesystem::path& path) const;

 private:
  NavMesh(dtNavMesh* mesh, float tile_size, TileCoord origin_tile);
  TileCoord ToLocalTile(TileCoord tile) const { return {tile.x - origin_tile_.x, tile.z - origin_tile_.z}; }
  TileCoord ToWorldTile(int x, int z) const { return {x + origin_tile_.x, z + origin_tile_.z}; }

  mutable std::shared_mutex mutex_;
  std::atomic<std::uint64_t> version_{0};
  dtNavMesh* mesh_;
  float tile_size_;
  TileCoord origin_tile_;
  SetCoverage coverage_;  // set by Load; written only there, before the navmesh is shared
  std::string profile_;   // set by Create or Load, before the navmesh is shared
  Vec3d origin_;
};

/// Corner `corner` (0..2) of detail triangle `triangle` of polygon `poly` in `tile`, in the navmesh's own
/// frame (NavMesh::ToWorld gives world space). Detour numbers a detail corner below the polygon's vertex
/// count as one of the polygon's vertices, the rest as the tile's detail vertices.
Vec3 DetailTriangleCorner(const dtMeshTile& tile, int poly, int triangle, int corner);

/// The tiles of `mesh` that hold data, in coordinate order (x, then y, then layer): what is written or drawn
/// from a navmesh must not depend on which worker published a tile first (that decides its slot).
std::vector<const dtMeshTile*> TilesInOrder(const dtNavMesh& mesh);

}  // namespace strata::navmesh
