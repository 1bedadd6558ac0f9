#include "assets/json/StrictJson.h"

#include <new>
#include <set>
#include <vector>

namespace strata {

namespace {

Error JsonError(const std::string& source, const std::string& why) {
  return MakeError(ErrorCode::kParseError, source + ": " + why);
}

// Per value a json node (16 bytes) and the array's or map's share of it; per key a map node and its string.
constexpr std::uint64_t kBytesPerValue = 32;
constexpr std::uint64_t kBytesPerKey = 96;

struct TextShape {
  std::size_t deepest = 0;
  std::size_t deepest_at = 0;  // byte offset where the nesting went past the limit, if it did
  std::uint64_t values = 1;
  std::uint64_t keys = 0;
  std::uint64_t string_bytes = 0;
};

// One pass over the text outside strings: how deep it nests, how many values and keys it has.
TextShape ShapeOf(std::string_view text, std::size_t max_depth) {
  TextShape shape;
  std::size_t depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      ++shape.string_bytes;
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    switch (c) {
      case '"':
        in_string = true;
        break;
      case '[':
      case '{':
        ++shape.values;
        if (++depth > shape.deepest) {
          shape.deepest = depth;
          if (depth == max_depth + 1) shape.deepest_at = i;
        }
        break;
      case ']':
      case '}':
        if (depth > 0) --depth;
        break;
      case ',':
        ++shape.values;
        break;
      case ':':
        ++shape.keys;
        break;
      default:
        break;
    }
  }
  return shape;
}

std::uint64_t Estimate(const TextShape& shape) {
  return shape.values * kBytesPerValue + shape.keys * kBytesPerKey + shape.string_bytes;
}

}  // namespace

std::uint64_t EstimateJsonMemory(std::string_view text) {
  return Estimate(ShapeOf(text, SIZE_MAX - 1));
}

Result<nlohmann::json> ParseStrictJson(std::string_view text, const std::string& source,
                                       const JsonLimits& limits) {
  const TextShape shape = ShapeOf(text, limits.max_depth);
  if (shape.deepest > limits.max_depth)
    return JsonError(source, "nests deeper than " + std::to_string(limits.max_depth) + " levels (at byte " +
                                 std::to_string(shape.deepest_at) + ")");
  const std::uint64_t estimate = Estimate(shape);
  if (estimate > limits.max_memory_bytes)
    return JsonError(source, "would take about " + std::to_string(estimate >> 20) +
                                 " MB in memory, more than the " +
                                 std::to_string(limits.max_memory_bytes >> 20) + " MB allowed for it");
  // Keys seen in each open object, innermost last; the first key given twice is the error.
  std::vector<std::set<std::string>> open_objects;
  std::string duplicate;
  const nlohmann::json::parser_callback_t callback = [&](int, nlohmann::json::parse_event_t event,
                                                         nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (event == Event::object_start) {
      open_objects.emplace_back();
    } else if (event == Event::object_end) {
      if (!open_objects.empty()) open_objects.pop_back();
    } else if (event == Event::key && !open_objects.empty() && duplicate.empty()) {
      if (!open_objects.back().insert(parsed.get<std::string>()).second)
        duplicate = parsed.get<std::string>();
    }
    return true;
  };
  try {
    nlohmann::json document = nlohmann::json::parse(text.begin(), text.end(), callback);
    if (!duplicate.empty())
      return JsonError(source, "the key \"" + duplicate + "\" appears twice in one object");
    return document;
  } catch (const nlohmann::json::exception& error) {
    // parse_error, and out_of_range for numbers beyond a double (1e400).
    return JsonError(source, std::string("invalid JSON: ") + error.what());
  } catch (const std::bad_alloc&) {
    return JsonError(source, "needs more memory than there is");
  }
}

}  // namespace strata
