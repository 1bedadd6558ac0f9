#include "navmesh/SetChecksums.h"

#include <array>
#include <cstring>

namespace strata::navmesh {

namespace {

constexpr std::uint32_t kMagic = 'S' << 24 | 'T' << 16 | 'C' << 8 | 'K';
constexpr std::uint32_t kVersion = 1;
// magic, version, tile count, header CRC, shard, shard count, first x/z, last x/z
constexpr std::size_t kFixedWords = 10;
constexpr std::size_t kFixedBytes = kFixedWords * sizeof(std::uint32_t);

constexpr std::array<std::uint32_t, 256> MakeCrcTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  return table;
}
constexpr std::array<std::uint32_t, 256> kCrcTable = MakeCrcTable();

void AppendWord(std::string& out, std::uint32_t word) {
  char bytes[sizeof(word)];
  std::memcpy(bytes, &word, sizeof(word));
  out.append(bytes, sizeof(bytes));
}

std::uint32_t WordAt(std::span<const unsigned char> bytes, std::size_t index) {
  std::uint32_t word = 0;
  std::memcpy(&word, bytes.data() + index * sizeof(word), sizeof(word));
  return word;
}

}  // namespace

std::uint32_t Crc32(std::span<const unsigned char> bytes, std::uint32_t crc) {
  crc ^= 0xFFFFFFFFu;
  for (const unsigned char byte : bytes) crc = kCrcTable[(crc ^ byte) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

std::uint32_t HeaderCrc(std::span<const unsigned char> set_header, const SetCoverage& coverage) {
  const std::int32_t words[6] = {coverage.shard,   coverage.shard_count, coverage.first.x,
                                 coverage.first.z, coverage.last.x,      coverage.last.z};
  return Crc32({reinterpret_cast<const unsigned char*>(words), sizeof(words)}, Crc32(set_header));
}

std::string EncodeSetChecksums(const SetChecksums& checksums) {
  std::string out;
  const SetCoverage& coverage = checksums.coverage;
  for (const std::uint32_t word :
       {kMagic, kVersion, static_cast<std::uint32_t>(checksums.tile_crcs.size()), checksums.header_crc,
        static_cast<std::uint32_t>(coverage.shard), static_cast<std::uint32_t>(coverage.shard_count),
        static_cast<std::uint32_t>(coverage.first.x), static_cast<std::uint32_t>(coverage.first.z),
        static_cast<std::uint32_t>(coverage.last.x), static_cast<std::uint32_t>(coverage.last.z)})
    AppendWord(out, word);
  for (const std::uint32_t crc : checksums.tile_crcs) AppendWord(out, crc);
  return out;
}

std::optional<SetChecksums> DecodeSetChecksums(std::span<const unsigned char> bytes, std::size_t tile_count,
                                               std::string& problem) {
  if (bytes.size() != kFixedBytes + tile_count * sizeof(std::uint32_t) || WordAt(bytes, 0) != kMagic ||
      WordAt(bytes, 1) != kVersion || WordAt(bytes, 2) != tile_count) {
    problem = "unexpected bytes after the last tile (not a checksum trailer for this many tiles)";
    return std::nullopt;
  }
  SetChecksums checksums;
  checksums.header_crc = WordAt(bytes, 3);
  const auto signed_word = [&](std::size_t index) { return static_cast<std::int32_t>(WordAt(bytes, index)); };
  SetCoverage& coverage = checksums.coverage;
  coverage = {
      signed_word(4), signed_word(5), {signed_word(6), signed_word(7)}, {signed_word(8), signed_word(9)}};
  if (coverage.shard_count < 0 || coverage.shard < 0 ||
      (coverage.known() && coverage.shard >= coverage.shard_count) || coverage.first.x > coverage.last.x ||
      coverage.first.z > coverage.last.z) {
    problem = "corrupt coverage in the checksum trailer";
    return std::nullopt;
  }
  for (std::size_t i = 0; i < tile_count; ++i) checksums.tile_crcs.push_back(WordAt(bytes, kFixedWords + i));
  return checksums;
}

}  // namespace strata::navmesh
