// JointConstraintKind: the step's joints (Constraint) as one kind of constraint of the ConstraintSolver. A
// group's joints are one sequential split, solved one joint at a time after the contacts in every warm-start,
// velocity and relax round, in alternating order; the rows that always hold of islands that need it (a
// heavy body on a light one) are solved exactly by a ExactJointSolver after each pass (with those joints'
// limits and drives solved against them), and after the last substep a position round removes part of the
// joints' drift. Threading as ConstraintKind.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "physics/constraints/Constraint.h"
#include "physics/constraints/ConstraintKind.h"
#include "physics/constraints/ExactJointSolver.h"

namespace strata {

class JointConstraintKind final : public ConstraintKind {
 public:
  /// The step's joints, bound to their solver bodies, and per joint the island body index of a side that
  /// moves; call before the solver's BeginStep.
  void SetJoints(std::span<Constraint* const> joints, std::span<const std::uint32_t> island_body) {
    input_joints_ = joints;
    input_island_body_ = island_body;
  }

  void BeginStep(const SolverStep& step, std::uint32_t job_count) override;
  std::uint32_t IslandWork(std::uint32_t island) const override;
  bool WantsExactIsland(std::uint32_t) const override { return false; }
  void BeginGroups(std::span<const SolverGroup> groups) override;
  GroupLayout PrepareGroup(const SolverGroup& group, BlockArena& arena, std::uint32_t job) override;
  std::uint32_t SetupItems(std::uint32_t) const override { return 0; }  // set up by Constraint::BeginStep
  void Setup(std::uint32_t, std::uint32_t, std::uint32_t, BlockArena&) override {}
  std::uint32_t Items(std::uint32_t group, const SolverPass& pass) const override;
  void Run(std::uint32_t group, const SolverPass& pass, std::uint32_t begin, std::uint32_t end,
           std::uint32_t job) override;

 private:
  // Who solves a joint's rows: the passes all of them; ExactJointSolver its rigid rows and the passes the
  // rest; or ExactJointSolver all of them (the passes only warm start it).
  static constexpr std::uint8_t kPassesSolve = 0, kExactRigidRows = 1, kExactOnly = 2;
  struct Group {
    Constraint* const* joints = nullptr;  // in island order
    std::uint32_t joint_count = 0;
    const std::uint8_t* exact = nullptr;  // per joint: kPassesSolve, kExactRigidRows or kExactOnly
    ExactJointSolver* exact_solver = nullptr;
    // The exact solve holds all the group's joints and nothing else moves their bodies within a substep's
    // passes: a velocity or relax pass after one of the same kind finds nothing left to do (see Run).
    bool exact_alone = false;
    // The substep and kind of the pass whose exact solve left the bodies as they are (-1: none since the
    // last warm start or build).
    int solved_substep = -1;
    SolverPassKind solved_kind = SolverPassKind::kWarmStart;
  };
  struct alignas(64) JobScratch {
    std::vector<std::uint32_t> first_row_of_body;  // ExactJointSolver scratch, by solver index
  };

  void SortJointsByIsland();
  // Whether a joint asks for its island's rigid rows to be solved exactly (see PhysicsSettings).
  bool NeedsExactSolve(const Constraint& joint) const;

  std::span<Constraint* const> input_joints_;
  std::span<const std::uint32_t> input_island_body_;
  SolverStep step_;
  SoftSpring rigid_spring_;                  // the rigid rows while they push drift out
  std::vector<std::uint32_t> island_begin_;  // by island, into joints_: its joints
  std::vector<Constraint*> joints_;          // every island's joints, island after island
  std::vector<std::uint8_t> exact_;          // by joints_ entry
  std::vector<Group> groups_;
  std::vector<JobScratch> jobs_;
};

}  // namespace strata
