// ExactContactSolver: one small island's contact rows solved together, exactly, instead of one row at a
// time: first all friction axes, then all normals. Gauss-Seidel passes move momentum through a stack one
// contact per pass, and between a heavy and a light body a thousandth at a time, so a tall tower sags and
// buckles and a 1000 kg box squeezes out the 1 kg box under it; solving each set's coupling matrix (a banded
// L D L^T factor of the rows that are not at a limit, those found by a few active-set rounds) lands where
// unlimited passes would. Two sets, one row per point and three friction rows per contact, cost much less
// than one set of three rows per point (the factorisation goes with the cube of the rows). Because the solve
// is exact, each contact's spring can be as stiff as the load it carries needs (see Create). Its contacts'
// points come without friction rows of their own (SetupSolverContact without point friction rows): it warm
// starts and solves friction per contact. One island per solver; ContactConstraintKind runs a solver on one
// thread at a time.
#pragma once

#include <cstdint>
#include <span>

#include "physics/constraints/ContactSolver.h"
#include "physics/constraints/SkylineLdlt.h"
#include "physics/core/BlockArena.h"

namespace strata {

/// The contact rows of one island and how they couple, for one step.
class ExactContactSolver {
 public:
  /// Islands with more contact points than this are left to the sequential passes.
  static constexpr std::uint32_t kMaxPoints = 128;

  /// Lays out the rows of `contacts` (set up for this step, warm impulses in place) in `arena`, ordered so
  /// that the coupling matrix is banded (reverse Cuthill-McKee over contacts that share a body), and
  /// computes it. `weight_per_impulse` (1 / (|g| substep)) turns a contact's warm impulse into the mass it
  /// carries; its spring is scaled to that mass, so every contact of a stack sags about as much as one box
  /// on the floor (g / omega^2). nullptr if there are no points or more than kMaxPoints.
  static ExactContactSolver* Create(BlockArena& arena, std::span<SolverContact* const> contacts,
                                    const SolverBody* bodies, float weight_per_impulse);

  /// Applies the contacts' accumulated impulses to the bodies (replacing WarmStartContact over the island's
  /// contacts, whose points have no friction rows of their own): each point's normal impulse, and each
  /// contact's friction impulses as its patch's.
  void WarmStart(SolverBody* bodies);

  /// One pass (replacing SolveContactVelocity over the island's contacts): in a velocity pass (`use_bias`)
  /// the friction impulses with which, all together, each contact holds still within the friction of its
  /// normal impulses so far; then, in every pass, the normal impulses with which, all together, no point
  /// sinks (softly with `use_bias`, rigidly in relax passes) and none pulls. `deepest` as in
  /// SolveContactVelocity.
  void Solve(SolverBody* bodies, const SubstepContext& context, bool use_bias, float* deepest);

 private:
  // A contact's friction as one patch (as PhysX has it): both friction axes at the centre of its points and a
  // twist about the normal. For points on one plane these three rows span what two rows per point span, so
  // the exact solve moves the bodies as per-point rows would, with at most three friction rows a contact
  // instead of eight: the factorisation, which goes with the cube of the rows, costs a fraction. The bounds
  // are the patch's: the tangent impulse within friction times the contact's normal impulse, the twist
  // within friction times each point's normal impulse times its distance from the centre.
  struct Patch {
    Vec4
        angular_a[3];  // the rows' angular parts on A: the centre's arm x each friction axis, then the normal
    Vec4 angular_b[3];
    Vec4 response_a[3];  // inverse inertia of A times angular_a
    Vec4 response_b[3];
    Vec4 turn[ContactManifold::kMaxPoints];    // normal x each point's offset from the centre (in the plane)
    float lever[ContactManifold::kMaxPoints];  // each offset's length (|turn|), for the twist's bound
    float spread;                              // the offsets' squared lengths summed; no twist row when ~0
    float accumulated[3];                      // the rows' impulses, gathered from the points' each pass
  };
  struct Row {
    SolverContact* contact;
    SolverContactPoint* point;  // a normal row's point
    Patch* patch;               // a friction row's patch
    const Vec4* direction;      // linear part (zero for the twist)
    const Vec4* angular[2];     // on A's side, on B's
    const Vec4* response[2];
    std::uint32_t body_a;  // 0 unless the solver moves that side
    std::uint32_t body_b;
    std::uint8_t axis;  // 0: the normal, 1 and 2: the friction axes, 3: the twist
    float load;         // the contact's spring scale: carried mass over its heavier body's mass, >= 1
  };
  // The free rows' block of (coupling + softness), factored, kept while the same rows are free with the same
  // softness.
  struct Factor {
    SkylineLdlt ldlt;               // over the free rows, packed in row order
    std::uint32_t* rows = nullptr;  // packed row -> row
    std::uint8_t* free = nullptr;   // what it was made of
    float* softness = nullptr;
    bool valid = false;
  };
  // The rows of one kind (the normals, or the friction axes) and how they couple. The coupling matrix is
  // kept by row, non-zero entries only (a row touches the rows of contacts that share a body with its own):
  // row i's entries are [neighbour_begin[i], neighbour_begin[i + 1]), coupling[k] the velocity change of
  // row i per unit impulse on row neighbours[k].
  struct RowSet {
    Row* rows = nullptr;
    std::uint32_t count = 0;
    std::uint32_t* neighbour_begin = nullptr;  // count + 1
    std::uint32_t* neighbours = nullptr;
    float* coupling = nullptr;  // filled by Couple when a pass first needs it
    float* diagonal = nullptr;  // each row's own entry: its inverse effective mass
    Factor factors[2];          // [use_bias] for the normals; friction (velocity passes only): [0]
    // What Couple reads: contact k's rows [row_begin[k], row_begin[k + 1]); its links (banded positions)
    // linked[linked_begin[k] ..], the e-th link's rows from link_offset[e] in each of k's neighbour lists.
    std::uint32_t contact_count = 0;
    const std::uint32_t* row_begin = nullptr;
    const std::uint32_t* link_offset = nullptr;
    const std::uint32_t* linked_begin = nullptr;
    const std::uint32_t* linked = nullptr;
    bool coupled = false;
  };
  // What Create orders and shares between the two sets.
  struct Layout;

  // A body two contacts both move: its inverse mass, the product of the side signs (-1 on A's side, +1 on
  // B's) and each contact's side (0: A, 1: B).
  struct SharedBody {
    float inverse_mass;
    float sign;
    std::uint8_t side_i, side_j;
  };
  static void MakePatch(const SolverContact& c, const SolverBody* bodies, Patch& patch);
  static void GatherPatch(const SolverContact& c, Patch& patch);
  static void SpreadPatch(SolverContact& c, const Patch& patch, int axis, float delta);
  // A row's impulse so far: its point's normal impulse, or its patch's along the row's axis.
  static float& Accumulated(const Row& row);
  static int SharedBodies(const Row& i, const Row& j, const SolverBody* bodies, SharedBody shared[2]);
  static void BuildRowSet(BlockArena& arena, const Layout& layout, const SolverBody* bodies, bool friction,
                          RowSet& set);
  // BuildRowSet's parts: the rows contact by contact (returns where each contact's rows begin), and each
  // row's neighbours.
  static std::uint32_t* LayOutRows(BlockArena& arena, const Layout& layout, const SolverBody* bodies,
                                   bool friction, RowSet& set);
  static void LinkRows(BlockArena& arena, const Layout& layout, const std::uint32_t* row_begin, RowSet& set);
  // The coupling entry of row i with a row of direction `direction_j` and responses `response_j` (by side)
  // through the bodies they share.
  static float Coupling(const Row& i, const Vec4& direction_j, const Vec4* const response_j[2],
                        const SharedBody shared[2], int shared_count);
  // Fills the set's coupling, once a step.
  static void Couple(RowSet& set, const SolverBody* bodies);
  static void AllocateFactor(BlockArena& arena, const RowSet& set, Factor& factor);
  bool Refactor(const RowSet& set, Factor& factor);
  void SolveWith(const Factor& factor, const double* right, double* out) const;
  double Residual(const RowSet& set, std::uint32_t row, const double* impulse) const;
  // Whether the pass's starting impulses already solve the set: no free row's residual above the tolerance
  // and no held row pulled off its limit (a resting contact's friction after its warm start). Then there is
  // nothing to factor.
  bool AtMinimum(RowSet& set, const SolverBody* bodies);
  // One round: move the free rows towards their minimum, stopping at the first limit hit (that row is then
  // held), or, at the minimum, free the held rows that would move off their limits. False when done.
  bool FreeRowsStep(const RowSet& set, Factor& factor);
  // The set's impulses, all together, against the bodies' velocities now; applies them. False if the active
  // set did not settle within its rounds.
  bool SolveRows(RowSet& set, SolverBody* bodies, const SubstepContext& context, bool use_bias,
                 float* lowest);
  // SolveRows' parts: each row's limits, softness, start and offset from the velocities now; the solved
  // impulses back into the contacts and the bodies' velocities.
  void LoadRows(const RowSet& set, const SolverBody* bodies, const SubstepContext& context, bool use_bias,
                float* lowest);
  void ApplyImpulses(const RowSet& set, SolverBody* bodies);

  std::span<SolverContact* const> contacts_;
  Patch* patches_ = nullptr;  // by contact
  RowSet normals_;
  RowSet friction_;
  // Scratch of one pass, as long as the longer set.
  double* offset_ = nullptr;   // velocity + bias, with the start impulses applied
  double* start_ = nullptr;    // the accumulated impulses the pass starts from
  double* right_ = nullptr;    // right-hand side of the free rows (for the change from start)
  double* impulse_ = nullptr;  // the pass's solution
  double* lower_ = nullptr;
  double* upper_ = nullptr;
  double* target_ = nullptr;  // the free rows' equality-constrained minimum
  double* scratch_ = nullptr;
  float* softness_ = nullptr;
  std::uint8_t* free_ = nullptr;
  std::uint32_t* packed_of_ = nullptr;
};

}  // namespace strata
