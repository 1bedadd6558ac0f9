// StrictJson: what every JSON reader of Strata refuses beyond invalid JSON, and what it still reads.
#include "assets/json/StrictJson.h"

#include <gtest/gtest.h>

#include <string>

namespace strata::test {
namespace {

TEST(StrictJson, ReadsValidJsonAsNlohmannDoes) {
  const std::string text = R"({"a": [1, 2.5, "x", {"b": null}], "c": {"a": true}})";
  const Result<nlohmann::json> parsed = ParseStrictJson(text, "ok.json");
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(*parsed, nlohmann::json::parse(text)) << "the same key in different objects is fine";
}

TEST(StrictJson, RefusesDeepNestingDuplicateKeysAndHugeNumbers) {
  const std::string deep = std::string(65, '[') + std::string(65, ']');
  const std::string allowed = std::string(64, '[') + std::string(64, ']');
  EXPECT_TRUE(ParseStrictJson(allowed, "d.json").ok());
  const Result<nlohmann::json> too_deep = ParseStrictJson(deep, "d.json");
  ASSERT_FALSE(too_deep.ok());
  EXPECT_NE(too_deep.error().message.find("d.json: nests deeper than 64 levels (at byte 64)"),
            std::string::npos)
      << too_deep.error().message;
  EXPECT_TRUE(
      ParseStrictJson("[\"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[\"]", "s.json")
          .ok())
      << "brackets inside strings do not nest";
  const Result<nlohmann::json> twice = ParseStrictJson(R"({"x": {"k": 1, "k": 2}})", "t.json");
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.error().message.find("the key \"k\" appears twice"), std::string::npos)
      << twice.error().message;
  const Result<nlohmann::json> escaped = ParseStrictJson(R"({"k": 1, "\u006b": 2})", "e.json");
  EXPECT_FALSE(escaped.ok()) << "the same key spelled with an escape";
  EXPECT_FALSE(ParseStrictJson("[1e400]", "n.json").ok());
  EXPECT_FALSE(ParseStrictJson("{\"a\": ", "cut.json").ok());
}

TEST(StrictJson, EstimatesMemoryBeforeBuildingTheDocument) {
  std::string numbers = "[";
  for (int i = 0; i < 100000; ++i) numbers += "1,";
  numbers += "1]";
  const std::uint64_t estimate = EstimateJsonMemory(numbers);
  EXPECT_GE(estimate, 100000u * 16u) << "at least a json node per value";
  JsonLimits limits;
  limits.max_memory_bytes = estimate - 1;
  const Result<nlohmann::json> refused = ParseStrictJson(numbers, "big.json", limits);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("in memory"), std::string::npos) << refused.error().message;
  limits.max_memory_bytes = estimate;
  EXPECT_TRUE(ParseStrictJson(numbers, "big.json", limits).ok());
}

}  // namespace
}  // namespace strata::test
