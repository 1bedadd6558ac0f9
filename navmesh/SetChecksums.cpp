#include "navmesh/SetChecksums.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>

namespace strata::navmesh {

namespace {

constexpr std::uint32_t kMagic = 'S' << 24 | 'T' << 16 | 'C' << 8 | 'K';
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kVersionWithProfile = 2;
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

std::uint32_t HeaderCrc(std::span<const unsigned char> set_header, const SetCoverage& coverage,
                        const std::string& profile) {
  const std::int32_t words[6] = {coverage.shard,   coverage.shard_count, coverage.first.x,
                                 coverage.first.z, coverage.last.x,      coverage.last.z};
  const std::uint32_t crc =
      Crc32({reinterpret_cast<const unsigned char*>(words), sizeof(words)}, Crc32(set_header));
  return Crc32({reinterpret_cast<const unsigned char*>(profile.data()), profile.size()}, crc);
}

std::string EncodeSetChecksums(const SetChecksums& checksums) {
  std::string out;
  const SetCoverage& coverage = checksums.coverage;
  const bool named = !checksums.profile.empty();
  for (const std::uint32_t word :
       {kMagic, named ? kVersionWithProfile : kVersion,
        static_cast<std::uint32_t>(checksums.tile_crcs.size()), checksums.header_crc,
        static_cast<std::uint32_t>(coverage.shard), static_cast<std::uint32_t>(coverage.shard_count),
        static_cast<std::uint32_t>(coverage.first.x), static_cast<std::uint32_t>(coverage.first.z),
        static_cast<std::uint32_t>(coverage.last.x), static_cast<std::uint32_t>(coverage.last.z)})
    AppendWord(out, word);
  if (named) {
    // Its length, then its bytes padded with zeros to whole words.
    AppendWord(out, static_cast<std::uint32_t>(checksums.profile.size()));
    std::string padded = checksums.profile;
    padded.resize((padded.size() + 3) / 4 * 4, '\0');
    out += padded;
  }
  for (const std::uint32_t crc : checksums.tile_crcs) AppendWord(out, crc);
  return out;
}

namespace {

// A version 2 trailer's profile name from the words after the fixed ones; the words it takes, or 0 with
// `problem` set.
std::size_t DecodeProfile(std::span<const unsigned char> bytes, std::string& profile, std::string& problem) {
  if (bytes.size() < kFixedBytes + sizeof(std::uint32_t)) return 0;
  const std::uint32_t length = WordAt(bytes, kFixedWords);
  const std::size_t words = 1 + (length + 3) / 4;
  if (length == 0 || length > kMaxProfileNameBytes ||
      bytes.size() < kFixedBytes + words * sizeof(std::uint32_t)) {
    problem = "corrupt profile name in the checksum trailer";
    return 0;
  }
  profile.assign(reinterpret_cast<const char*>(bytes.data()) + kFixedBytes + sizeof(std::uint32_t), length);
  const auto allowed = [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; };
  if (!std::all_of(profile.begin(), profile.end(), allowed)) {
    problem = "corrupt profile name in the checksum trailer";
    return 0;
  }
  return words;
}

}  // namespace

std::optional<SetChecksums> DecodeSetChecksums(std::span<const unsigned char> bytes, std::size_t tile_count,
                                               std::string& problem) {
  const auto not_a_trailer = [&] {
    problem = "unexpected bytes after the last tile (not a checksum trailer for this many tiles)";
    return std::nullopt;
  };
  if (bytes.size() < kFixedBytes || WordAt(bytes, 0) != kMagic || WordAt(bytes, 2) != tile_count)
    return not_a_trailer();
  const std::uint32_t version = WordAt(bytes, 1);
  if (version != kVersion && version != kVersionWithProfile) return not_a_trailer();
  SetChecksums checksums;
  std::size_t profile_words = 0;
  if (version == kVersionWithProfile) {
    profile_words = DecodeProfile(bytes, checksums.profile, problem);
    if (profile_words == 0) return problem.empty() ? not_a_trailer() : std::nullopt;
  }
  const std::size_t first_crc = kFixedWords + profile_words;
  if (bytes.size() != (first_crc + tile_count) * sizeof(std::uint32_t)) return not_a_trailer();
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
  for (std::size_t i = 0; i < tile_count; ++i) checksums.tile_crcs.push_back(WordAt(bytes, first_crc + i));
  return checksums;
}

}  // namespace strata::navmesh
