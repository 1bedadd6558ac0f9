#include "tools/levelgen/LevelGenerator.h"

#include <algorithm>
#include <cmath>

namespace strata::levelgen {

std::uint32_t MeshBuilder::Vertex(const Vec3& v) {
  mesh_.vertices.push_back(v);
  return static_cast<std::uint32_t>(mesh_.vertices.size() - 1);
}

void MeshBuilder::Quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::uint32_t ia = Vertex(a), ib = Vertex(b), ic = Vertex(c), id = Vertex(d);
  mesh_.triangles.push_back({ia, ib, ic});
  mesh_.triangles.push_back({ia, ic, id});
}

void MeshBuilder::AddFloor(float x0, float x1, float z0, float z1, float y) {
  Quad({x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0});
}

void MeshBuilder::AddBox(const Vec3& min, const Vec3& max) {
  const float x0 = min.x(), y0 = min.y(), z0 = min.z(), x1 = max.x(), y1 = max.y(), z1 = max.z();
  Quad({x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0});  // top (+y)
  Quad({x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1});  // bottom (-y)
  Quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1});  // +x
  Quad({x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0});  // -x
  Quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1});  // +z
  Quad({x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0});  // -z
}

void MeshBuilder::AddRamp(const Vec3& min, const Vec3& max, bool along_x, bool rising_positive) {
  // Build rising along +x in a local frame, then map the corners into place.
  const auto place = [&](float u, float y, float w) -> Vec3 {
    // u in [0, 1] along the rise, w in [0, 1] across it.
    const float t = rising_positive ? u : 1.0f - u;
    if (along_x) return {min.x() + t * (max.x() - min.x()), y, min.z() + w * (max.z() - min.z())};
    return {min.x() + w * (max.x() - min.x()), y, min.z() + t * (max.z() - min.z())};
  };
  const float low = min.y(), high = max.y();
  const Vec3 a = place(0, low, 0), b = place(1, low, 0), c = place(1, low, 1), d = place(0, low, 1);
  const Vec3 e = place(1, high, 0), f = place(1, high, 1);
  // Winding depends on whether the mapping mirrors the frame; fix each face by its intended normal.
  const auto oriented_quad = [&](Vec3 p, Vec3 q, Vec3 r, Vec3 s, const Vec3& outward) {
    if ((q - p).cross(r - p).dot(outward) < 0.0f) std::swap(q, s);
    Quad(p, q, r, s);
  };
  const auto oriented_triangle = [&](const Vec3& p, Vec3 q, Vec3 r, const Vec3& outward) {
    if ((q - p).cross(r - p).dot(outward) < 0.0f) std::swap(q, r);
    const std::uint32_t ip = Vertex(p), iq = Vertex(q), ir = Vertex(r);
    mesh_.triangles.push_back({ip, iq, ir});
  };
  const Vec3 center = 0.5f * (min + max);
  const auto outward = [&](const Vec3& face_point) { return face_point - center; };
  oriented_quad(a, b, c, d, Vec3(0, -1, 0));                                       // bottom
  oriented_quad(a, d, f, e, Vec3(0, 1, 0));                                        // slope, faces up
  oriented_quad(b, e, f, c, outward(0.5f * (b + f)).cwiseProduct(Vec3(1, 0, 1)));  // high end wall
  oriented_triangle(a, b, e, outward(0.25f * (a + b) + 0.5f * e).cwiseProduct(Vec3(1, 0, 1)));  // side
  oriented_triangle(d, c, f, outward(0.25f * (d + c) + 0.5f * f).cwiseProduct(Vec3(1, 0, 1)));  // side
}

void MeshBuilder::AddStairs(const Vec3& start, int steps, float rise, float run, float width,
                            bool rise_toward_minus_x) {
  for (int i = 0; i < steps; ++i) {
    const int height_steps = rise_toward_minus_x ? steps - i : i + 1;
    AddBox(Vec3(start.x() + run * static_cast<float>(i), start.y(), start.z()),
           Vec3(start.x() + run * static_cast<float>(i + 1),
                start.y() + rise * static_cast<float>(height_steps), start.z() + width));
  }
}

GeneratedLevel Courtyard() {
  MeshBuilder builder;
  constexpr float kSize = 64.0f;
  // Ground in 8 m quads, leaving out the trench x in [40, 48], which runs the level's whole depth so the
  // bridge is the only way across.
  for (float z = 0.0f; z < kSize; z += 8.0f)
    for (float x = 0.0f; x < kSize; x += 8.0f)
      if (x != 40.0f) builder.AddFloor(x, x + 8.0f, z, z + 8.0f, 0.0f);
  // The trench: a floor 6 m down, its side walls and end walls.
  builder.AddFloor(40.0f, 48.0f, 0.0f, kSize, -6.0f);
  builder.AddBox({38.0f, -6.0f, 0.0f}, {40.0f, 0.0f, kSize});
  builder.AddBox({48.0f, -6.0f, 0.0f}, {50.0f, 0.0f, kSize});
  builder.AddBox({40.0f, -6.0f, -2.0f}, {48.0f, 0.0f, 0.0f});
  builder.AddBox({40.0f, -6.0f, kSize}, {48.0f, 0.0f, kSize + 2.0f});
  // The bridge: a 4 m wide deck at ground level with low rails.
  builder.AddBox({38.0f, -0.4f, 30.0f}, {50.0f, 0.0f, 34.0f});
  builder.AddBox({40.0f, 0.0f, 29.8f}, {48.0f, 1.0f, 30.0f});
  builder.AddBox({40.0f, 0.0f, 34.0f}, {48.0f, 1.0f, 34.2f});
  // Perimeter walls (3 m), with a 4 m gate in the south wall.
  builder.AddBox({0.0f, 0.0f, 0.0f}, {30.0f, 3.0f, 0.5f});
  builder.AddBox({34.0f, 0.0f, 0.0f}, {kSize, 3.0f, 0.5f});
  builder.AddBox({0.0f, 0.0f, kSize - 0.5f}, {kSize, 3.0f, kSize});
  builder.AddBox({0.0f, 0.0f, 0.5f}, {0.5f, 3.0f, kSize - 0.5f});
  builder.AddBox({kSize - 0.5f, 0.0f, 0.5f}, {kSize, 3.0f, kSize - 0.5f});
  // An inner wall across two tiles and some pillars.
  builder.AddBox({6.0f, 0.0f, 20.0f}, {30.0f, 3.0f, 20.6f});
  for (const float x : {10.0f, 18.0f, 26.0f}) builder.AddBox({x, 0.0f, 10.0f}, {x + 1.2f, 2.5f, 11.2f});
  builder.AddBox({52.0f, 0.0f, 40.0f}, {56.0f, 1.5f, 44.0f});  // a crate stack too high to climb
  // The platform (3 m) with a 30 degree ramp up its west side and stairs down its east side.
  builder.AddBox({12.0f, 0.0f, 38.0f}, {22.0f, 3.0f, 50.0f});
  const float ramp_run = 3.0f / std::tan(30.0f * kPi / 180.0f);
  builder.AddRamp({12.0f - ramp_run, 0.0f, 42.0f}, {12.0f, 3.0f, 46.0f}, true, true);
  builder.AddStairs({22.0f, 0.0f, 42.0f}, 9, 0.3f, 0.6f, 4.0f, true);  // 2.7 m down to 0.3 m
  // A 50 degree ramp to a ledge: too steep, so the ledge is an island of its own.
  builder.AddBox({54.0f, 0.0f, 54.0f}, {63.5f, 3.0f, 63.5f});
  const float steep_run = 3.0f / std::tan(50.0f * kPi / 180.0f);
  builder.AddRamp({56.0f, 0.0f, 54.0f - steep_run}, {60.0f, 3.0f, 54.0f}, false, true);
  return {"courtyard", builder.Take()};
}

namespace {

// SplitMix64: a fixed, well-mixed sequence from the seed, the same on every platform.
class FieldRandom {
 public:
  explicit FieldRandom(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// In [low, high), on a 1/1024 grid of the span so the file's numbers are short and exact.
  float Uniform(float low, float high) {
    return low + (high - low) * static_cast<float>(Next() % 1024) / 1024.0f;
  }

 private:
  std::uint64_t state_;
};

constexpr float kFieldCell = 25.6f;

// One feature inside the cell whose low corner is (x, z): it keeps 2 m from the cell's edges, so features
// never touch and the ground between them stays walkable.
void AddFieldFeature(MeshBuilder& builder, FieldRandom& random, float x, float z) {
  const float margin = 2.0f, span = kFieldCell - 2.0f * margin;
  const std::uint64_t kind = random.Next() % 10;
  const float width = random.Uniform(4.0f, 10.0f), depth = random.Uniform(4.0f, 10.0f);
  const float x0 = x + margin + random.Uniform(0.0f, span - width);
  const float z0 = z + margin + random.Uniform(0.0f, span - depth);
  if (kind < 3) {  // open ground
    return;
  } else if (kind < 6) {  // a building
    builder.AddBox({x0, 0.0f, z0}, {x0 + width, random.Uniform(2.5f, 8.0f), z0 + depth});
  } else if (kind < 8) {  // a ramp up onto a roof: a second walkable level, linked to the ground
    const float height = random.Uniform(1.5f, 3.0f), ramp = 2.0f * height;  // about 27 degrees
    const float start = x + margin + random.Uniform(0.0f, span - ramp - width);
    builder.AddRamp({start, 0.0f, z0}, {start + ramp, height, z0 + depth}, /*along_x=*/true,
                    /*rising_positive=*/true);
    builder.AddBox({start + ramp, 0.0f, z0}, {start + ramp + width, height, z0 + depth});
  } else if (kind < 9) {  // a low wall, one agent's climb too high
    builder.AddBox({x0, 0.0f, z0}, {x0 + width, 1.2f, z0 + 0.4f});
  } else {  // a pillar
    builder.AddBox({x0, 0.0f, z0}, {x0 + 1.0f, 6.0f, z0 + 1.0f});
  }
}

}  // namespace

GeneratedLevel Field(float size, std::uint32_t seed) {
  MeshBuilder builder;
  FieldRandom random(seed);
  const int cells = std::max(1, static_cast<int>(std::ceil(size / kFieldCell - 1e-4f)));
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      const float x = static_cast<float>(i) * kFieldCell, z = static_cast<float>(j) * kFieldCell;
      builder.AddFloor(x, std::min(x + kFieldCell, size), z, std::min(z + kFieldCell, size), 0.0f);
      // Features only in whole cells, so a size that is not a multiple of the cell still ends in ground.
      if (x + kFieldCell <= size && z + kFieldCell <= size) AddFieldFeature(builder, random, x, z);
    }
  }
  return {"field", builder.Take()};
}

GeneratedLevel Arena() {
  MeshBuilder builder;
  builder.AddFloor(0.0f, 25.6f, 0.0f, 25.6f, 0.0f);
  for (const float x : {6.0f, 18.0f})
    for (const float z : {6.0f, 18.0f}) builder.AddBox({x, 0.0f, z}, {x + 1.5f, 3.0f, z + 1.5f});
  builder.AddStairs({10.0f, 0.0f, 11.0f}, 3, 0.3f, 1.0f, 3.0f);
  return {"arena", builder.Take()};
}

}  // namespace strata::levelgen
