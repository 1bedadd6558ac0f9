// A scratch path under the system temporary folder that no other test process shares: ctest runs each test
// in its own process, several at once, so a fixed name would let one test read or delete another's file.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace strata::test {

inline std::filesystem::path TempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("strata_" + std::to_string(::getpid()) + "_" + name);
}

}  // namespace strata::test
