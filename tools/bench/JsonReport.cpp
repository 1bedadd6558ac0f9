#include "tools/bench/JsonReport.h"

#include <filesystem>

#include "physics/core/OutputFile.h"

namespace strata::bench {

bool JsonDestinationExists(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code error;
  return parent.empty() || std::filesystem::is_directory(parent, error);
}

Status WriteJsonReport(const std::string& path, const nlohmann::json& document) {
  return WriteOutputFile(path, document.dump(2) + "\n");
}

}  // namespace strata::bench
