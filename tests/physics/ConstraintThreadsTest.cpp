// Joints on many threads: chains solved exactly and by passes give the same bodies on a thread pool as on
// one thread, while another thread adds and removes joints (its calls wait for each step's end). Run under
// ThreadSanitizer by the tsan label.
#include <atomic>
#include <thread>

#include "TestWorld.h"
#include "physics/constraints/ConstraintManager.h"
#include "physics/core/ThreadPoolJobSystem.h"

namespace strata::test {
namespace {

struct ChainWorld {
  std::unique_ptr<PhysicsSystem> world;
  std::vector<BodyID> chain_bodies;
  BodyID loose_a;
  BodyID loose_b;
};

// Eight chains of ten links: the even ones end in a 20 kg ball (an exact solve), the odd ones in 1 kg, or in
// 20 kg too when `every_ball_heavy`.
ChainWorld MakeChains(std::shared_ptr<JobSystem> jobs, const PhysicsSettings& settings,
                      bool every_ball_heavy) {
  PhysicsSystemConfig config;
  config.job_system = std::move(jobs);
  ChainWorld made{std::move(*PhysicsSystem::Create(config, settings)), {}, {}, {}};
  PhysicsSystem& world = *made.world;
  Add(world, Static(Box(20.0f, 0.5f, 20.0f), Vec3(0.0f, -0.5f, 0.0f)));
  for (int c = 0; c < 8; ++c) {
    BodyID previous;
    for (int i = 0; i <= 10; ++i) {
      const bool ball = i == 10;
      BodyCreationSettings part = Dynamic(ball ? Sphere(0.2f) : Capsule(0.1f, 0.03f),
                                          Vec3(-8.0f + 2.0f * c + 0.2f * i + 0.1f, 4.0f, 0.0f),
                                          Quat(Eigen::AngleAxisf(0.5f * kPi, Vec3::UnitZ())));
      part.mass = ball && (c % 2 == 0 || every_ball_heavy) ? 20.0f : 1.0f;
      const BodyID id = Add(world, part);
      made.chain_bodies.push_back(id);
      PointJointSettings joint;
      joint.body_a = previous;
      joint.body_b = id;
      joint.anchor = Vec3(-8.0f + 2.0f * c + 0.2f * i, 4.0f, 0.0f);
      EXPECT_TRUE(world.constraints().Add(joint).ok());
      previous = id;
    }
  }
  made.loose_a = Add(world, Dynamic(Box(0.2f, 0.2f, 0.2f), Vec3(0.0f, 0.2f, 10.0f)));
  made.loose_b = Add(world, Dynamic(Box(0.2f, 0.2f, 0.2f), Vec3(1.0f, 0.2f, 10.0f)));
  return made;
}

std::vector<Vec3> FinalChainPositions(ChainWorld& made, bool churn_joints) {
  std::atomic<bool> stepping{true};
  std::atomic<int> churned{0};
  std::thread churner;
  if (churn_joints)
    churner = std::thread([&] {
      // Joins and parts the two loose boxes over and over: every call waits for the step in progress.
      DistanceJointSettings rod;
      rod.body_a = made.loose_a;
      rod.body_b = made.loose_b;
      rod.anchor_a = Vec3(0.2f, 0.2f, 10.0f);
      rod.anchor_b = Vec3(0.8f, 0.2f, 10.0f);
      while (stepping.load(std::memory_order_acquire) && churned.load() < 200) {
        const Result<ConstraintID> id = made.world->constraints().Add(rod);
        ASSERT_TRUE(id.ok());
        ASSERT_TRUE(made.world->constraints().GetForces(*id).ok());
        ASSERT_TRUE(made.world->constraints().Remove(*id).ok());
        churned.fetch_add(1);
      }
    });
  for (int step = 0; step < 120; ++step) EXPECT_TRUE(made.world->Step(1.0f / 60.0f).ok());
  stepping.store(false, std::memory_order_release);
  if (churner.joinable()) churner.join();
  EXPECT_EQ(made.world->constraints().count(), 88u);
  std::vector<Vec3> positions;
  for (const BodyID id : made.chain_bodies) positions.push_back(Position(*made.world, id));
  return positions;
}

TEST(ConstraintThreads, ChainsSolveTheSameOnAThreadPoolWhileJointsComeAndGo) {
  // At the default passes; and at one substep of 10 velocity and 2 relax passes with every chain solved
  // exactly, where the chains in the air skip their repeated passes.
  PhysicsSettings many_passes;
  many_passes.substeps = 1;
  many_passes.velocity_iterations = 10;
  many_passes.relax_iterations = 2;
  for (const bool exact_only : {false, true}) {
    const PhysicsSettings settings = exact_only ? many_passes : PhysicsSettings();
    ChainWorld serial = MakeChains(std::make_shared<SerialJobSystem>(), settings, exact_only);
    const std::vector<Vec3> expected = FinalChainPositions(serial, false);
    ChainWorld pooled = MakeChains(std::make_shared<ThreadPoolJobSystem>(3), settings, exact_only);
    const std::vector<Vec3> got = FinalChainPositions(pooled, true);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i)
      EXPECT_EQ(got[i], expected[i]) << "chain body " << i << (exact_only ? ", every chain exact" : "");
  }
}

}  // namespace
}  // namespace strata::test
