// The exact solve of small resting islands (ExactContactSolver): which islands take it, that stacks and
// heavy-on-light pairs hold with it where the sequential passes let them sag or slide, that it keeps friction
// (a box held on a slope, a box sliding down one at the closed-form rate), that its per-contact friction
// warm starts as the points' own rows would, and that it is deterministic.
#include <cmath>
#include <new>

#include "TestWorld.h"
#include "physics/constraints/ContactSolver.h"
#include "physics/constraints/ExactContactSolver.h"

namespace strata::test {
namespace {

constexpr int kSecond = 60;

struct Stack {
  std::vector<BodyID> boxes;  // bottom to top
  Vec3 top_start;
};

// `count` unit boxes of `base_mass` kg, the top one `top_mass` kg, on a static floor.
Stack AddStack(PhysicsSystem& world, int count, float base_mass = 1.0f, float top_mass = 1.0f) {
  Add(world, Static(Box(20, 1, 20), Vec3(0, -1, 0)));
  Stack stack;
  for (int i = 0; i < count; ++i) {
    BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(0, 0.5f + static_cast<float>(i), 0));
    box.mass = i + 1 == count ? top_mass : base_mass;
    stack.boxes.push_back(Add(world, box));
  }
  stack.top_start = Position(world, stack.boxes.back());
  return stack;
}

PhysicsSettings Awake(bool exact) {
  PhysicsSettings settings;
  settings.allow_sleeping = false;  // the tests watch motion at rest
  settings.exact_small_islands = exact;
  return settings;
}

TEST(ExactSolve, RestingStacksAreSolvedDirectlyLoneBodiesAndTheSwitchedOffWorldAreNot) {
  for (const bool exact : {true, false}) {
    auto world = MakeWorld(Awake(exact));
    AddStack(*world, 3);
    Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(5, 0.5f, 0)));  // alone on the floor
    StepFor(*world, 30);
    EXPECT_EQ(world->last_step_stats().islands, 2u);
    EXPECT_EQ(world->last_step_stats().exact_islands, exact ? 1u : 0u);
  }
}

TEST(ExactSolve, ALonePairAtRestIsLeftToTheSequentialPasses) {
  PhysicsSettings settings = Awake(true);
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  // Two boxes touching face to face, at rest, with nothing else: one contact, no load to carry through.
  for (const float x : {0.0f, 1.0f}) Add(*world, Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(x, 0, 0)));
  StepFor(*world, 3);
  EXPECT_EQ(world->last_step_stats().islands, 1u);
  EXPECT_EQ(world->last_step_stats().exact_islands, 0u);
}

TEST(ExactSolve, MovingPilesAreLeftToTheSequentialPasses) {
  PhysicsSettings settings = Awake(true);
  settings.gravity = Vec3::Zero();
  auto world = MakeWorld(settings);
  // Two boxes in contact drifting together at 3 m/s: an island of two bodies, but not at rest.
  for (const float x : {0.0f, 1.0f}) {
    BodyCreationSettings box = Dynamic(Box(0.5f, 0.5f, 0.5f), Vec3(x, 0, 0));
    box.linear_velocity = Vec3(3, 0, 0);
    box.linear_damping = 0.0f;
    Add(*world, box);
  }
  StepFor(*world, 3);
  EXPECT_EQ(world->last_step_stats().islands, 1u);
  EXPECT_EQ(world->last_step_stats().exact_islands, 0u);
}

TEST(ExactSolve, ThirtyBoxTowerStandsWithinFourCentimetresAtSeveralStepsAndSubsteps) {
  for (const float dt : {1.0f / 30.0f, 1.0f / 60.0f})
    for (const int substeps : {2, 4}) {
      PhysicsSettings settings = Awake(true);
      settings.substeps = substeps;
      auto world = MakeWorld(settings);
      const Stack stack = AddStack(*world, 30);
      StepFor(*world, static_cast<int>(5.0f / dt), dt);
      const float moved = (Position(*world, stack.boxes.back()) - stack.top_start).norm();
      EXPECT_LT(moved, 0.04f) << "dt " << dt << " substeps " << substeps;
      EXPECT_EQ(world->last_step_stats().exact_islands, 1u);
    }
}

TEST(ExactSolve, HeavyBoxOnALightOneSinksLessThanAMillimetreUpToAThousandToOne) {
  for (const float ratio : {10.0f, 100.0f, 1000.0f})
    for (const int substeps : {1, 4}) {
      PhysicsSettings settings = Awake(true);
      settings.substeps = substeps;
      auto world = MakeWorld(settings);
      const Stack stack = AddStack(*world, 2, 1.0f, ratio);
      StepFor(*world, 5 * kSecond);
      const Vec3 heavy = Position(*world, stack.boxes.back());
      EXPECT_LT((heavy - stack.top_start).norm(), substeps == 1 ? 3e-3f : 1e-3f)
          << "1:" << ratio << " substeps " << substeps;
      EXPECT_GT(Position(*world, stack.boxes.front()).y(), 0.49f);  // the light box is not squeezed out
    }
}

// A 1000 kg slab (8 x 1 x 4 m) on a static floor, both with friction 1: what a small box rests on to make an
// island of two resting bodies.
void AddSlabOnFloor(PhysicsSystem& world) {
  BodyCreationSettings floor = Static(Box(20, 1, 20), Vec3(0, -1, 0));
  floor.friction = 1.0f;
  Add(world, floor);
  BodyCreationSettings slab = Dynamic(Box(4, 0.5f, 2), Vec3(0, 0.5f, 0));
  slab.mass = 1000.0f;
  slab.friction = 1.0f;
  Add(world, slab);
}

TEST(ExactSolve, FrictionHoldsABoxOnASlopeAndLetsOneSlideAtTheClosedFormRate) {
  // Gravity tilted by 20 degrees makes the floor a slope. A heavy slab holds fast on it (friction 1); a small
  // box rests on the slab: an island of two resting bodies. Pair friction is sqrt(a * b), so the small box's
  // own coefficient is the square of the pair's.
  const float angle = 20.0f * kPi / 180.0f;
  for (const float friction : {0.8f, 0.2f}) {
    PhysicsSettings settings = Awake(true);
    settings.gravity = 9.81f * Vec3(std::sin(angle), -std::cos(angle), 0);
    auto world = MakeWorld(settings);
    AddSlabOnFloor(*world);
    BodyCreationSettings box = Dynamic(Box(0.25f, 0.25f, 0.25f), Vec3(-2, 1.25f, 0));
    box.friction = friction * friction;
    box.linear_damping = 0.0f;
    const BodyID id = Add(*world, box);
    const Vec3 start = Position(*world, id);
    StepFor(*world, kSecond / 2);  // slow enough (< 1 m/s) to stay with the exact solve
    EXPECT_EQ(world->last_step_stats().exact_islands, 1u);
    const float travelled = (Position(*world, id) - start).norm();
    if (friction > std::tan(angle)) {
      EXPECT_LT(travelled, 0.005f);
    } else {
      // Down the slope at g (sin a - mu cos a) for half a second, from rest.
      const float expected = 0.5f * 9.81f * (std::sin(angle) - friction * std::cos(angle)) * 0.25f;
      EXPECT_NEAR(travelled, expected, 0.05f * expected);
    }
  }
}

TEST(ExactSolve, FrictionHoldsATwistBelowItsTorqueAndTurnsABoxAboveAtTheClosedFormRate) {
  // A 0.5 m box rests on a 1000 kg slab (an island of two resting bodies) and is twisted about the vertical.
  // Its four corners each carry a quarter of its weight at r = 0.25 sqrt 2 from the centre, so friction
  // resists up to mu m g r; above that it spins up at (torque - mu m g r) / I, I = m (0.5^2 + 0.5^2) / 12.
  const float mu = 0.5f, mass = 125.0f, arm = 0.25f * std::sqrt(2.0f);
  const float limit = mu * mass * 9.81f * arm, inertia = mass * 0.5f / 12.0f;
  for (const float factor : {0.5f, 2.0f}) {
    auto world = MakeWorld(Awake(true));
    AddSlabOnFloor(*world);
    BodyCreationSettings box = Dynamic(Box(0.25f, 0.25f, 0.25f), Vec3(0, 1.25f, 0));
    box.friction = mu * mu;  // the pair's is sqrt(a * b)
    box.mass = mass;
    box.angular_damping = 0.0f;
    const BodyID id = Add(*world, box);
    StepFor(*world, kSecond / 2);  // settled
    EXPECT_EQ(world->last_step_stats().exact_islands, 1u);
    const Quat start = *world->bodies().GetRotation(id);
    const int steps = kSecond / 2;
    for (int i = 0; i < steps; ++i) {
      ASSERT_TRUE(world->bodies().AddTorque(id, Vec3(0, factor * limit, 0)).ok());
      StepFor(*world, 1);
    }
    if (factor < 1.0f) {
      EXPECT_LT(start.angularDistance(*world->bodies().GetRotation(id)), 0.002f);
    } else {
      const float time = static_cast<float>(steps) / kSecond;
      const float expected = (factor - 1.0f) * limit / inertia * time;
      EXPECT_NEAR(world->bodies().GetAngularVelocity(id)->y(), expected, 0.02f * expected);
    }
  }
}

// A face-on-face contact between solver bodies `a` and `b` (0: the fixed body): four points on the plane
// through `centre` across `normal`, each with its own last-step impulses (times `load`).
ContactConstraint* FaceContact(BlockArena& arena, std::uint32_t a, std::uint32_t b, const Vec3& normal,
                               const Vec3& centre, const Vec3& centre_of_mass_a, const Vec3& centre_of_mass_b,
                               float load) {
  const Vec3 u = normal.unitOrthogonal(), v = normal.cross(u);
  auto* contact =
      new (arena.Allocate(ContactConstraint::Bytes(4), alignof(ContactConstraint))) ContactConstraint;
  *contact = {normal, a, b, 0.6f, 0.0f, nullptr, 4, a != 0, b != 0, false};
  const float corners[4][2] = {{0.5f, 0.4f}, {-0.5f, 0.4f}, {-0.5f, -0.4f}, {0.5f, -0.4f}};
  for (int k = 0; k < 4; ++k) {
    const Vec3 point = centre + corners[k][0] * u + corners[k][1] * v;
    ContactConstraintPoint& p = *new (&contact->points()[k]) ContactConstraintPoint;
    p.r_a = point - centre_of_mass_a;
    p.r_b = point - centre_of_mass_b;
    p.warm_normal = load * (1.0f + 0.7f * static_cast<float>(k));
    p.warm_friction =
        load * ((0.3f - 0.2f * static_cast<float>(k)) * u + (0.1f * static_cast<float>(k * k) - 0.2f) * v);
    p.separation = -0.001f;
    p.normal_velocity = 0.0f;
  }
  return contact;
}

TEST(ExactSolve, PatchWarmStartMovesTheBodiesAsThePointsOwnFrictionRowsWould) {
  // A tilted light box on the ground under a heavy box, both with inertia off their axes: the exact solve's
  // contacts carry no friction rows per point, and warm start their friction as one patch each.
  SolverBody bodies[3];
  const Vec3 lower(0.2f, 0.5f, -0.1f), upper(0.25f, 1.5f, -0.05f);
  const Mat3 turn = Quat(Eigen::AngleAxisf(0.4f, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  const Mat3 inverse_inertia[2] = {turn * Vec3(6, 4, 3).asDiagonal() * turn.transpose(),
                                   turn * Vec3(0.06f, 0.05f, 0.03f).asDiagonal() * turn.transpose()};
  for (int body = 1; body <= 2; ++body) {
    bodies[body].inverse_mass = body == 1 ? 1.0f : 0.01f;
    for (int column = 0; column < 3; ++column)
      bodies[body].inverse_inertia[column] = ToVec4(inverse_inertia[body - 1].col(column));
  }
  const Vec3 up = Vec3(0.1f, 1.0f, -0.05f).normalized();
  BlockArena arena;
  ContactConstraint* constraints[2] = {
      FaceContact(arena, 0, 1, up, Vec3(0.2f, 0.0f, -0.1f), Vec3::Zero(), lower, 3.0f),
      FaceContact(arena, 1, 2, up, Vec3(0.22f, 1.0f, -0.08f), lower, upper, 1.0f)};
  const SubstepContext context{MakeSoftSpring(30, 10, 1.0f / 240),
                               MakeSoftSpring(60, 10, 1.0f / 240),
                               240,
                               3,
                               0,
                               1,
                               1.0f / (9.81f / 240)};
  SolverBody per_point[3] = {bodies[0], bodies[1], bodies[2]};
  SolverContact* full[2];
  SolverContact* patched[2];
  for (int k = 0; k < 2; ++k) {
    full[k] = SetupSolverContact(arena, *constraints[k], per_point, context);
    WarmStartContact(*full[k], per_point);
    patched[k] = SetupSolverContact(arena, *constraints[k], bodies, context, false);
  }
  ExactContactSolver* solver = ExactContactSolver::Create(arena, patched, bodies, context.weight_per_impulse);
  ASSERT_NE(solver, nullptr);
  solver->WarmStart(bodies);
  for (int body = 1; body <= 2; ++body) {
    EXPECT_LT((bodies[body].linear_velocity - per_point[body].linear_velocity).norm(),
              1e-5f * per_point[body].linear_velocity.norm());
    EXPECT_LT((bodies[body].angular_velocity - per_point[body].angular_velocity).norm(),
              1e-4f * per_point[body].angular_velocity.norm());
  }
  // The rows left out are set up when a sequential pass needs them, as the full setup has them.
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(patched[k]->friction_rows_pending);
    SetupPendingFrictionRows(*patched[k], bodies);
    EXPECT_FALSE(patched[k]->friction_rows_pending);
    for (int i = 0; i < 4; ++i) {
      const SolverContactPoint &p = patched[k]->points()[i], &q = full[k]->points()[i];
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(p.angular_a[axis], q.angular_a[axis]);
        EXPECT_EQ(p.response_b[axis], q.response_b[axis]);
      }
      EXPECT_EQ(p.tangent_mass, q.tangent_mass);
      EXPECT_EQ(p.tangent_impulse[0], q.tangent_impulse[0]);
    }
  }
}

TEST(ExactSolve, SameInputsGiveTheSameTowerToTheBit) {
  std::vector<Vec3> tops;
  for (int run = 0; run < 2; ++run) {
    auto world = MakeWorld(Awake(true));
    const Stack stack = AddStack(*world, 12, 1.0f, 50.0f);
    StepFor(*world, 2 * kSecond);
    tops.push_back(Position(*world, stack.boxes.back()));
  }
  EXPECT_EQ(tops[0], tops[1]);
}

}  // namespace
}  // namespace strata::test
