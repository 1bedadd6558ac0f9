#include "tools/cli/Validators.h"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace strata::cli {

CLI::Validator FiniteIn(double min, double max) {
  std::ostringstream description;
  description << "FINITE in [" << min << " - " << max << "]";
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return "not a number: " + text;
        if (!std::isfinite(value)) return "must be a finite number, got " + text;
        if (value < min || value > max) {
          std::ostringstream out;
          out << "must be in [" << min << ", " << max << "], got " << text;
          return out.str();
        }
        return {};
      },
      description.str());
}

CLI::Validator CountIn(long min, long max, const std::string& what) {
  return CLI::Validator(
      [min, max, what](std::string& text) -> std::string {
        long value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return "not a whole number: " + text;
        if (value < min || value > max)
          return what + " must be from " + std::to_string(min) + " to " + std::to_string(max) + ", got " +
                 text;
        return {};
      },
      "INT in [" + std::to_string(min) + " - " + std::to_string(max) + "]");
}

Status DistinctFiles(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::filesystem::path> resolved;
  for (const auto& [option, path] : files) {
    std::error_code error;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, error);
    resolved.push_back(error ? std::filesystem::absolute(path, error) : canonical);
  }
  // Devices and pipes (/dev/null, /dev/stdout) may take several outputs: nothing is replaced there.
  const auto skipped = [&](std::size_t k) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(files[k].second, error);
    return files[k].second.empty() ||
           (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status));
  };
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (skipped(i)) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (skipped(j)) continue;
      std::error_code error;
      if (resolved[i] == resolved[j] || std::filesystem::equivalent(files[i].second, files[j].second, error))
        return MakeError(ErrorCode::kInvalidArgument, files[j].first + " and " + files[i].first +
                                                          " name the same file (" + files[i].second +
                                                          "): give each its own");
    }
  }
  return Status::Ok();
}

}  // namespace strata::cli
