// ExactJointSolver: solves the rows of a group's joints that always hold (anchor points, hinge axes, fixed
// rotations, rods) exactly, all at once, instead of one joint after another. Sequential passes move a load
// along a chain one link per pass and between a 100 kg ball and a 1 kg link a hundredth at a time, so a
// 100-link chain swung from 60 degrees stretched by 5 cm; the exact solve holds it within 0.1 mm. The
// rows' coupling matrix J M^-1 J^T is banded for chains and nearly so for trees (joints in the order they
// were made), so it is factored as a block skyline LDL^T (a joint's rows a block): rows couple only through a
// body they share. Built and factored once per pose version (the poses at a substep's start, those after its
// integration): the soft velocity passes scale the rigid solution (Box2D's mass and impulse scales, for all
// rows at once). Allocated in a job's arena for one step; used by the one job that solves its group's joints.
#pragma once

#include <cstdint>
#include <span>

#include "physics/constraints/BlockSkylineLdlt.h"
#include "physics/constraints/Constraint.h"
#include "physics/core/BlockArena.h"

namespace strata {

class ExactJointSolver {
 public:
  /// For `joints` (bound to this step's solver bodies). `first_row_of_body` is scratch by solver index,
  /// at least as long as the solver body array, every entry kNoRow; it is left so.
  static ExactJointSolver* Create(BlockArena& arena, std::span<Constraint* const> joints,
                                  std::uint32_t* first_row_of_body);
  static constexpr std::uint32_t kNoRow = ~0u;

  /// The rows from the poses now, the coupling matrix and its factorization, unless they were built at
  /// `pose_version` already (SolverPass::pose_version; -1 always builds).
  void Build(SolverBody* bodies, const SolverPose* poses, float elapsed, int pose_version);
  /// One exact solve of the rows against the velocities now: soft with the drift bias (`pass.use_bias`),
  /// else rigid.
  void Solve(SolverBody* bodies, const ConstraintPassContext& pass);

  /// After the step's last substep: moves the bodies (poses and their motion since the step began, not
  /// their velocities) to take a fifth of the rows' position errors out, by the exact solve:
  /// integrating a link that turns fast moves its anchor off the circle it turns on (a whipping chain's
  /// end opened by centimetres), which velocity rows cannot see.
  void SolvePositions(SolverBody* bodies, SolverPose* poses, float elapsed, int pose_version);

  std::uint32_t row_count() const { return row_count_; }

 private:
  struct Row {
    JointRow row;
    std::uint32_t body_a;  // solver index, 0 when the side takes no impulse
    std::uint32_t body_b;
    float fixed_rate;    // the rate the sides that take no impulse (a kinematic body) give the row
    Vec3 push_a_linear;  // M^-1 J^T of each side: how an impulse of 1 changes its velocities
    Vec3 push_a_angular;
    Vec3 push_b_linear;
    Vec3 push_b_angular;
  };
  // Writes the coupling of joint `block_i`'s rows with joint `block_j`'s (each named by its first row; j no
  // later than i) into the factorization's rows.
  void CoupleBlocks(std::uint32_t block_i, std::uint32_t block_j);
  float Rate(const SolverBody* bodies, const Row& row) const;

  std::span<Constraint* const> joints_;
  Row* rows_ = nullptr;
  std::uint32_t* first_ = nullptr;  // per row: the first row it couples with (its skyline's start)
  std::uint32_t* end_ = nullptr;    // per row: one past its joint's last row
  BlockSkylineLdlt ldlt_;           // J M^-1 J^T, factored a joint's rows at a time
  double* scratch_ = nullptr;       // right-hand side, then impulse changes
  std::uint32_t row_count_ = 0;
  int built_version_ = -1;  // the pose version the rows and factorization are of
};

}  // namespace strata
