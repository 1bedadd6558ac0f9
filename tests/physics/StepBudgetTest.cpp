// The step's memory budgets (PhysicsSystemConfig::max_body_pairs, max_contact_constraints), as Jolt has
// them: bodies spawned at one point (a common spawn bug) would want pairs for every two of them; the step
// takes its budget's worth, drops and counts the rest, warns once and goes on stepping.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "TestWorld.h"

namespace strata::test {
namespace {

struct PileWorld {
  std::unique_ptr<PhysicsSystem> world;
  std::vector<BodyID> bodies;
  std::vector<std::string> warnings;
};

// `count` spheres over a floor, at one point or (with `spacing`) in rows, in a world with the given budgets
// (0: the default).
std::unique_ptr<PileWorld> Pile(int count, std::size_t max_pairs, std::size_t max_constraints, int threads,
                                float spacing = 0.0f) {
  auto pile = std::make_unique<PileWorld>();
  PhysicsSystemConfig config;
  config.max_bodies = static_cast<std::uint32_t>(count + 1);
  config.thread_count = threads;
  config.max_body_pairs = max_pairs;
  config.max_contact_constraints = max_constraints;
  config.warning = [warnings = &pile->warnings](const std::string& message) { warnings->push_back(message); };
  pile->world = std::move(*PhysicsSystem::Create(config));
  Add(*pile->world, Static(Box(50, 0.5f, 50), Vec3(0, -0.5f, 0)));
  for (int i = 0; i < count; ++i) {
    const Vec3 position(spacing * static_cast<float>(i % 10), 5.0f, spacing * static_cast<float>(i / 10));
    pile->bodies.push_back(Add(*pile->world, Dynamic(Sphere(0.5f), position)));
  }
  return pile;
}

TEST(StepBudgetThreads, BodiesAtOnePointStepWithinTheBudgetAndWarnOnce) {
  constexpr int kBodies = 3000;  // 4.5 million pairs wanted
  constexpr std::size_t kMaxPairs = 20000, kMaxConstraints = 5000;
  for (const int threads : {1, 2}) {
    auto pile = Pile(kBodies, kMaxPairs, kMaxConstraints, threads);
    std::size_t most_pairs = 0, most_manifolds = 0, dropped = 0;
    for (int step = 0; step < 5; ++step) {
      ASSERT_TRUE(pile->world->Step(1.0f / 60.0f).ok());
      const StepStats& stats = pile->world->last_step_stats();
      most_pairs = std::max(most_pairs, stats.pairs);
      most_manifolds = std::max(most_manifolds, stats.manifolds);
      dropped += stats.pairs_dropped + stats.bodies_skipped;
    }
    EXPECT_LE(most_pairs, kMaxPairs) << threads << " threads";
    EXPECT_LE(most_manifolds, kMaxPairs) << "manifolds come from pairs taken";
    EXPECT_GT(dropped, 0u);
    ASSERT_EQ(pile->warnings.size(), 2u) << "one warning per budget, however many steps exceed it";
    EXPECT_NE(pile->warnings[0].find("PhysicsSystemConfig::max_body_pairs"), std::string::npos)
        << pile->warnings[0];
    EXPECT_NE(pile->warnings[1].find("PhysicsSystemConfig::max_contact_constraints"), std::string::npos)
        << pile->warnings[1];
    for (const BodyID id : pile->bodies) ASSERT_TRUE(IsFinite(Position(*pile->world, id)));
  }
}

TEST(StepBudget, AWorldWithinItsBudgetsDropsNothingAndSaysNothing) {
  auto pile = Pile(60, 0, 0, 1, /*spacing=*/1.05f);  // side by side; the default budgets, 16 per body slot
  for (int step = 0; step < 30; ++step) {
    ASSERT_TRUE(pile->world->Step(1.0f / 60.0f).ok());
    EXPECT_EQ(pile->world->last_step_stats().pairs_dropped, 0u);
    EXPECT_EQ(pile->world->last_step_stats().constraints_dropped, 0u);
  }
  EXPECT_TRUE(pile->warnings.empty());
}

TEST(StepBudget, AConstraintBudgetBelowThePairsDropsConstraintsOnly) {
  auto pile = Pile(400, 1000000, 100, 1);
  ASSERT_TRUE(pile->world->Step(1.0f / 60.0f).ok());
  const StepStats& stats = pile->world->last_step_stats();
  EXPECT_EQ(stats.pairs_dropped, 0u);
  EXPECT_GT(stats.constraints_dropped, 0u);
  ASSERT_EQ(pile->warnings.size(), 1u);
  EXPECT_NE(pile->warnings[0].find("contact constraints"), std::string::npos);
}

}  // namespace
}  // namespace strata::test
