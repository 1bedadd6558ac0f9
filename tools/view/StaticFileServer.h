// StaticFileServer: serves one folder's files over HTTP on 127.0.0.1, for `strata view --serve` (a browser
// may refuse scripts and files opened from disk, and a remote machine's folder is easier to look at through
// an SSH tunnel to a port). GET and HEAD of files directly in the folder; anything else is 404 or 405.
// Only the loopback address is bound: nothing off the machine reaches it. One thread serves; Serve blocks.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>

#include "physics/core/Result.h"

namespace strata::view {

struct ServeOptions {
  int port = 8080;  ///< 0: any free port
  /// Stop after this long (0: until the process is interrupted).
  std::chrono::milliseconds duration{0};
  /// Called once listening, with the port (the chosen one when `port` is 0).
  std::function<void(int port)> on_listening;
};

/// Serves `folder` until the duration passes or SIGINT/SIGTERM arrives. Fails when the port cannot be bound.
Status ServeFolder(const std::filesystem::path& folder, const ServeOptions& options);

}  // namespace strata::view
