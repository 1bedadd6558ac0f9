// OutputFile: how the tools write their result files. A regular file is written beside the target, flushed
// and renamed over it, so a failed or killed write never leaves half a file where the old one was; a
// target that exists and is not a regular file (/dev/stdout, a pipe) is written in place, never replaced.
// A write that fails (a full disk, /dev/full) is an error, never a silent short file.
// Any thread, one writer per target at a time.
#pragma once

#include <filesystem>
#include <fstream>
#include <string_view>

#include "physics/core/Result.h"

namespace strata {

/// A result file written as it is produced (a long simulation's lines), replacing the target only on
/// Commit: until then the old file stays whole, and a writer dropped without Commit removes its temporary.
class OutputFile {
 public:
  /// Opens the temporary (or the device or pipe itself); check status() before writing.
  explicit OutputFile(std::filesystem::path path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// Whether the file could be opened; the error names the path.
  const Status& status() const { return status_; }
  std::ostream& stream() { return stream_; }
  /// Flushes, checks every write succeeded and renames the temporary over the target.
  Status Commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path written_;  // the temporary, or the target itself when written in place
  bool in_place_ = false;
  bool committed_ = false;
  std::ofstream stream_;
  Status status_;
};

/// Writes `bytes` to `path` as above; an error names the path and what failed.
Status WriteOutputFile(const std::filesystem::path& path, std::string_view bytes);

}  // namespace strata
