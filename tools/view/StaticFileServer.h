// StaticFileServer: serves one folder's files over HTTP on 127.0.0.1, for `strata view --serve` (a browser
// may refuse scripts and files opened from disk, and a remote machine's folder is easier to look at through
// an SSH tunnel to a port). GET and HEAD of regular files directly in the folder (never through a link);
// anything else is 404 or 405. Only the loopback address is bound: nothing off the machine reaches it.
// cpp-httplib serves; up to kConnections connections at once, each on its own worker, and a client silent for
// kClientTimeout (reading its request or taking our reply) is dropped, so slow or stalled clients cannot hold
// up the others. Serve blocks its caller.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>

#include "physics/core/Result.h"

namespace strata::view {

struct ServeOptions {
  static constexpr int kConnections = 256;
  static constexpr std::chrono::seconds kClientTimeout{1};
  int port = 8080;  ///< 0: any free port
  /// Stop after this long (0: until the process is interrupted).
  std::chrono::milliseconds duration{0};
  /// Called once listening, with the port (the chosen one when `port` is 0).
  std::function<void(int port)> on_listening;
};

/// Serves `folder` until the duration passes or SIGINT/SIGTERM arrives. Fails when the port cannot be bound.
Status ServeFolder(const std::filesystem::path& folder, const ServeOptions& options);

}  // namespace strata::view
