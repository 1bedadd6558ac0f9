// CliRunner: runs the `strata` executable the build made (STRATA_CLI) as a user would, for the CLI tests:
// its exit code, with standard output or standard error captured, and scratch files named per process.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/TempPath.h"

namespace strata::test {

inline const std::filesystem::path kScenes = STRATA_SCENES_DIR;
inline const std::filesystem::path kLevels = STRATA_LEVELS_DIR;

/// Runs the CLI with stdout captured into `output`.
inline int RunCliCapture(const std::string& arguments, std::string& output) {
  const std::filesystem::path captured = TempPath("cli_capture");
  const int status =
      std::system((std::string(STRATA_CLI) + " " + arguments + " > " + captured.string()).c_str());
  std::ifstream file(captured);
  output.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Runs the CLI with standard output discarded; `errors` gets what it wrote to standard error.
inline int RunCliErrors(const std::string& arguments, std::string& errors) {
  const std::filesystem::path captured = TempPath("cli_errors");
  const int status = std::system(
      (std::string(STRATA_CLI) + " " + arguments + " > /dev/null 2> " + captured.string()).c_str());
  std::ifstream file(captured);
  errors.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline int RunCli(const std::string& arguments) {
  const int status = std::system((std::string(STRATA_CLI) + " " + arguments + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream file(path);
  return nlohmann::json::parse(file);
}

}  // namespace strata::test
