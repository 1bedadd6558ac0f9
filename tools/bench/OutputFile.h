// OutputFile: how the tools write their result files. A regular file is written beside the target, flushed
// and renamed over it, so a failed or killed write never leaves half a file where the old one was; a
// target that exists and is not a regular file (/dev/stdout, a pipe) is written in place, never replaced.
// Any thread, one call per target at a time.
#pragma once

#include <filesystem>
#include <string_view>

#include "physics/core/Result.h"

namespace strata::bench {

/// Writes `bytes` to `path` as above; an error names the path and what failed.
Status WriteOutputFile(const std::filesystem::path& path, std::string_view bytes);

}  // namespace strata::bench
