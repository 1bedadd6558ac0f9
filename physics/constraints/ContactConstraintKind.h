// ContactConstraintKind: the step's contacts as one kind of constraint of the ConstraintSolver. A group's
// contacts are split (LargeIslandSplitter) so that no two in one parallel split move the same body: a
// parallel split is solved a register of lanes at a time (ContactBundle), the sequential split one contact at
// a time (ContactSolver), and small resting islands exactly (ExactContactSolver). Contacts warm-start, solve
// soft in velocity passes and rigid in relax passes, bounce in the restitution rounds, and leave their
// impulses in the body-pair cache for the next step. Threading as ConstraintKind.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "physics/constraints/ConstraintKind.h"
#include "physics/constraints/ContactBundle.h"
#include "physics/constraints/ContactConstraint.h"
#include "physics/constraints/ContactSolver.h"
#include "physics/constraints/ExactContactSolver.h"
#include "physics/solver/LargeIslandSplitter.h"

namespace strata {

class ContactConstraintKind final : public ConstraintKind {
 public:
  /// Small islands are solved exactly (with PhysicsSettings::exact_small_islands) when they have at least
  /// two bodies, at most this many contact points per body...
  static constexpr std::uint32_t kExactMaxPointsPerBody = 8;
  /// ...and every body moves and turns slower than this (m/s, rad/s) when the step begins.
  static constexpr float kExactRestSpeed = 1.0f;

  /// The step's contacts, indexed as in IslandBuilder::Finalize; call before the solver's BeginStep.
  void SetContacts(std::span<ContactConstraint* const> contacts) { contacts_ = contacts; }

  void BeginStep(const SolverStep& step, std::uint32_t job_count) override;
  std::uint32_t IslandWork(std::uint32_t island) const override;
  bool WantsExactIsland(std::uint32_t island) const override;
  void BeginGroups(std::span<const SolverGroup> groups) override;
  GroupLayout PrepareGroup(const SolverGroup& group, BlockArena& arena, std::uint32_t job) override;
  std::uint32_t SetupItems(std::uint32_t group) const override;
  void Setup(std::uint32_t group, std::uint32_t begin, std::uint32_t end, BlockArena& arena) override;
  std::uint32_t Items(std::uint32_t group, const SolverPass& pass) const override;
  void Run(std::uint32_t group, const SolverPass& pass, std::uint32_t begin, std::uint32_t end,
           std::uint32_t job) override;

  /// Deepest penetration the step's last pass saw (m, <= 0), once the solve is done.
  float deepest_penetration() const;
  /// Parallel and sequential splits of the most split group (0 if none), for profiles.
  std::uint32_t max_split_count() const;

 private:
  struct Group {
    std::uint32_t first_island = 0;
    std::uint32_t end_island = 0;
    std::uint32_t first_contact = 0;  // offset in ordered_
    IslandSplits splits;
    ContactBundle** bundles = nullptr;  // the parallel splits' bundles, split after split
    std::uint32_t bundle_begin[IslandSplits::kMaxSplits + 1] = {};
    std::uint32_t bundle_count = 0;
    ContactConstraint* const* sequential = nullptr;  // the sequential split's contacts
    SolverContact** sequential_contacts = nullptr;   // ...as set up in the setup round
    std::uint32_t sequential_count = 0;
    bool exact = false;  // small islands only, each solved by its own ExactContactSolver
    ExactContactSolver** exact_solvers = nullptr;  // one per island, set up in the setup round
  };
  struct alignas(64) JobScratch {
    std::vector<std::uint8_t> split_of;
    std::vector<ContactConstraint*> scratch;
    float deepest = 0.0f;
  };

  bool IsSequential(const Group& group, std::uint32_t split) const {
    return group.splits.last_is_sequential && split + 1 == group.splits.split_count;
  }
  void SetupExactSolvers(Group& group, BlockArena& arena);
  void RunSequential(Group& group, const SolverPass& pass, float* deepest);
  void RunBundles(Group& group, const SolverPass& pass, std::uint32_t begin, std::uint32_t end,
                  float* deepest);

  std::span<ContactConstraint* const> contacts_;
  SolverStep step_;
  SubstepContext context_{};  // elapsed set per pass
  // What context_'s springs and rates were worked out from (NaN at first, so the first step computes them).
  struct RateInputs {
    float substep = std::numeric_limits<float>::quiet_NaN();
    float contact_hertz = 0.0f;
    float contact_damping_ratio = 0.0f;
    Vec3 gravity = Vec3::Zero();
    bool operator==(const RateInputs& other) const {
      return substep == other.substep && contact_hertz == other.contact_hertz &&
             contact_damping_ratio == other.contact_damping_ratio && gravity == other.gravity;
    }
  };
  RateInputs rate_inputs_;
  std::vector<ContactConstraint*> ordered_;  // every group's contacts, island after island
  std::vector<std::uint32_t> body_masks_;    // LargeIslandSplitter scratch, by solver body
  std::vector<Group> groups_;
  std::vector<JobScratch> jobs_;
};

}  // namespace strata
