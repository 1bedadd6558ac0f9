// ContactOrdering: the order in which an island's contacts are solved exactly: contacts linked when they
// share a body the solver moves, then reverse Cuthill-McKee over those links, so a stack comes out end to
// end and its coupling matrix is banded (what SkylineLdlt factors cheaply). Pure functions over arena
// memory; one island, one thread.
#pragma once

#include <cstdint>
#include <span>

#include "physics/constraints/ContactSolver.h"
#include "physics/core/BlockArena.h"

namespace strata {

/// Each contact's links: itself and the contacts that share a body the solver moves with it, in increasing
/// order, as lists: links[begin[k] .. begin[k + 1]). Found through each body's contacts (a sort of (body,
/// contact) pairs), not by testing every pair of contacts.
void LinkContacts(BlockArena& arena, std::span<SolverContact* const> contacts, std::uint32_t*& begin,
                  std::uint32_t*& links);

/// Reverse Cuthill-McKee over the linked contacts into `order`, each component starting from a contact
/// with the fewest links; `degree` and `placed` are scratch of `count` entries.
void BandedOrder(std::uint32_t count, const std::uint32_t* begin, const std::uint32_t* links,
                 std::uint32_t* order, std::uint32_t* degree, std::uint8_t* placed);

}  // namespace strata
