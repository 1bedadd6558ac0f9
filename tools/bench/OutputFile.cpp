#include "tools/bench/OutputFile.h"

#include <cstdio>
#include <fstream>

namespace strata::bench {

Status WriteOutputFile(const std::filesystem::path& path, std::string_view bytes) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  const bool in_place = std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
  const std::filesystem::path target = in_place ? path : std::filesystem::path(path.string() + ".tmp");
  {
    std::ofstream out(target, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      if (!in_place) std::filesystem::remove(target, error);
      return MakeError(ErrorCode::kInvalidArgument, path.string() + ": cannot write the file");
    }
  }
  if (!in_place && std::rename(target.c_str(), path.c_str()) != 0) {
    std::filesystem::remove(target, error);
    return MakeError(ErrorCode::kInvalidArgument, path.string() + ": cannot replace the file");
  }
  return Status::Ok();
}

}  // namespace strata::bench
