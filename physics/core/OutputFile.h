// OutputFile: how the tools write their result files. The bytes go to a temporary created exclusively beside
// the target (a fresh name each time, never following a link), are synced to disk and renamed over the
// target, so a failed or killed write never leaves half a file, or an empty one, where the old one was. A
// target that exists and is not a regular file (/dev/stdout, a pipe, a link to one) is written in place,
// never replaced. A write that fails (a full disk, /dev/full) is an error, never a silent short file.
// Temporaries left by a killed writer are removed by the next writer of the same target. Any thread, one
// writer per target at a time.
#pragma once

#include <filesystem>
#include <memory>
#include <ostream>
#include <string_view>

#include "physics/core/Result.h"

namespace strata {

class DescriptorBuffer;

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
  /// Writes what is buffered, checks every write succeeded, syncs and renames the temporary over the target.
  Status Commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::unique_ptr<DescriptorBuffer> buffer_;
  std::ostream stream_;
  bool committed_ = false;
  Status status_;
};

/// Writes `bytes` to `path` as above; an error names the path and what failed.
Status WriteOutputFile(const std::filesystem::path& path, std::string_view bytes);

}  // namespace strata
