// NavMeshSettings: the Recast build parameters of a navmesh (cell sizes, agent, region and polygon
// settings) in world units, validated in one place before any tile is built.
// Value type; build it on any thread.
#pragma once

#include "navmesh/TileGrid.h"
#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata::navmesh {

/// Build parameters in metres and degrees. A tile is `tile_cells` x `tile_cells` cells of `cell_size`.
struct NavMeshSettings {
  float cell_size = 0.2f;         ///< horizontal voxel size (m)
  float cell_height = 0.2f;       ///< vertical voxel size (m)
  int tile_cells = 64;            ///< cells along a tile side (12.8 m at the default cell size)
  float agent_height = 2.0f;      ///< clearance an agent needs above the floor (m)
  float agent_radius = 0.6f;      ///< walkable area keeps this far from walls (m)
  float agent_max_climb = 0.9f;   ///< highest step an agent walks up (m)
  float agent_max_slope = 45.0f;  ///< steepest walkable slope (degrees)
  /// Deepest ledge an agent drops down (m): one-way links from walkable ledges to walkable ground up to this
  /// far below (0: none).
  float agent_max_drop = 0.0f;
  int region_min_size = 8;               ///< islands smaller than this many cells squared are dropped
  int region_merge_size = 20;            ///< regions smaller than this many cells squared are merged
  float edge_max_length = 12.0f;         ///< longest contour edge (m); 0 = unlimited
  float edge_max_error = 1.3f;           ///< how far a simplified contour may stray from the voxels (cells)
  int verts_per_poly = 6;                ///< 3..6
  float detail_sample_distance = 6.0f;   ///< detail mesh sampling (cells); < 0.9 turns it off
  float detail_sample_max_error = 1.0f;  ///< detail mesh height error (cell heights)

  /// The tile whose lower corner is the navmesh's own origin. Recast and Detour work in coordinates
  /// relative to it (world minus origin()), so a level far from the world origin keeps a float's full
  /// precision there; tile coordinates in the API stay world tiles. BakeLevel moves it to far levels.
  TileCoord origin_tile;

  /// Set by a service whose agent profiles share one rasterization of each tile (negative: this agent's
  /// own): the agent radius the tile border is sized for (at least agent_radius), and the climb within which
  /// the rasterizer favours a walkable surface over a steep one where they meet in a cell (at most
  /// agent_max_climb; the ledge filters still use agent_max_climb).
  float raster_border_radius = -1.0f;
  float raster_merge_climb = -1.0f;

  float tile_size() const { return cell_size * static_cast<float>(tile_cells); }
  /// World position of origin_tile's lower corner (y = 0).
  Vec3d origin() const;
  /// How far from the navmesh origin (m, on any axis) navmesh geometry may lie: 2^22 cells (839 km at
  /// 0.2 m). Beyond it a float resolves less than a third of a cell, and Recast's rasterizer (which clips
  /// triangles to cells in float) can overrun its buffers; such levels and requests are refused with this
  /// figure.
  float max_coordinate() const { return cell_size * 4194304.0f; }
  /// Cells of border around a tile so that erosion at its edge sees its neighbours' geometry.
  int border_cells() const;
  /// The climb the rasterizer merges walkable flags within (m).
  float merge_climb() const { return raster_merge_climb < 0.0f ? agent_max_climb : raster_merge_climb; }
  /// Every field in range; the message names the first bad one.
  Status Validate() const;
};

}  // namespace strata::navmesh
