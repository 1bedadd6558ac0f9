#include "tools/view/StaticFileServer.h"

#include <httplib.h>
#include <sys/stat.h>

#include <atomic>
#include <csignal>
#include <string>
#include <thread>

#include "physics/core/InputFile.h"

namespace strata::view {

namespace {

std::atomic<bool> g_stop_requested{false};

extern "C" void RequestStop(int) {
  g_stop_requested.store(true);
}

// The viewer's folder holds its page, its script, the scene and the recording's data: far below this.
constexpr std::uint64_t kMaxServedBytes = std::uint64_t{1} << 30;

const char* ContentType(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  if (extension == ".html") return "text/html; charset=utf-8";
  if (extension == ".js") return "text/javascript; charset=utf-8";
  if (extension == ".glb") return "model/gltf-binary";
  if (extension == ".json") return "application/json";
  if (extension == ".png") return "image/png";
  return "application/octet-stream";
}

// The file a request names, if it is a regular file directly in the folder and not a link (a link could
// lead anywhere, /etc/passwd included).
std::filesystem::path Resolve(const std::filesystem::path& folder, std::string name) {
  if (name.empty()) name = "index.html";
  if (name.find_first_of("/\\%") != std::string::npos || name == "." || name == "..") return {};
  const std::filesystem::path path = folder / name;
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return {};
  return path;
}

void Serve(const std::filesystem::path& folder, const httplib::Request& request,
           httplib::Response& response) {
  const std::filesystem::path path = Resolve(folder, request.matches[1].str());
  response.set_header("Cache-Control", "no-store");
  if (path.empty()) {
    response.status = 404;
    response.set_content("not found\n", "text/plain");
    return;
  }
  // ReadInputFile opens without following a link swapped in since Resolve, and re-checks the type.
  Result<std::string> bytes = ReadInputFile(path, kMaxServedBytes);
  if (!bytes) {
    response.status = 404;
    response.set_content("not found\n", "text/plain");
    return;
  }
  response.set_content(std::move(*bytes), ContentType(path));
}

}  // namespace

Status ServeFolder(const std::filesystem::path& folder, const ServeOptions& options) {
  if (options.port < 0 || options.port > 65535)
    return MakeError(ErrorCode::kInvalidArgument,
                     "port must be in [0, 65535], got " + std::to_string(options.port));
  httplib::Server server;
  server.new_task_queue = [] { return new httplib::ThreadPool(ServeOptions::kConnections); };
  server.set_read_timeout(ServeOptions::kClientTimeout);
  server.set_write_timeout(ServeOptions::kClientTimeout);
  server.set_keep_alive_timeout(ServeOptions::kClientTimeout.count());
  server.set_payload_max_length(16 * 1024);  // requests carry no bodies worth having
  const auto serve = [&folder](const httplib::Request& request, httplib::Response& response) {
    Serve(folder, request, response);
  };
  server.Get(R"(/([^/]*))", serve);
  server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
    if (response.body.empty()) response.set_content(std::to_string(response.status) + "\n", "text/plain");
  });
  int port = options.port;
  if (port == 0) {
    port = server.bind_to_any_port("127.0.0.1");
  } else if (!server.bind_to_port("127.0.0.1", port)) {
    port = -1;
  }
  if (port <= 0)
    return MakeError(
        ErrorCode::kInvalidArgument,
        "cannot listen on 127.0.0.1:" + std::to_string(options.port) + ": " + std::strerror(errno));
  if (options.on_listening) options.on_listening(port);

  g_stop_requested.store(false);
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
  std::thread stopper([&] {
    const auto end = std::chrono::steady_clock::now() + options.duration;
    while (!g_stop_requested.load() &&
           (options.duration.count() == 0 || std::chrono::steady_clock::now() < end))
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    server.stop();
  });
  server.listen_after_bind();
  g_stop_requested.store(true);
  stopper.join();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  return Status::Ok();
}

}  // namespace strata::view
