// JsonReport: how the benchmark commands write their figures as JSON (`--json FILE`): the destination
// checked before minutes of measuring, the file written whole or not at all. Any thread.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "physics/core/Result.h"

namespace strata::bench {

/// Whether a file can be made at `path`: its folder exists (or it names none).
bool JsonDestinationExists(const std::string& path);
/// Writes `document` (indented) to `path` through WriteOutputFile.
Status WriteJsonReport(const std::string& path, const nlohmann::json& document);

}  // namespace strata::bench
