// SetChecksums: the checksums Strata appends to a navmesh set file. RecastDemo reads a set header and its
// tiles and stops, so a trailer after the last tile keeps the file RecastDemo's; Strata's loader checks every
// tile (and the set header) against it, and loads a file without one (RecastDemo's own) unchecked.
// Pure functions; any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "navmesh/TileGrid.h"

namespace strata::navmesh {

/// Which share of a level's tiles a set file holds: share `shard` of `shard_count` of the tiles in the
/// rectangle first..last (world tile coordinates, inclusive), taken in coordinate order every shard_count-th
/// from the shard-th (LevelBakeOptions). shard_count 0: not known (a RecastDemo file, a partial merge).
struct SetCoverage {
  std::int32_t shard = 0;
  std::int32_t shard_count = 0;
  TileCoord first;
  TileCoord last;
  bool known() const { return shard_count > 0; }
  bool operator==(const SetCoverage&) const = default;
};

/// CRC-32 (IEEE 802.3, as zlib and PNG compute it) of `bytes`, continuing from `crc` (a CRC of earlier
/// bytes).
std::uint32_t Crc32(std::span<const unsigned char> bytes, std::uint32_t crc = 0);

/// The CRC of the set header's bytes, the coverage and the profile's name: what SetChecksums::header_crc
/// holds.
std::uint32_t HeaderCrc(std::span<const unsigned char> set_header, const SetCoverage& coverage,
                        const std::string& profile = {});

/// The most bytes of a profile name a trailer holds.
inline constexpr std::size_t kMaxProfileNameBytes = 64;

struct SetChecksums {
  std::uint32_t header_crc = 0;  ///< HeaderCrc
  SetCoverage coverage;
  std::string profile;                   ///< the agent profile the set was built for (empty: not named)
  std::vector<std::uint32_t> tile_crcs;  ///< over each tile's header and data, as saved
};

/// The trailer's bytes: magic, version, the tile count, the set header's CRC, the coverage, (version 2, when
/// the set names its profile) the profile's name, and one CRC per tile.
std::string EncodeSetChecksums(const SetChecksums& checksums);

/// Reads a trailer of exactly `bytes` for `tile_count` tiles; nullopt with `problem` set when the bytes are
/// not one (a file whose bytes after its last tile are anything else is damaged).
std::optional<SetChecksums> DecodeSetChecksums(std::span<const unsigned char> bytes, std::size_t tile_count,
                                               std::string& problem);

}  // namespace strata::navmesh
