// StrictJson: how every JSON file Strata reads is parsed (scenes, recordings, glTF headers). Beyond valid
// JSON: nesting at most max_depth deep (a deep array must not exhaust the stack of whoever walks it), no key
// twice in one object (which value was meant?), and the document's memory estimated from the text before it
// is built, so a large file is refused with a message instead of running the machine out of memory. Errors
// name the source and, where known, the byte. Pure functions; any thread.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "physics/core/Result.h"

namespace strata {

struct JsonLimits {
  std::size_t max_depth = 64;
  /// What the parsed document may take in memory (estimated: nlohmann's nodes and strings).
  std::uint64_t max_memory_bytes = std::uint64_t{1} << 30;
};

/// Parses `text` (from `source`, named in errors) under `limits`; kParseError for anything refused.
Result<nlohmann::json> ParseStrictJson(std::string_view text, const std::string& source,
                                       const JsonLimits& limits = {});

/// The memory ParseStrictJson estimates for `text`'s document (bytes): a node per value, a map entry per
/// key, the strings' characters.
std::uint64_t EstimateJsonMemory(std::string_view text);

}  // namespace strata
