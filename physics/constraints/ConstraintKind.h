// ConstraintKind: one kind of constraint that the ConstraintSolver drives through a step: contacts
// (ContactConstraintKind) and joints (JointConstraintKind). The solver owns the solver bodies, the groups of
// islands, the rounds, gravity and integration; a kind lays its constraints of a group out in splits and runs
// the items of a split in each round. Threading: BeginStep and BeginGroups alone; PrepareGroup once per group
// from any job; Setup and Run from any job, the solver never handing two jobs at once items that move the
// same body (items of one parallel split, or the single item of a sequential split).
#pragma once

#include <cstdint>
#include <span>

#include "physics/PhysicsSettings.h"
#include "physics/body/SolverBody.h"
#include "physics/core/BlockArena.h"
#include "physics/solver/IslandBuilder.h"

namespace strata {

/// What every kind sees of a step's solve; the arrays stay owned by the caller of ConstraintSolver.
struct SolverStep {
  const IslandBuilder* islands = nullptr;
  SolverBody* bodies = nullptr;  ///< solver index = island body index + 1; 0 is the fixed body
  SolverPose* poses = nullptr;
  std::uint32_t solver_body_count = 0;
  float dt = 0.0f;          ///< the step
  float substep_dt = 0.0f;  ///< dt / substeps
  const PhysicsSettings* settings = nullptr;
};

/// A group of consecutive islands solved together by one schedule of rounds.
struct SolverGroup {
  std::uint32_t index = 0;
  std::uint32_t first_island = 0;
  std::uint32_t end_island = 0;
  /// Every island in it is solved exactly (each kind with constraints in it asked for that).
  bool exact = false;
  /// Every island in it holds constraints of one kind at most: no other kind's passes move the bodies of a
  /// kind's constraints here.
  bool one_kind_per_island = false;
};

/// How a kind laid out its constraints of one group.
struct GroupLayout {
  std::uint32_t splits = 0;  ///< splits it takes in every warm-start, velocity and relax round
  bool parallel = false;     ///< some split has more than one item: jobs share the group's rounds
  bool bounces = false;      ///< it needs the restitution rounds after the last substep
  bool positions = false;    ///< it needs the position rounds after the last substep
};

enum class SolverPassKind : std::uint8_t { kWarmStart, kVelocity, kRelax, kRestitution, kPositions };

/// One round's pass over one of a kind's splits.
struct SolverPass {
  SolverPassKind kind = SolverPassKind::kWarmStart;
  std::uint32_t split = 0;  ///< the kind's own split index
  int iteration = 0;
  int substep = 0;
  /// Seconds into the step of the poses the pass sees: a velocity pass sees its substep's start, a relax
  /// pass the poses after that substep's integration, a position pass the step's end.
  float elapsed = 0.0f;
  /// How many integrations the poses the pass sees have had this step: passes with the same count see the
  /// same poses (a substep's warm start and velocity passes; its relax passes and the next warm start).
  int pose_version = 0;
  bool reverse = false;          ///< visit the constraints backwards (alternates from pass to pass)
  bool last_solve_pass = false;  ///< the step's last velocity or relax pass
  bool keeps_impulses = false;   ///< the step's last pass that changes impulses: they warm-start the next
};

/// Base of the kinds of constraint the ConstraintSolver solves.
class ConstraintKind {
 public:
  virtual ~ConstraintKind() = default;

  /// Once a step, before the solver forms its groups.
  virtual void BeginStep(const SolverStep& step, std::uint32_t job_count) = 0;
  /// How much of its work lies in `island` (what group forming weighs); 0 if none.
  virtual std::uint32_t IslandWork(std::uint32_t island) const = 0;
  /// Whether it would solve `island` exactly; an island is exact when every kind with work in it says so,
  /// and exact islands share groups only with exact islands.
  virtual bool WantsExactIsland(std::uint32_t island) const = 0;
  /// Once the groups are formed (index order), before any PrepareGroup.
  virtual void BeginGroups(std::span<const SolverGroup> groups) = 0;
  /// Orders and splits its constraints of `group` (any job, once per group).
  virtual GroupLayout PrepareGroup(const SolverGroup& group, BlockArena& arena, std::uint32_t job) = 0;
  /// Items of the group's setup round (run before its first substep).
  virtual std::uint32_t SetupItems(std::uint32_t group) const = 0;
  virtual void Setup(std::uint32_t group, std::uint32_t begin, std::uint32_t end, BlockArena& arena) = 0;
  /// Items of one of its splits in `pass` (0: nothing to do in that round).
  virtual std::uint32_t Items(std::uint32_t group, const SolverPass& pass) const = 0;
  /// Runs items [begin, end) of `pass`.
  virtual void Run(std::uint32_t group, const SolverPass& pass, std::uint32_t begin, std::uint32_t end,
                   std::uint32_t job) = 0;
};

}  // namespace strata
