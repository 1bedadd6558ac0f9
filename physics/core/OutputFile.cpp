#include "physics/core/OutputFile.h"

#include <cstdio>

namespace strata {

namespace {
Error OutputError(const std::filesystem::path& path, const std::string& why) {
  return {ErrorCode::kInvalidArgument, path.string() + ": " + why};
}
}  // namespace

OutputFile::OutputFile(std::filesystem::path path) : path_(std::move(path)) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path_, error);
  in_place_ = std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
  if (std::filesystem::is_directory(status)) {
    status_ = OutputError(path_, "is a directory");
    return;
  }
  written_ = in_place_ ? path_ : std::filesystem::path(path_.string() + ".tmp");
  stream_.open(written_, std::ios::binary | std::ios::trunc);
  if (!stream_) status_ = OutputError(path_, "cannot open for writing");
}

OutputFile::~OutputFile() {
  if (committed_ || in_place_ || written_.empty()) return;
  stream_.close();
  std::error_code error;
  std::filesystem::remove(written_, error);
}

Status OutputFile::Commit() {
  if (!status_) return status_;
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  stream_.close();
  if (!written || stream_.fail()) return status_ = OutputError(path_, "cannot write the file (disk full?)");
  committed_ = true;
  if (in_place_) return Status::Ok();
  if (std::rename(written_.c_str(), path_.c_str()) != 0) {
    std::error_code error;
    std::filesystem::remove(written_, error);
    return status_ = OutputError(path_, "cannot replace the file");
  }
  return Status::Ok();
}

Status WriteOutputFile(const std::filesystem::path& path, std::string_view bytes) {
  OutputFile file(path);
  if (!file.status()) return file.status();
  file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return file.Commit();
}

}  // namespace strata
