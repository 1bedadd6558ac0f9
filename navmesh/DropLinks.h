// DropLinks: one-way links from the walkable edge of a ledge down to walkable ground below it, found in one
// tile's own Recast data, so an agent that may drop `agent_max_drop` metres finds paths a walker alone does
// not. Deterministic (the same tile gives the same links); a pure function, any thread.
#pragma once

#include <vector>

#include <Recast.h>

#include "navmesh/NavMeshSettings.h"
#include "physics/math/Math.h"

namespace strata::navmesh {

/// A drop from `top` (on a ledge's walkable edge) to `bottom` (on walkable ground), in the navmesh's frame.
struct DropLink {
  Vec3 top;
  Vec3 bottom;
};

/// At most this many links per tile: a tile of cliffs must not blow up its Detour data.
inline constexpr std::size_t kMaxDropLinksPerTile = 256;

/// The drops from the outer edges of `mesh`'s walkable polygons: from points along each edge (one per 2 m),
/// straight out across the ledge (no wall or step up on the way) and down more than a climb and at most
/// agent_max_drop, to ground that `compact` (this agent's eroded walkable cells) holds an agent's width
/// beyond the ledge. `solid` is the tile's rasterized geometry. None when agent_max_drop is 0.
std::vector<DropLink> FindDropLinks(const NavMeshSettings& settings, const rcPolyMesh& mesh,
                                    const rcHeightfield& solid, const rcCompactHeightfield& compact);

}  // namespace strata::navmesh
