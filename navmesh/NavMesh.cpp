// About 600 lines, on purpose: besides publishing and reading, a navmesh loads files, and every count, index
// and link of every tile is checked here before Detour sees a byte (Detour trusts its data); those checks
// read the file layout Save writes, so they stay beside it.
#include "navmesh/NavMesh.h"

#include <DetourAlloc.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <map>
#include <mutex>
#include <span>
#include <sstream>
#include <string>
#include <tuple>

#include "navmesh/SetChecksums.h"
#include "physics/core/InputFile.h"
#include "physics/core/OutputFile.h"

namespace strata::navmesh {

namespace {

// RecastDemo's tiled navmesh set file: a set header, then per tile a tile header and the tile's bytes.
constexpr std::int32_t kSetMagic = 'M' << 24 | 'S' << 16 | 'E' << 8 | 'T';
constexpr std::int32_t kSetVersion = 1;

struct SetHeader {
  std::int32_t magic;
  std::int32_t version;
  std::int32_t tile_count;
  dtNavMeshParams params;
};
struct SetTileHeader {
  dtTileRef ref;
  std::int32_t size;
};
static_assert(sizeof(SetHeader) == 40 && sizeof(SetTileHeader) == 8, "must match RecastDemo's layout");

// A navmesh set of the most tiles Detour's references allow, each of a large tile's size, is far below this.
constexpr std::uint64_t kMaxFileBytes = std::uint64_t{1} << 30;

std::span<const unsigned char> AsBytes(const std::string& bytes) {
  return {reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()};
}

Error FileError(const std::filesystem::path& path, const std::string& why) {
  return MakeError(ErrorCode::kParseError, path.string() + ": " + why);
}

/// Calls `function(const dtMeshTile&)` for every tile that holds data, in slot order (for sums and counts,
/// which that order cannot change).
template <class Function>
void ForEachTile(const dtNavMesh& mesh, Function&& function) {
  for (int i = 0; i < mesh.getMaxTiles(); ++i) {
    const dtMeshTile* tile = mesh.getTile(i);
    if (tile && tile->header && tile->dataSize > 0) function(*tile);
  }
}

/// Clears what Detour writes into a tile's data when it links the tile into a navmesh (the link array and
/// each polygon's first link), in `copy`, a copy of the tile's data.
void ClearRuntimeLinks(const dtMeshTile& tile, char* copy) {
  const auto offset = [&](const void* part) {
    return static_cast<std::size_t>(static_cast<const unsigned char*>(part) - tile.data);
  };
  std::memset(copy + offset(tile.links), 0,
              sizeof(dtLink) * static_cast<std::size_t>(tile.header->maxLinkCount));
  for (int i = 0; i < tile.header->polyCount; ++i) {
    const unsigned int no_link = DT_NULL_LINK;
    std::memcpy(copy + offset(&tile.polys[i].firstLink), &no_link, sizeof(no_link));
  }
}

constexpr int Align4(int bytes) {
  return (bytes + 3) & ~3;
}

/// The size dtCreateNavMeshData gives a tile with these counts.
long ExpectedTileSize(const dtMeshHeader& header) {
  const auto bytes = [](std::size_t element, int count) {
    return static_cast<long>(Align4(static_cast<int>(element) * count));
  };
  return bytes(sizeof(dtMeshHeader), 1) + bytes(sizeof(float) * 3, header.vertCount) +
         bytes(sizeof(dtPoly), header.polyCount) + bytes(sizeof(dtLink), header.maxLinkCount) +
         bytes(sizeof(dtPolyDetail), header.detailMeshCount) +
         bytes(sizeof(float) * 3, header.detailVertCount) + bytes(4, header.detailTriCount) +
         bytes(sizeof(dtBVNode), header.bvNodeCount) +
         bytes(sizeof(dtOffMeshConnection), header.offMeshConCount);
}

// `count` elements of T copied out of tile data at `cursor` (which need not be aligned for T), and the cursor
// moved past them as Detour lays them out (4-byte aligned).
template <class T>
std::vector<T> TakeArray(const unsigned char*& cursor, int count) {
  std::vector<T> out(static_cast<std::size_t>(count));
  if (!out.empty()) std::memcpy(out.data(), cursor, out.size() * sizeof(T));
  cursor += Align4(static_cast<int>(sizeof(T)) * count);
  return out;
}

bool Finite3(const float* v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// Whether point `v` lies in the box from `low` to `high` grown by `margin`.
bool Inside(const float* v, const float* low, const float* high, float margin) {
  for (int k = 0; k < 3; ++k)
    if (!(v[k] >= low[k] - margin && v[k] <= high[k] + margin)) return false;
  return true;
}

/// What is wrong with a tile's header, or nothing: counts in range and agreeing with the size, bounds finite
/// and in the grid cell the header names (a tile moved to another cell would answer paths there).
std::string HeaderProblem(const dtMeshHeader& header, std::size_t size, const dtNavMeshParams& params) {
  const int counts[] = {header.vertCount,       header.polyCount,       header.maxLinkCount,
                        header.detailMeshCount, header.detailVertCount, header.detailTriCount,
                        header.bvNodeCount,     header.offMeshConCount};
  for (const int count : counts)
    if (count < 0 || count > (1 << 24)) return "a count is out of range";
  if (ExpectedTileSize(header) != static_cast<long>(size)) return "its size does not match its counts";
  // Ground polygons first, then one two-point polygon per off-mesh link, which has no detail mesh.
  if (header.offMeshConCount > header.polyCount ||
      header.offMeshBase != header.polyCount - header.offMeshConCount ||
      2 * header.offMeshConCount > header.vertCount)
    return "its off-mesh link counts do not match its polygons";
  if (header.detailMeshCount != header.offMeshBase) return "detail meshes do not match polygons";
  if (!Finite3(header.bmin) || !Finite3(header.bmax) || !Inside(header.bmin, header.bmin, header.bmax, 0.0f))
    return "its bounds are not finite or inside out";
  // The bounds' centre in the header's grid cell (the bounds carry a border of a few cells on each side).
  const double centre[2] = {0.5 * (static_cast<double>(header.bmin[0]) + header.bmax[0]),
                            0.5 * (static_cast<double>(header.bmin[2]) + header.bmax[2])};
  const int cell[2] = {header.x, header.y};
  for (int k = 0; k < 2; ++k) {
    const double low =
        static_cast<double>(params.orig[2 * k]) + static_cast<double>(cell[k]) * params.tileWidth;
    if (!(centre[k] >= low && centre[k] <= low + params.tileWidth))
      return "it names grid cell (" + std::to_string(header.x) + ", " + std::to_string(header.y) +
             ") but its bounds lie elsewhere";
  }

  return {};
}

/// What is wrong with polygon `p`, or nothing: vertex and detail indices in range, ground only, neighbours
/// in the tile or through a side, detail triangles Detour can walk.
std::string PolygonProblem(std::size_t p, const dtPoly& poly, const dtPolyDetail& detail,
                           const unsigned char* detail_tris, const dtMeshHeader& header) {
  const std::string which = "polygon " + std::to_string(p);
  if (poly.vertCount < 3 || poly.vertCount > DT_VERTS_PER_POLYGON) return which + " has a bad vertex count";
  // Off-mesh links would index a table we never write.
  if (poly.getType() != DT_POLYTYPE_GROUND) return which + " is not a ground polygon";
  for (int v = 0; v < poly.vertCount; ++v) {
    if (poly.verts[v] >= header.vertCount) return which + " has a vertex index out of range";
    // 0: a border; 1..offMeshBase: a ground polygon of this tile; DT_EXT_LINK | side: a link out of the
    // tile through side 0, 2, 4 or 6 (another side makes Detour link the tile to itself in ways it cannot
    // read).
    const unsigned short neighbour = poly.neis[v];
    const bool inner = neighbour <= header.offMeshBase;
    const unsigned side = neighbour & 0xffu;
    const bool outer = neighbour == (DT_EXT_LINK | side) && side <= 6 && side % 2 == 0;
    if (!inner && !outer) return which + " has a neighbour that is neither in the tile nor a side of it";
  }
  if (static_cast<long>(detail.vertBase) + detail.vertCount > header.detailVertCount ||
      static_cast<long>(detail.triBase) + detail.triCount > header.detailTriCount)
    return which + " has detail ranges out of range";
  if (detail.triCount == 0) return which + " has no detail triangles";
  int boundary_edges = 0;
  for (int t = 0; t < detail.triCount; ++t) {
    const unsigned char* corners = detail_tris + (detail.triBase + t) * 4;
    // The fourth byte flags which of the triangle's edges lie on the polygon's outline (2 bits an edge,
    // only the low one used). Detour's nearest point falls back to those edges and reads through a null
    // pointer when a polygon has none (fuzz_navmesh found the flags of a triangle flipped): the outline
    // needs at least one flagged edge a polygon side.
    const unsigned char flags = corners[3];
    if ((flags & 0xC0u) != 0 || (flags & 0x2Au) != 0)
      return which + " has a detail triangle with bad edge flags";
    boundary_edges += (flags & 1u) + ((flags >> 2) & 1u) + ((flags >> 4) & 1u);
    for (int k = 0; k < 3; ++k)
      if (corners[k] >= poly.vertCount + detail.vertCount)
        return which + " has a detail triangle index out of range";
    // Three distinct corners: Detour's nearest-point search walks the edges between them and reads
    // through a null pointer when a polygon's triangles give it none (fuzz_navmesh found 0, 0, 0).
    if (corners[0] == corners[1] || corners[1] == corners[2] || corners[2] == corners[0])
      return which + " has a detail triangle with a repeated corner";
  }
  if (boundary_edges < poly.vertCount)
    return which + " has fewer outline edges in its detail mesh than sides";
  return {};
}

/// A neighbour inside the tile shares the edge and names the polygon back through it (checked once every
/// polygon's counts are known good): Detour's walks (raycasts, paths) follow these links, and a polygon that
/// is its own neighbour, or a one-way link, sends a raycast round in circles forever (fuzz_navmesh found
/// one).
std::string NeighbourProblem(const std::vector<dtPoly>& polys) {
  for (std::size_t p = 0; p < polys.size(); ++p) {
    const dtPoly& poly = polys[p];
    for (int v = 0; v < poly.vertCount; ++v) {
      const unsigned short neighbour = poly.neis[v];
      if (neighbour == 0 || (neighbour & DT_EXT_LINK)) continue;
      const std::size_t other = neighbour - 1u;
      const unsigned short from = poly.verts[v], to = poly.verts[(v + 1) % poly.vertCount];
      const dtPoly& back = polys[other];
      bool shared = false;
      for (int w = 0; w < back.vertCount && other != p && !shared; ++w)
        shared = back.verts[w] == to && back.verts[(w + 1) % back.vertCount] == from && back.neis[w] == p + 1;
      if (!shared)
        return "polygon " + std::to_string(p) + " names polygon " + std::to_string(other) +
               " as a neighbour it does not share an edge with";
    }
  }
  return {};
}

/// What is wrong with a tile's off-mesh links (drop links), or nothing: each a two-point polygon after the
/// ground ones, naming its polygon, with a finite radius no wider than a tile, a side Detour knows, and its
/// start in the tile (where it links to the ground).
std::string OffMeshLinkProblem(const std::vector<dtPoly>& polys,
                               const std::vector<dtOffMeshConnection>& links, const dtMeshHeader& header,
                               const dtNavMeshParams& params) {
  const float margin = 0.01f * params.tileWidth;
  for (std::size_t i = 0; i < links.size(); ++i) {
    const std::string which = "off-mesh link " + std::to_string(i);
    const dtPoly& poly = polys[static_cast<std::size_t>(header.offMeshBase) + i];
    if (poly.getType() != DT_POLYTYPE_OFFMESH_CONNECTION || poly.vertCount != 2 ||
        poly.verts[0] >= header.vertCount || poly.verts[1] >= header.vertCount)
      return which + " has a bad polygon";
    const dtOffMeshConnection& link = links[i];
    if (link.poly != header.offMeshBase + i) return which + " names another polygon";
    if (!std::isfinite(link.rad) || link.rad <= 0.0f || link.rad > params.tileWidth)
      return which + " has a bad radius";
    if (link.side != 0xff && link.side > 7) return which + " has a bad side";
    if (!Finite3(link.pos) || !Finite3(link.pos + 3) || !Inside(link.pos, header.bmin, header.bmax, margin))
      return which + " does not start in the tile";
  }
  return {};
}

/// What is wrong with a tile, or nothing: counts, indices and sizes must agree (so Detour never reads
/// outside the tile), bounds and vertices must be finite with every vertex inside the bounds, and the bounds
/// must lie in the grid cell the header names.
std::string TileProblem(std::span<const unsigned char> bytes, const dtNavMeshParams& params) {
  if (bytes.size() < sizeof(dtMeshHeader)) return "too short for a tile header";
  dtMeshHeader header;
  std::memcpy(&header, bytes.data(), sizeof(header));
  if (header.magic != DT_NAVMESH_MAGIC || header.version != DT_NAVMESH_VERSION)
    return "not a Detour tile (magic or version)";
  if (std::string problem = HeaderProblem(header, bytes.size(), params); !problem.empty()) return problem;
  const unsigned char* cursor = bytes.data() + Align4(sizeof(dtMeshHeader));
  const std::vector<float> verts = TakeArray<float>(cursor, 3 * header.vertCount);
  const std::vector<dtPoly> polys = TakeArray<dtPoly>(cursor, header.polyCount);
  cursor += Align4(static_cast<int>(sizeof(dtLink)) * header.maxLinkCount);
  const std::vector<dtPolyDetail> details = TakeArray<dtPolyDetail>(cursor, header.detailMeshCount);
  const std::vector<float> detail_verts = TakeArray<float>(cursor, 3 * header.detailVertCount);
  const unsigned char* detail_tris = cursor;
  cursor += Align4(4 * header.detailTriCount);
  const std::vector<dtBVNode> nodes = TakeArray<dtBVNode>(cursor, header.bvNodeCount);
  const std::vector<dtOffMeshConnection> links =
      TakeArray<dtOffMeshConnection>(cursor, header.offMeshConCount);

  // Vertices may sit a little outside the bounds (Recast rounds them to cells); a cell is far less than this.
  // A link's far end may lie in the next tile.
  const float margin = 0.01f * params.tileWidth;
  const std::size_t ground_verts = verts.size() / 3 - 2 * links.size();
  for (const std::vector<float>* list : {&verts, &detail_verts})
    for (std::size_t v = 0; v < list->size(); v += 3) {
      const bool link_end = list == &verts && v / 3 >= ground_verts;
      if (!Inside(&(*list)[v], header.bmin, header.bmax, link_end ? params.tileWidth : margin))
        return std::string(list == &verts ? "vertex " : "detail vertex ") + std::to_string(v / 3) +
               " is not finite or lies outside the tile";
    }
  const std::vector<dtPoly> ground(polys.begin(), polys.begin() + header.offMeshBase);
  for (std::size_t p = 0; p < ground.size(); ++p)
    if (std::string problem = PolygonProblem(p, ground[p], details[p], detail_tris, header); !problem.empty())
      return problem;
  if (std::string problem = NeighbourProblem(ground); !problem.empty()) return problem;
  for (const dtBVNode& node : nodes)
    if (node.i >= header.offMeshBase || node.i < -header.bvNodeCount)
      return "a bounding-volume node is out of range";
  return OffMeshLinkProblem(polys, links, header, params);
}

double PolygonArea(const dtMeshTile& tile, const dtPoly& poly) {
  double twice_area = 0.0;
  for (int i = 0; i < poly.vertCount; ++i) {
    const float* a = &tile.verts[poly.verts[i] * 3];
    const float* b = &tile.verts[poly.verts[(i + 1) % poly.vertCount] * 3];
    twice_area += static_cast<double>(a[0]) * b[2] - static_cast<double>(b[0]) * a[2];
  }
  return std::abs(twice_area) * 0.5;
}

}  // namespace

NavMesh::NavMesh(dtNavMesh* mesh, float tile_size, TileCoord origin_tile)
    : mesh_(mesh),
      tile_size_(tile_size),
      origin_tile_(origin_tile),
      origin_(static_cast<double>(origin_tile.x) * tile_size, 0.0,
              static_cast<double>(origin_tile.z) * tile_size) {}

Result<std::unique_ptr<NavMesh>> NavMesh::Create(float tile_size, int max_tiles, TileCoord origin_tile,
                                                 std::string profile) {
  if (profile.size() > kMaxProfileNameBytes)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh: a profile name is at most 64 bytes");
  if (!std::isfinite(tile_size) || tile_size <= 0.0f)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh: tile size must be a positive number");
  if (max_tiles < 1 || max_tiles > (1 << 16))
    return MakeError(ErrorCode::kInvalidArgument, "navmesh: max_tiles must be in [1, 65536]");
  const int tile_bits = std::bit_width(std::bit_ceil(static_cast<unsigned>(max_tiles))) - 1;
  dtNavMeshParams params{};
  params.tileWidth = tile_size;
  params.tileHeight = tile_size;
  params.maxTiles = 1 << tile_bits;
  params.maxPolys = 1 << (22 - tile_bits);
  dtNavMesh* mesh = dtAllocNavMesh();
  if (!mesh || dtStatusFailed(mesh->init(&params))) {
    dtFreeNavMesh(mesh);
    return MakeError(ErrorCode::kCapacityExceeded, "navmesh: Detour could not allocate the tile table");
  }
  std::unique_ptr<NavMesh> navmesh(new NavMesh(mesh, tile_size, origin_tile));
  navmesh->profile_ = std::move(profile);
  return navmesh;
}

NavMesh::~NavMesh() {
  dtFreeNavMesh(mesh_);
}

Status NavMesh::ReplaceTile(TileCoord tile, TileData data) {
  const std::unique_lock lock(mutex_);
  // Checked before the old tile goes: Detour itself would take the tile, and its polygons past the limit
  // would get references that spill into the tile bits (paths through the wrong tile).
  if (!data.empty()) {
    if (data.size() < static_cast<int>(sizeof(dtMeshHeader)))
      return MakeError(ErrorCode::kInvalidArgument, "navmesh: tile data shorter than its header");
    dtMeshHeader header;
    std::memcpy(&header, data.bytes().data(), sizeof(header));
    const int max_polygons = mesh_->getParams()->maxPolys;
    if (header.polyCount > max_polygons)
      return MakeError(ErrorCode::kCapacityExceeded,
                       "navmesh: tile (" + std::to_string(tile.x) + ", " + std::to_string(tile.z) + ") has " +
                           std::to_string(header.polyCount) + " polygons, more than the " +
                           std::to_string(max_polygons) + " a tile holds in a navmesh of " +
                           std::to_string(mesh_->getMaxTiles()) + " tiles (fewer tiles leave more bits)");
  }
  const TileCoord local = ToLocalTile(tile);
  if (const dtTileRef old = mesh_->getTileRefAt(local.x, local.z, 0)) {
    mesh_->removeTile(old, nullptr, nullptr);
    version_.fetch_add(1, std::memory_order_release);
  }
  if (data.empty()) return Status::Ok();
  version_.fetch_add(1, std::memory_order_release);
  const int size = data.size();
  unsigned char* bytes = data.Release();
  const dtStatus status = mesh_->addTile(bytes, size, DT_TILE_FREE_DATA, 0, nullptr);
  if (dtStatusFailed(status)) {
    dtFree(bytes);
    return MakeError(ErrorCode::kCapacityExceeded, "navmesh: Detour refused tile (" + std::to_string(tile.x) +
                                                       ", " + std::to_string(tile.z) +
                                                       ") (tile table full or polygon limit exceeded)");
  }
  return Status::Ok();
}

void NavMesh::RemoveTile(TileCoord tile) {
  (void)ReplaceTile(tile, TileData());
}

int NavMesh::tile_count() const {
  return Read([](const dtNavMesh& mesh) {
    int count = 0;
    ForEachTile(mesh, [&](const dtMeshTile&) { ++count; });
    return count;
  });
}

std::vector<TileCoord> NavMesh::Tiles() const {
  return Read([this](const dtNavMesh& mesh) {
    std::vector<TileCoord> tiles;
    ForEachTile(
        mesh, [&](const dtMeshTile& tile) { tiles.push_back(ToWorldTile(tile.header->x, tile.header->y)); });
    std::sort(tiles.begin(), tiles.end());
    return tiles;
  });
}

int NavMesh::polygon_count() const {
  return Read([](const dtNavMesh& mesh) {
    int count = 0;
    ForEachTile(mesh, [&](const dtMeshTile& tile) { count += tile.header->offMeshBase; });
    return count;
  });
}

int NavMesh::link_count() const {
  return Read([](const dtNavMesh& mesh) {
    int count = 0;
    ForEachTile(mesh, [&](const dtMeshTile& tile) { count += tile.header->offMeshConCount; });
    return count;
  });
}

double NavMesh::WalkableArea() const {
  return Read([](const dtNavMesh& mesh) {
    // Summed per tile in tile order, so the total does not depend on the order tiles were published in.
    std::map<TileCoord, double> per_tile;
    ForEachTile(mesh, [&](const dtMeshTile& tile) {
      double& area = per_tile[{tile.header->x, tile.header->y}];
      for (int i = 0; i < tile.header->polyCount; ++i) {
        const dtPoly& poly = tile.polys[i];
        if (poly.getType() == DT_POLYTYPE_GROUND) area += PolygonArea(tile, poly);
      }
    });
    double total = 0.0;
    for (const auto& [coord, area] : per_tile) total += area;
    return total;
  });
}

namespace {

/// Appends `tiles` as a set file holds them (each named by the reference it gets when the file is loaded into
/// a fresh navmesh, with its runtime links cleared: Detour rebuilds them when it adds the tile), with a CRC
/// of each.
void AppendTiles(const dtNavMesh& mesh, const std::vector<const dtMeshTile*>& tiles, std::string& bytes,
                 std::vector<std::uint32_t>& tile_crcs) {
  tile_crcs.reserve(tile_crcs.size() + tiles.size());
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const dtMeshTile& tile = *tiles[i];
    constexpr unsigned int kFreshSalt = 1;  // what dtNavMesh::init gives every tile slot
    const SetTileHeader tile_header{mesh.encodePolyId(kFreshSalt, static_cast<unsigned int>(i), 0),
                                    tile.dataSize};
    const std::size_t tile_start = bytes.size();
    bytes.append(reinterpret_cast<const char*>(&tile_header), sizeof(tile_header));
    bytes.append(reinterpret_cast<const char*>(tile.data), static_cast<std::size_t>(tile.dataSize));
    ClearRuntimeLinks(tile, bytes.data() + tile_start + sizeof(tile_header));
    tile_crcs.push_back(Crc32(AsBytes(bytes).subspan(tile_start)));
  }
}

}  // namespace

Status NavMesh::Save(const std::filesystem::path& path, std::optional<SetCoverage> coverage) const {
  std::string bytes;
  std::vector<std::uint32_t> tile_crcs;
  Read([&](const dtNavMesh& mesh) {
    // The same navmesh gives the same file whatever order its tiles were published in (worker threads race
    // for that): tiles go in coordinate order.
    const std::vector<const dtMeshTile*> tiles = TilesInOrder(mesh);
    SetHeader header{kSetMagic, kSetVersion, static_cast<std::int32_t>(tiles.size()), *mesh.getParams()};
    // Detour's own origin stays zero (it works relative to ours); the file records ours there.
    for (int k = 0; k < 3; ++k) header.params.orig[k] = static_cast<float>(origin_[k]);
    bytes.append(reinterpret_cast<const char*>(&header), sizeof(header));
    AppendTiles(mesh, tiles, bytes, tile_crcs);
  });
  const SetCoverage saved_coverage = coverage.value_or(coverage_);
  bytes += EncodeSetChecksums({HeaderCrc(AsBytes(bytes).first(sizeof(SetHeader)), saved_coverage, profile_),
                               saved_coverage, profile_, std::move(tile_crcs)});
  // Beside the target and renamed over it: a kill or a full disk never leaves half a navmesh there.
  return WriteOutputFile(path, bytes);
}

std::uint32_t NavMesh::TilesCrc() const {
  std::string bytes;
  std::vector<std::uint32_t> tile_crcs;
  Read([&](const dtNavMesh& mesh) { AppendTiles(mesh, TilesInOrder(mesh), bytes, tile_crcs); });
  return Crc32(AsBytes(bytes));
}

namespace {

// What is wrong with a set header, or nothing: counts Detour can hold (with room for the salt in a polygon
// reference) and an origin on a tile corner, whose tile (x, z) goes to `origin_tile`.
std::string SetHeaderProblem(const SetHeader& header, double (&origin_tile)[2]) {
  const dtNavMeshParams& params = header.params;
  if (header.tile_count < 0 || header.tile_count > params.maxTiles || params.maxTiles < 1 ||
      params.maxTiles > (1 << 16) || params.maxPolys < 1 || !std::isfinite(params.tileWidth) ||
      params.tileWidth <= 0.0f || params.tileWidth != params.tileHeight || !Finite3(params.orig))
    return std::string("corrupt navmesh set header");
  // A 32-bit polygon reference holds the tile, the polygon and at least 10 bits of salt. Detour computes
  // the salt's bits unsigned, so tables too large for that wrap instead of failing, and every reference
  // then decodes wrong (fuzz_navmesh: maxTiles 22,532 with 2^18 polygons read through a bad pointer).
  if (std::bit_width(std::bit_ceil(static_cast<unsigned>(params.maxTiles))) - 1 +
          std::bit_width(std::bit_ceil(static_cast<unsigned>(params.maxPolys))) - 1 >
      22)
    return std::string(
        "corrupt navmesh set header (its tile and polygon counts leave no room for the salt "
        "in a polygon reference)");
  // The origin is the lower corner of a tile (y = 0); Detour gets the rest relative to it.
  origin_tile[0] = std::round(params.orig[0] / static_cast<double>(params.tileWidth));
  origin_tile[1] = std::round(params.orig[2] / static_cast<double>(params.tileWidth));
  if (params.orig[1] != 0.0f || std::abs(origin_tile[0]) > (1 << 26) ||
      std::abs(origin_tile[1]) > (1 << 26) ||
      std::abs(origin_tile[0] * params.tileWidth - params.orig[0]) > 1e-3 * std::abs(params.orig[0]) + 1e-3 ||
      std::abs(origin_tile[1] * params.tileWidth - params.orig[2]) > 1e-3 * std::abs(params.orig[2]) + 1e-3)
    return std::string("corrupt navmesh set header (origin not on a tile corner)");
  return {};
}

}  // namespace

Result<std::unique_ptr<NavMesh>> NavMesh::Load(const std::filesystem::path& path) {
  Result<std::string> read = ReadInputFile(path, kMaxFileBytes);
  if (!read) return read.error();
  const std::span<const unsigned char> bytes(reinterpret_cast<const unsigned char*>(read->data()),
                                             read->size());
  if (bytes.size() < sizeof(SetHeader)) return FileError(path, "too short for a navmesh set header");
  SetHeader header;
  std::memcpy(&header, bytes.data(), sizeof(header));
  if (header.magic != kSetMagic) return FileError(path, "not a navmesh set (bad magic)");
  if (header.version != kSetVersion)
    return FileError(path, "unsupported navmesh set version " + std::to_string(header.version));
  double origin_tile[2] = {0.0, 0.0};
  if (const std::string problem = SetHeaderProblem(header, origin_tile); !problem.empty())
    return FileError(path, problem);
  const dtNavMeshParams& params = header.params;
  dtNavMeshParams local_params = params;
  std::fill(std::begin(local_params.orig), std::end(local_params.orig), 0.0f);
  dtNavMesh* mesh = dtAllocNavMesh();
  std::unique_ptr<NavMesh> navmesh(new NavMesh(
      mesh, params.tileWidth, {static_cast<int>(origin_tile[0]), static_cast<int>(origin_tile[1])}));
  if (!mesh || dtStatusFailed(mesh->init(&local_params)))
    return FileError(path, "Detour rejected the navmesh parameters");

  // Where each tile lies, then the checksums (when the file has them) before Detour sees a byte.
  std::size_t offset = sizeof(SetHeader);
  std::vector<std::size_t> tile_starts;
  for (int i = 0; i < header.tile_count; ++i) {
    SetTileHeader tile_header;
    if (bytes.size() - offset < sizeof(tile_header)) return FileError(path, "truncated (tile header)");
    std::memcpy(&tile_header, bytes.data() + offset, sizeof(tile_header));
    if (tile_header.ref == 0 || tile_header.size <= 0 ||
        static_cast<std::size_t>(tile_header.size) > bytes.size() - offset - sizeof(tile_header))
      return FileError(path, "truncated or corrupt tile " + std::to_string(i));
    tile_starts.push_back(offset);
    offset += sizeof(tile_header) + static_cast<std::size_t>(tile_header.size);
  }
  tile_starts.push_back(offset);
  if (offset != bytes.size()) {
    std::string problem;
    const std::optional<SetChecksums> checksums =
        DecodeSetChecksums(bytes.subspan(offset), tile_starts.size() - 1, problem);
    if (!checksums) return FileError(path, problem);
    if (HeaderCrc(bytes.first(sizeof(SetHeader)), checksums->coverage, checksums->profile) !=
        checksums->header_crc)
      return FileError(path, "the set header does not match its checksum (the file is damaged)");
    for (std::size_t i = 0; i + 1 < tile_starts.size(); ++i)
      if (Crc32(bytes.subspan(tile_starts[i], tile_starts[i + 1] - tile_starts[i])) !=
          checksums->tile_crcs[i])
        return FileError(path,
                         "tile " + std::to_string(i) + " does not match its checksum (the file is damaged)");
    navmesh->coverage_ = checksums->coverage;
    navmesh->profile_ = checksums->profile;
  }
  for (int i = 0; i < header.tile_count; ++i) {
    SetTileHeader tile_header;
    std::memcpy(&tile_header, bytes.data() + tile_starts[static_cast<std::size_t>(i)], sizeof(tile_header));
    const std::span<const unsigned char> tile_bytes(
        bytes.data() + tile_starts[static_cast<std::size_t>(i)] + sizeof(tile_header),
        static_cast<std::size_t>(tile_header.size));
    if (const std::string problem = TileProblem(tile_bytes, local_params); !problem.empty())
      return FileError(path, "corrupt tile " + std::to_string(i) + ": " + problem);
    TileData data = TileData::CopyOf(tile_bytes);
    unsigned char* raw = data.Release();
    if (dtStatusFailed(mesh->addTile(raw, tile_header.size, DT_TILE_FREE_DATA, tile_header.ref, nullptr))) {
      dtFree(raw);
      return FileError(path,
                       "tile " + std::to_string(i) + " was refused by Detour (duplicate or bad reference)");
    }
  }
  return navmesh;
}

Status NavMesh::WriteObj(const std::filesystem::path& path) const {
  std::ostringstream file;
  file << "# Strata navmesh: detail triangles of every walkable polygon\n";
  Read([&](const dtNavMesh& mesh) {
    int written = 0;
    for (const dtMeshTile* in_order : TilesInOrder(mesh)) {
      const dtMeshTile& tile = *in_order;
      for (int p = 0; p < tile.header->polyCount; ++p) {
        if (tile.polys[p].getType() != DT_POLYTYPE_GROUND) continue;
        for (int t = 0; t < tile.detailMeshes[p].triCount; ++t) {
          for (int k = 0; k < 3; ++k) {
            // In double and with 12 digits: a level 10,000 km out keeps its millimetres (a float there has
            // metres, and six digits would collapse it to one point).
            const Vec3d world = DetailTriangleCorner(tile, p, t, k).cast<double>() + origin_;
            char line[128];
            std::snprintf(line, sizeof(line), "v %.12g %.12g %.12g\n", world.x(), world.y(), world.z());
            file << line;
          }
          file << "f " << written + 1 << ' ' << written + 2 << ' ' << written + 3 << '\n';
          written += 3;
        }
      }
    }
  });
  return WriteOutputFile(path, file.str());
}

std::vector<const dtMeshTile*> TilesInOrder(const dtNavMesh& mesh) {
  std::vector<const dtMeshTile*> tiles;
  ForEachTile(mesh, [&](const dtMeshTile& tile) { tiles.push_back(&tile); });
  std::sort(tiles.begin(), tiles.end(), [](const dtMeshTile* a, const dtMeshTile* b) {
    return std::tuple(a->header->x, a->header->y, a->header->layer) <
           std::tuple(b->header->x, b->header->y, b->header->layer);
  });
  return tiles;
}

Vec3 DetailTriangleCorner(const dtMeshTile& tile, int poly, int triangle, int corner) {
  const dtPoly& polygon = tile.polys[poly];
  const dtPolyDetail& detail = tile.detailMeshes[poly];
  const unsigned char index =
      tile.detailTris[(detail.triBase + static_cast<unsigned>(triangle)) * 4 + corner];
  const float* v = index < polygon.vertCount
                       ? &tile.verts[polygon.verts[index] * 3]
                       : &tile.detailVerts[(detail.vertBase + index - polygon.vertCount) * 3];
  return {v[0], v[1], v[2]};
}

}  // namespace strata::navmesh
