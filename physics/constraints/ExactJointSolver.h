// ExactJointSolver: solves the rows of a group's joints that always hold (anchor points, hinge axes, fixed
// rotations, rods) exactly, all at once, instead of one joint after another. Sequential passes move a load
// along a chain one link per pass and between a 100 kg ball and a 1 kg link a hundredth at a time, so a
// 100-link chain swung from 60 degrees stretched by 5 cm; the exact solve holds it within 0.1 mm. The
// rows' coupling matrix J M^-1 J^T is banded for chains and nearly so for trees (joints in the order they
// were made), so it is factored as a block skyline LDL^T (a joint's rows a block): rows couple only through a
// body they share. Built and factored once per pose version (the poses at a substep's start, those after its
// integration): the soft velocity passes scale the rigid solution (Box2D's mass and impulse scales, for all
// rows at once). The joints' limits, motors and springs are solved against those rows, each with the
// effective mass the rigid rows leave it. Allocated in a job's arena for one step; used by the one job that
// solves its group's joints.
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
  /// `pose_version` already (SolverPass::pose_version; -1 always builds). Returns whether it built them.
  bool Build(SolverBody* bodies, const SolverPose* poses, float elapsed, int pose_version);
  /// Whether it solves its joints' limits, drives and springs too (Constraint::FreeRowPasses), against the
  /// rigid rows; else the passes solve them against each joint's two bodies alone. It does unless the
  /// island's directions times its rigid rows and six numbers per body pass kMaxReducedEntries.
  bool solves_free_rows() const { return responses_ != nullptr; }
  /// After a Build: sets the joints up for `pass` and makes each direction their free rows act along
  /// (Constraint::FreeRows) an effective mass with the rigid rows holding, k = j M^-1 j^T - b^T A^-1 b
  /// (b: the rigid rows' coupling with the row), and the rigid rows' response to an impulse along it,
  /// A^-1 b: one solve of the factorization per direction.
  void ReduceFreeRows(SolverBody* bodies, const SolverPose* poses, const ConstraintPassContext& pass,
                      float elapsed);
  /// One Gauss-Seidel pass over the joints' free rows (when it solves them): each impulse moves the two
  /// bodies and, through the rigid rows' response, every body those rows hold, so the rigid rows stay as
  /// they were and the row gets what the island lets it have.
  void SolveFreeRows(SolverBody* bodies, const ConstraintPassContext& pass);
  /// The most numbers the free directions' responses may take (1 MiB of floats): their cost grows with
  /// directions times the island's size, so a larger island leaves its limits to the passes.
  static constexpr std::uint32_t kMaxReducedEntries = 1u << 18;
  /// One exact solve of the rows against the velocities now, with the drift bias in velocity passes
  /// (`pass.use_bias`). Soft in those passes (Box2D's mass and impulse scales), but rigid when it solves
  /// free rows (a joint has a limit, drive or spring): their effective masses assume the rigid rows hold, and
  /// a soft solve would hand a tenth of a limit's load back to the light body each pass (a flap on a welded
  /// block broke loose in 25 steps).
  void Solve(SolverBody* bodies, const ConstraintPassContext& pass);

  /// After the step's last substep: moves the bodies (poses and their motion since the step began, not
  /// their velocities) to take a fifth of the rows' position errors out, by the exact solve:
  /// integrating a link that turns fast moves its anchor off the circle it turns on (a whipping chain's
  /// end opened by centimetres), which velocity rows cannot see.
  void SolvePositions(SolverBody* bodies, SolverPose* poses, float elapsed, int pose_version);

  std::uint32_t row_count() const { return row_count_; }

 private:
  // A row as the passes read it, 4-wide (w = 0): its rate and its push on a body are a few SIMD operations,
  // and a joint's rows share their two bodies, so a pass reads and writes each body once per joint.
  struct alignas(16) Row {
    Vec4 linear;
    Vec4 angular_a;
    Vec4 angular_b;
    Vec4 push_a_linear;  // M^-1 J^T of each side: how an impulse of 1 changes its velocities
    Vec4 push_a_angular;
    Vec4 push_b_linear;
    Vec4 push_b_angular;
    float* impulse;
    float error;
    float fixed_rate;      // the rate the sides that take no impulse (a kinematic body) give the row
    std::uint32_t body_a;  // solver index, 0 when the side takes no impulse
    std::uint32_t body_b;
  };
  // The same row in double, for the coupling matrix: products of floats are exact in double, so an entry
  // is rounded once, when its terms are summed. By side (0 = A, 1 = B).
  struct alignas(16) CouplingRow {
    Eigen::Vector4d linear;
    Eigen::Vector4d angular[2];
    Eigen::Vector4d push_linear[2];
    Eigen::Vector4d push_angular[2];
  };
  // The row for `joint_row` of a joint whose sides are `body_a` and `body_b` (solver indices), seen as
  // `view`, and its double copy.
  static Row MakeRow(const ConstraintBodies& view, const JointRow& joint_row, std::uint32_t body_a,
                     std::uint32_t body_b);
  static void MakeCouplingRow(const Row& row, CouplingRow& coupling);
  // Writes the coupling of joint `block_i`'s rows with joint `block_j`'s (each named by its first row; j no
  // later than i) into the factorization's rows.
  void CoupleBlocks(std::uint32_t block_i, std::uint32_t block_j);
  static float Rate(const SolverBody* bodies, const Row& row);

  std::span<Constraint* const> joints_;
  Row* rows_ = nullptr;
  CouplingRow* coupling_rows_ = nullptr;
  std::uint32_t* first_ = nullptr;  // per row: the first row it couples with (its skyline's start)
  std::uint32_t* end_ = nullptr;    // per row: one past its joint's last row
  BlockSkylineLdlt ldlt_;           // J M^-1 J^T, factored a joint's rows at a time
  double* scratch_ = nullptr;       // right-hand side, then impulse changes
  // A direction a joint's free rows act along: its row, its effective mass with the rigid rows holding, and
  // the island bodies its impulse moves ([body_begin, body_end), by island number).
  struct FreeDirection {
    Row row;
    float effective_mass;
    std::uint32_t body_begin;
    std::uint32_t body_end;
  };
  // A body's velocity change per unit impulse along a direction: linear, then angular.
  static constexpr int kBodyResponseSize = 6;
  // The response of the rigid rows to an impulse of 1 along `free` (A^-1 b, into `response`) and of the
  // island's bodies (into `body_response`), and its effective mass; `local_a`/`local_b` number its bodies.
  FreeDirection Reduce(const Row& free, const CouplingRow& free_coupling, std::uint32_t local_a,
                       std::uint32_t local_b, float* response, float* body_response);
  // Adds `scale` times `row`'s pushes on its bodies (island numbers `local_a`, `local_b`) to body_scratch_.
  void AddPush(const Row& row, std::uint32_t local_a, std::uint32_t local_b, double scale);

  // When it solves the free rows: the island's moving bodies (`island_body_`: solver index by island
  // number; `local_body_`: each joint's two sides' numbers, kNoRow for a side that takes no impulse); per
  // joint its first direction (joint_count + 1 entries); the directions; and per direction the rigid rows'
  // impulses (row_count_) and the bodies' velocity changes (kBodyResponseSize per body) an impulse of 1
  // along it causes.
  std::uint32_t body_count_ = 0;
  std::uint32_t* island_body_ = nullptr;
  std::uint32_t* local_body_ = nullptr;
  std::uint32_t* free_begin_ = nullptr;
  FreeDirection* directions_ = nullptr;
  float* responses_ = nullptr;
  float* body_responses_ = nullptr;
  double* body_scratch_ = nullptr;
  double* coupling_ = nullptr;  // a free row's coupling with each rigid row
  std::uint32_t row_count_ = 0;
  int built_version_ = -1;  // the pose version the rows and factorization are of
};

}  // namespace strata
