// LevelGenerator: builds the bundled sample levels (assets/levels) from boxes, wedges and quads, so they
// can be regenerated and their features (ramps, stairs, bridge, walls) are known exactly to tests.
// Pure functions; safe from any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "assets/import/MeshImporter.h"

namespace strata::levelgen {

/// Appends closed, outward-facing (counter-clockwise) solids and open surfaces to a triangle list.
class MeshBuilder {
 public:
  /// A closed box [min, max].
  void AddBox(const Vec3& min, const Vec3& max);
  /// A closed wedge over [min, max] in x-z rising from height min.y at `low_x`/`low_z` side to max.y at the
  /// opposite side, along x when `along_x`, else along z.
  void AddRamp(const Vec3& min, const Vec3& max, bool along_x, bool rising_positive);
  /// A flight of `steps` boxes standing on start.y, each `run` long along +x and `width` wide (+z from
  /// start); each step is `rise` higher than the last, rising toward +x or, with `rise_toward_minus_x`, -x.
  void AddStairs(const Vec3& start, int steps, float rise, float run, float width,
                 bool rise_toward_minus_x = false);
  /// An upward-facing quad [x0, x1] x [z0, z1] at height y.
  void AddFloor(float x0, float x1, float z0, float z1, float y);

  ImportedMesh Take() { return std::move(mesh_); }

 private:
  std::uint32_t Vertex(const Vec3& v);
  void Quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);  // counter-clockwise from outside

  ImportedMesh mesh_;
};

/// A described level: the mesh plus what its name and file are.
struct GeneratedLevel {
  std::string name;
  ImportedMesh mesh;
};

/// "courtyard": 64 m x 64 m (5 x 5 navmesh tiles) with perimeter walls and a gate, an inner wall,
/// pillars, a 30 degree ramp and a flight of stairs up to a 3 m platform, a 50 degree ramp to a ledge,
/// and an 8 m wide, 6 m deep trench across the whole level, crossed by one bridge.
GeneratedLevel Courtyard();
/// "arena": a 25.6 m square floor (2 x 2 tiles) with pillars and low steps; small and quick to bake.
GeneratedLevel Arena();
/// "field": an open world's worth of ground, `size` m square from the origin, with a feature in most 25.6 m
/// cells (a building, a ramp up onto a roof, a low wall, a pillar), placed by `seed` alone: the same size
/// and seed give the same triangles on any machine (no std:: distributions, whose output is the library's
/// choice). For farm bakes and open-world tests at any scale; `size` from 25.6 m to 16 km.
GeneratedLevel Field(float size, std::uint32_t seed);

}  // namespace strata::levelgen
