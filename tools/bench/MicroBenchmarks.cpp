// Google Benchmark micro benchmarks for the hot pieces: 1M-triangle mesh build and queries, the narrow
// phase pair tests, hull building, and whole steps of worlds of a few bodies (Strata's fixed cost per step),
// Bullet beside. `strata_microbench` prints the figures; nothing here asserts on time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numeric>
#include <random>

#include "physics/narrowphase/CollideShapes.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"
#include "physics/solver/IslandBuilder.h"
#include "tools/accuracy/AccuracyCases.h"
#include "tools/bench/BenchScenes.h"

namespace strata {
namespace {

struct GridMesh {
  std::vector<Vec3> vertices;
  std::vector<TriangleMeshShape::Indices> triangles;
};

// A wavy grid of cells x cells quads: 2 * cells^2 triangles.
GridMesh MakeGrid(int cells) {
  GridMesh grid;
  for (int z = 0; z <= cells; ++z)
    for (int x = 0; x <= cells; ++x)
      grid.vertices.emplace_back(x * 1.0f, 2.0f * std::sin(x * 0.1f) * std::cos(z * 0.1f), z * 1.0f);
  for (int z = 0; z < cells; ++z)
    for (int x = 0; x < cells; ++x) {
      const std::uint32_t i0 = z * (cells + 1) + x, i1 = i0 + 1, i2 = i0 + cells + 1, i3 = i2 + 1;
      grid.triangles.push_back({i0, i2, i1});
      grid.triangles.push_back({i1, i2, i3});
    }
  return grid;
}

const GridMesh& MillionTriangleGrid() {
  static const GridMesh grid = MakeGrid(708);  // 1,002,528 triangles
  return grid;
}

const TriangleMeshShape& MillionTriangleMesh() {
  static const ShapeRef mesh =
      *TriangleMeshShape::Create(MillionTriangleGrid().vertices, MillionTriangleGrid().triangles);
  return static_cast<const TriangleMeshShape&>(*mesh);
}

void BM_TriangleMeshBuild1M(benchmark::State& state) {
  const GridMesh& grid = MillionTriangleGrid();
  for (auto _ : state) benchmark::DoNotOptimize(TriangleMeshShape::Create(grid.vertices, grid.triangles));
  state.counters["triangles"] = static_cast<double>(grid.triangles.size());
}
BENCHMARK(BM_TriangleMeshBuild1M)->Unit(benchmark::kMillisecond);

// 3 x 6 x 3 m boxes at random places on the terrain (a body's neighbourhood in the narrow phase).
template <class TriangleShape>
void QueryBoxes(benchmark::State& state, const TriangleShape& shape) {
  std::mt19937 random(1);
  std::uniform_real_distribution<float> coordinate(0.0f, 700.0f);
  std::vector<std::uint32_t> found;
  for (auto _ : state) {
    found.clear();
    const Vec3 center(coordinate(random), 0.0f, coordinate(random));
    shape.QueryBox(AABB::FromCenterHalfExtents(center, Vec3(1.5f, 3.0f, 1.5f)), found);
    benchmark::DoNotOptimize(found.data());
  }
}

// 100 m rays slanting down from 10 m above the terrain towards random places on it.
void CastRays(benchmark::State& state, const Shape& shape) {
  std::mt19937 random(2);
  std::uniform_real_distribution<float> coordinate(0.0f, 700.0f);
  ShapeRayHit hit;
  for (auto _ : state) {
    const Vec3 origin(coordinate(random), 10.0f, coordinate(random));
    const Vec3 target(coordinate(random), -5.0f, coordinate(random));
    benchmark::DoNotOptimize(shape.CastRay(origin, (target - origin).normalized() * 100.0f, 1.0f, hit));
  }
}

void BM_TriangleMeshQueryBox1M(benchmark::State& state) {
  QueryBoxes(state, MillionTriangleMesh());
}
BENCHMARK(BM_TriangleMeshQueryBox1M);

void BM_TriangleMeshRayCast1M(benchmark::State& state) {
  CastRays(state, MillionTriangleMesh());
}
BENCHMARK(BM_TriangleMeshRayCast1M);

// The same million triangles as a height field: the grid is the index, so there is nothing to build.
const HeightFieldShape& MillionTriangleField() {
  static const ShapeRef field = [] {
    constexpr int kSamples = 709;
    std::vector<float> heights;
    for (const Vec3& vertex : MillionTriangleGrid().vertices) heights.push_back(vertex.y());
    return *HeightFieldShape::Create(kSamples, kSamples, 1.0f, heights);
  }();
  return static_cast<const HeightFieldShape&>(*field);
}

void BM_HeightFieldQueryBox1M(benchmark::State& state) {
  QueryBoxes(state, MillionTriangleField());
}
BENCHMARK(BM_HeightFieldQueryBox1M);

void BM_HeightFieldRayCast1M(benchmark::State& state) {
  CastRays(state, MillionTriangleField());
}
BENCHMARK(BM_HeightFieldRayCast1M);

template <class MakeA, class MakeB>
void CollidePair(benchmark::State& state, MakeA make_a, MakeB make_b, const Pose& pose_b) {
  const ShapeRef a = make_a(), b = make_b();
  const Pose pose_a{Vec3::Zero(), Quat::Identity()};
  for (auto _ : state) {
    ContactManifold manifold;
    benchmark::DoNotOptimize(CollideConvexConvex(static_cast<const ConvexShape&>(*a), pose_a,
                                                 static_cast<const ConvexShape&>(*b), pose_b, 0.02f,
                                                 manifold));
  }
}

void BM_CollideBoxOnBox(benchmark::State& state) {
  CollidePair(
      state, [] { return *BoxShape::Create(Vec3(1, 1, 1), 0.0f); },
      [] { return *BoxShape::Create(Vec3(1, 1, 1), 0.0f); },
      Pose{Vec3(0.2f, 1.99f, 0.1f), Quat(Eigen::AngleAxisf(0.1f, Vec3::UnitY()))});
}
BENCHMARK(BM_CollideBoxOnBox);

// The same pair rounded by the default convex radius: GJK on the cores instead of separating axes.
void BM_CollideRoundedBoxOnBox(benchmark::State& state) {
  CollidePair(
      state, [] { return *BoxShape::Create(Vec3(1, 1, 1)); }, [] { return *BoxShape::Create(Vec3(1, 1, 1)); },
      Pose{Vec3(0.2f, 1.99f, 0.1f), Quat(Eigen::AngleAxisf(0.1f, Vec3::UnitY()))});
}
BENCHMARK(BM_CollideRoundedBoxOnBox);

void BM_CollideCapsuleOnBox(benchmark::State& state) {
  CollidePair(
      state, [] { return *BoxShape::Create(Vec3(2, 1, 2)); },
      [] { return *CapsuleShape::Create(0.75f, 0.5f); },
      Pose{Vec3(0.2f, 1.49f, 0.1f), Quat(Eigen::AngleAxisf(1.5f, Vec3::UnitZ()))});
}
BENCHMARK(BM_CollideCapsuleOnBox);

// Each convex_vs_mesh benchmark shape resting, tilted, on the benchmark's wavy mesh at 64 places (the last
// one a little below the surface): one CollideConvexMesh call per place, so the figure is per body per step.
void BM_CollideConvexOnMesh(benchmark::State& state) {
  const bench::BenchScene scene = bench::MakeConvexVsMesh();
  const ShapeRef mesh = *TriangleMeshShape::Create(scene.meshes[0].vertices, scene.meshes[0].triangles);
  ShapeRef convex;
  switch (state.range(0)) {
    case 0:
      convex = *SphereShape::Create(0.5f), state.SetLabel("sphere");
      break;
    case 1:
      convex = *BoxShape::Create(Vec3(0.5f, 0.75f, 1.0f)), state.SetLabel("box");
      break;
    case 2:
      convex = *CapsuleShape::Create(0.75f, 0.5f), state.SetLabel("capsule");
      break;
    case 3:
      convex = *ConvexHullShape::Create(scene.hulls[0].points), state.SetLabel("hull");
      break;
    // The same box and hull with sharp edges: separating axes instead of GJK on the rounded cores.
    case 4:
      convex = *BoxShape::Create(Vec3(0.5f, 0.75f, 1.0f), 0.0f), state.SetLabel("sharp box");
      break;
    default:
      convex = *ConvexHullShape::Create(scene.hulls[0].points, 0.0f), state.SetLabel("sharp hull");
      break;
  }
  const auto& shape = static_cast<const ConvexShape&>(*convex);
  const auto& triangle_mesh = static_cast<const TriangleMeshShape&>(*mesh);
  std::vector<Pose> poses;
  for (int i = 0; i < 64; ++i) {
    const float x = -120.0f + 3.7f * static_cast<float>(i), z = 40.0f - 2.3f * static_cast<float>(i);
    ShapeRayHit hit;
    if (!triangle_mesh.CastRay(Vec3(x, 50.0f, z), Vec3(0, -100.0f, 0), 1.0f, hit)) continue;
    const float ground = 50.0f - 100.0f * hit.fraction;
    // The lowest point of the tilted shape just touches (or sinks a centimetre into) the ground below it.
    const Quat rotation(Eigen::AngleAxisf(0.2f * static_cast<float>(i), Vec3(1, 2, 3).normalized()));
    const float lowest = (rotation * shape.Support(rotation.conjugate() * Vec3(0, -1, 0))).y();
    poses.push_back({Vec3(x, ground - lowest - 0.005f * static_cast<float>(i % 3), z), rotation});
  }
  std::vector<ContactManifold> out;
  const Pose identity;
  std::size_t manifolds = 0;
  for (auto _ : state) {
    for (const Pose& pose : poses) {
      out.clear();
      CollideConvexMesh(shape, pose, triangle_mesh, identity, 0.05f, {}, out);
      manifolds += out.size();
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * poses.size()));
  state.counters["manifolds_per_body"] =
      static_cast<double>(manifolds) / static_cast<double>(state.iterations() * poses.size());
}
BENCHMARK(BM_CollideConvexOnMesh)->DenseRange(0, 5);

// The pyramid benchmark's contact graph: boxes whose centres are closer than 3 m touch (side neighbours at
// 2 m, the four below at 2.9 m), linked in the order the narrow phase finds them (by the lower body).
struct ContactGraph {
  std::uint32_t bodies = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
};

const ContactGraph& PyramidContactGraph() {
  static const ContactGraph graph = [] {
    ContactGraph g;
    std::vector<Vec3> centres;
    for (const BodyDescription& body : bench::MakePyramid().bodies)
      if (body.IsDynamic()) centres.push_back(body.position);
    g.bodies = static_cast<std::uint32_t>(centres.size());
    for (std::uint32_t a = 0; a < g.bodies; ++a)
      for (std::uint32_t b = a + 1; b < g.bodies; ++b)
        if ((centres[a] - centres[b]).norm() < 3.0f) g.links.emplace_back(a, b);
    return g;
  }();
  return graph;
}

// Lock-free union: time per Link and how many links each find followed (the design: 0.07 us, 0.9 loops).
void BM_IslandLink(benchmark::State& state) {
  const ContactGraph& graph = PyramidContactGraph();
  IslandBuilder islands;
  std::uint64_t hops = 0;
  for (auto _ : state) {
    islands.Reset(graph.bodies);
    for (const auto& [a, b] : graph.links) hops += islands.Link(a, b);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * graph.links.size()));
  state.counters["links"] = static_cast<double>(graph.links.size());
  state.counters["ns_per_link"] = benchmark::Counter(
      static_cast<double>(state.iterations() * graph.links.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
  // Two finds per link.
  state.counters["loops_per_find"] =
      static_cast<double>(hops) / (2.0 * static_cast<double>(state.iterations() * graph.links.size()));
}
BENCHMARK(BM_IslandLink);

// The part of island building left on one thread: Finalize, after the links were made in the narrow phase.
void BM_IslandFinalizeSerialPart(benchmark::State& state) {
  const ContactGraph& graph = PyramidContactGraph();
  IslandBuilder islands;
  std::vector<std::uint32_t> constraint_body;
  for (const auto& link : graph.links) constraint_body.push_back(link.first);
  for (auto _ : state) {
    state.PauseTiming();
    islands.Reset(graph.bodies);
    for (const auto& [a, b] : graph.links) islands.Link(a, b);
    state.ResumeTiming();
    islands.Finalize(constraint_body);
    benchmark::DoNotOptimize(islands.island_count());
  }
}
BENCHMARK(BM_IslandFinalizeSerialPart);

// What the step did on one thread before: union-find over every contact, a find per body, then the
// bodies and contacts grouped by island.
void BM_IslandSerialUnionFindBefore(benchmark::State& state) {
  const ContactGraph& graph = PyramidContactGraph();
  std::vector<std::uint32_t> parent(graph.bodies), island_of(graph.bodies), counts, order(graph.bodies);
  std::vector<std::uint32_t> contact_order(graph.links.size());
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (auto _ : state) {
    std::iota(parent.begin(), parent.end(), 0u);
    for (const auto& [a, b] : graph.links) {
      const std::uint32_t ra = find(a), rb = find(b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    counts.assign(graph.bodies + 1, 0);
    for (std::uint32_t i = 0; i < graph.bodies; ++i) ++counts[(island_of[i] = find(i)) + 1];
    for (std::uint32_t i = 1; i <= graph.bodies; ++i) counts[i] += counts[i - 1];
    for (std::uint32_t i = 0; i < graph.bodies; ++i) order[counts[island_of[i]]++] = i;
    for (std::size_t k = 0; k < graph.links.size(); ++k) contact_order[k] = island_of[graph.links[k].first];
    benchmark::DoNotOptimize(order.data());
    benchmark::DoNotOptimize(contact_order.data());
  }
}
BENCHMARK(BM_IslandSerialUnionFindBefore);

void BM_ConvexHullBuild(benchmark::State& state) {
  std::mt19937 random(3);
  std::normal_distribution<float> coordinate(0.0f, 1.0f);
  std::vector<Vec3> points(static_cast<std::size_t>(state.range(0)));
  for (Vec3& p : points) p = Vec3(coordinate(random), coordinate(random), coordinate(random));
  for (auto _ : state) benchmark::DoNotOptimize(ConvexHullShape::Create(points));
}
BENCHMARK(BM_ConvexHullBuild)->Arg(32)->Arg(256);

// Worlds of a few bodies, where the cost every step pays whatever the scene decides: the accuracy suite's
// sliding box (`energy_drift`, 60 s) and 100 kg box on a 1 kg one (`mass_ratio_100`, 5 s), run whole from
// the start at dt 1/30 with one step, one velocity and one relax pass (Bullet's cheapest setting in the
// suite). Argument 1 runs Bullet. One iteration is the whole run; building the world is not timed.
void StepWholeRun(benchmark::State& state, const SceneDescription& scene, double seconds) {
  const bool bullet = state.range(0) == 1;
  const accuracy::AccuracySetting setting{"dt1/30 sub1", 1.0f / 30.0f, 1, 1, 1, true, true};
  const int steps = static_cast<int>(std::ceil(seconds / setting.dt - 1e-6));
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<accuracy::AccuracyEngine> engine =
        bullet ? accuracy::MakeBulletEngine() : accuracy::MakeStrataEngine();
    if (!engine || !engine->Build(scene, setting)) {
      state.SkipWithError(engine ? "the scene did not build" : "built without Bullet");
      return;
    }
    state.ResumeTiming();
    for (int step = 0; step < steps; ++step)
      if (!engine->Step()) {
        state.SkipWithError("a step failed");
        return;
      }
  }
  state.SetItemsProcessed(state.iterations() * steps);  // items/s = steps/s
}

void BM_StepSlidingBox(benchmark::State& state) {
  StepWholeRun(state, accuracy::SlidingBoxScene(), 60.0);
}
BENCHMARK(BM_StepSlidingBox)->ArgName("bullet")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The sliding box without its walls, on a floor wide enough for the minute (180 m at 3 m/s): both engines
// keep the box on the floor, so this is what one sliding contact costs each, like for like. In
// BM_StepSlidingBox Bullet's box, set tumbling by the wall hits, is off the floor for most of its steps.
void BM_StepSlidingOnFloor(benchmark::State& state) {
  SceneDescription scene = accuracy::SlidingBoxScene();
  scene.bodies.erase(scene.bodies.begin() + 1, scene.bodies.begin() + 3);  // the walls
  scene.bodies.front().half_extents = Vec3(200.0f, 1.0f, 200.0f);
  StepWholeRun(state, scene, 60.0);
}
BENCHMARK(BM_StepSlidingOnFloor)->ArgName("bullet")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// One sphere drifting through empty space for a minute (no gravity, 1 m/s): no pair, no contact, no cast, so
// all of its time is what every step costs whatever the world holds.
void BM_StepOneBody(benchmark::State& state) {
  SceneDescription scene;
  BodyDescription sphere;
  sphere.shape = SceneShape::kSphere;
  sphere.radius = 0.5f;
  sphere.linear_velocity = Vec3(1, 0, 0);
  scene.gravity = Vec3::Zero();
  scene.bodies.push_back(sphere);
  StepWholeRun(state, scene, 60.0);
}
BENCHMARK(BM_StepOneBody)->ArgName("bullet")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_StepHeavyOnLight(benchmark::State& state) {
  StepWholeRun(state, accuracy::HeavyOnLightScene(100.0f), 5.0);
}
BENCHMARK(BM_StepHeavyOnLight)->ArgName("bullet")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace strata

BENCHMARK_MAIN();
