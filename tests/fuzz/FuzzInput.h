// FuzzInput: what the fuzz targets share. Loaders read files, so an input is written to a file of this
// process's own (in the temporary directory) and the loader reads it back. One fuzzer per process, one
// thread: libFuzzer calls the target from its main thread.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace strata::fuzz {

/// Writes `data` to a per-process file named `stem` + `extension` and returns its path.
inline std::filesystem::path WriteInput(const std::uint8_t* data, std::size_t size, const std::string& stem,
                                        const std::string& extension) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     (stem + "_" + std::to_string(::getpid()) + extension);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace strata::fuzz
