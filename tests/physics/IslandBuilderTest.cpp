// The lock-free island builder against a plain sequential union-find: the same islands, each numbered by
// its lowest body, its bodies and constraints listed in ascending order, whether links come from one
// thread or several at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <thread>
#include <vector>

#include "physics/solver/IslandBuilder.h"

namespace strata::test {
namespace {

struct Edge {
  std::uint32_t a, b;
};

// A random contact graph: clusters of bodies joined inside, a few links between clusters, and loners.
std::vector<Edge> RandomGraph(std::uint32_t bodies, std::uint32_t edges, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::uint32_t> body(0, bodies - 1);
  std::vector<Edge> graph;
  for (std::uint32_t i = 0; i < edges; ++i) {
    const std::uint32_t a = body(random);
    const std::uint32_t span = (i % 17 == 0) ? bodies : 24;  // mostly local, sometimes far
    const std::uint32_t b =
        std::min<std::uint32_t>(bodies - 1, a + 1 + static_cast<std::uint32_t>(random() % span));
    if (a != b) graph.push_back({a, b});
  }
  return graph;
}

// The oracle: lowest body of each body's island.
std::vector<std::uint32_t> SequentialLowest(std::uint32_t bodies, const std::vector<Edge>& graph) {
  std::vector<std::uint32_t> parent(bodies);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x];
    return x;
  };
  for (const Edge& e : graph) {
    const std::uint32_t ra = find(e.a), rb = find(e.b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::vector<std::uint32_t> lowest(bodies);
  for (std::uint32_t i = 0; i < bodies; ++i) lowest[i] = find(i);
  return lowest;
}

// Checks Finalize's output against the oracle, with constraint k belonging to body graph[k].a.
void ExpectIslandsMatch(IslandBuilder& islands, const std::vector<Edge>& graph,
                        const std::vector<std::uint32_t>& lowest) {
  std::vector<std::uint32_t> constraint_body;
  for (const Edge& e : graph) constraint_body.push_back(e.a);
  islands.Finalize(constraint_body);
  const auto bodies = static_cast<std::uint32_t>(lowest.size());
  // Islands are numbered in order of their lowest body.
  std::vector<std::uint32_t> roots;
  for (std::uint32_t i = 0; i < bodies; ++i)
    if (lowest[i] == i) roots.push_back(i);
  ASSERT_EQ(islands.island_count(), roots.size());
  for (std::uint32_t island = 0; island < islands.island_count(); ++island) {
    const auto members = islands.bodies(island);
    ASSERT_FALSE(members.empty());
    EXPECT_EQ(members.front(), roots[island]);
    EXPECT_TRUE(std::is_sorted(members.begin(), members.end()));
    for (const std::uint32_t body : members) {
      EXPECT_EQ(lowest[body], roots[island]) << "body " << body;
      EXPECT_EQ(islands.island_of(body), island);
    }
    const auto constraints = islands.constraints(island);
    EXPECT_TRUE(std::is_sorted(constraints.begin(), constraints.end()));
    for (const std::uint32_t k : constraints)
      EXPECT_EQ(lowest[graph[k].a], roots[island]) << "constraint " << k;
  }
  std::size_t listed_bodies = 0, listed_constraints = 0;
  for (std::uint32_t island = 0; island < islands.island_count(); ++island) {
    listed_bodies += islands.bodies(island).size();
    listed_constraints += islands.constraints(island).size();
  }
  EXPECT_EQ(listed_bodies, bodies);
  EXPECT_EQ(listed_constraints, graph.size());
}

TEST(IslandBuilder, MatchesSequentialUnionFind) {
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    const std::uint32_t bodies = 3000;
    const std::vector<Edge> graph = RandomGraph(bodies, 2500, seed);
    IslandBuilder islands;
    islands.Reset(bodies);
    for (const Edge& e : graph) islands.Link(e.a, e.b);
    ExpectIslandsMatch(islands, graph, SequentialLowest(bodies, graph));
  }
}

TEST(IslandBuilder, ResetStartsOverAndLinkingTwiceChangesNothing) {
  IslandBuilder islands;
  islands.Reset(5);
  islands.Link(4, 3);
  islands.Link(3, 4);
  islands.Link(1, 0);
  EXPECT_EQ(islands.FindLowest(4), 3u);
  EXPECT_EQ(islands.FindLowest(1), 0u);
  islands.Reset(5);
  for (std::uint32_t i = 0; i < 5; ++i) EXPECT_EQ(islands.FindLowest(i), i);
  islands.Finalize({});
  EXPECT_EQ(islands.island_count(), 5u);
}

TEST(IslandBuilder, ChainLinkedHighToLowStaysShallow) {
  // The worst order for a naive union-find: each link hangs the chain one deeper. Links shorten paths as
  // they go, so the hops followed per link stay small on average.
  const std::uint32_t bodies = 10000;
  IslandBuilder islands;
  islands.Reset(bodies);
  std::uint64_t hops = 0;
  for (std::uint32_t i = bodies - 1; i > 0; --i) hops += islands.Link(i, i - 1);
  for (std::uint32_t i = 0; i < bodies; ++i) EXPECT_EQ(islands.FindLowest(i), 0u);
  EXPECT_LT(static_cast<double>(hops) / (bodies - 1), 4.0);
}

// Several threads link disjoint parts of one graph at once (as narrow-phase jobs do): the islands are the
// same as from one thread.
void ConcurrentLinks(int repeats) {
  const std::uint32_t bodies = 4000;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    const std::vector<Edge> graph = RandomGraph(bodies, 5000, 100u + static_cast<std::uint32_t>(repeat));
    IslandBuilder islands;
    islands.Reset(bodies);
    constexpr int kThreads = 4;
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        for (std::size_t k = static_cast<std::size_t>(t); k < graph.size(); k += kThreads)
          islands.Link(graph[k].a, graph[k].b);
      });
    for (std::thread& thread : threads) thread.join();
    ExpectIslandsMatch(islands, graph, SequentialLowest(bodies, graph));
  }
}

TEST(IslandBuilderThreads, ConcurrentLinksGiveTheSameIslands) {
  ConcurrentLinks(10);
}

TEST(IslandBuilderThreadsStress, ConcurrentLinksGiveTheSameIslandsHundredTimes) {
  ConcurrentLinks(100);
}

}  // namespace
}  // namespace strata::test
