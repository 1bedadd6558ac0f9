#include "tools/view/StaticFileServer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "physics/core/FileDescriptor.h"

namespace strata::view {

namespace {

std::atomic<bool> g_stop_requested{false};

extern "C" void RequestStop(int) {
  g_stop_requested.store(true);
}

const char* ContentType(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  if (extension == ".html") return "text/html; charset=utf-8";
  if (extension == ".js") return "text/javascript; charset=utf-8";
  if (extension == ".glb") return "model/gltf-binary";
  if (extension == ".json") return "application/json";
  if (extension == ".png") return "image/png";
  return "application/octet-stream";
}

void SendAll(int fd, const std::string& bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;  // the browser went away
    sent += static_cast<std::size_t>(n);
  }
}

std::string Response(int code, const char* reason, const char* type, const std::string& body, bool head) {
  std::string response = "HTTP/1.1 " + std::to_string(code) + " " + reason + "\r\nContent-Type: " + type +
                         "\r\nContent-Length: " + std::to_string(body.size()) +
                         "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
  if (!head) response += body;
  return response;
}

// The file a request line names, if it is a plain file directly in the folder.
std::filesystem::path Resolve(const std::filesystem::path& folder, std::string target) {
  target = target.substr(0, target.find_first_of("?#"));
  if (target == "/") target = "/index.html";
  if (target.size() < 2 || target[0] != '/') return {};
  const std::string name = target.substr(1);
  // Only names of the folder's own files: no separators, no "..", nothing escaped.
  if (name.find_first_of("/\\%") != std::string::npos || name == "." || name == "..") return {};
  const std::filesystem::path path = folder / name;
  std::error_code error;
  return std::filesystem::is_regular_file(path, error) ? path : std::filesystem::path();
}

void Handle(int client, const std::filesystem::path& folder) {
  std::string request;
  char buffer[4096];
  // The request line is all that matters; read until it is complete (or the client stops).
  while (request.find("\r\n") == std::string::npos && request.size() < 16384) {
    pollfd ready{client, POLLIN, 0};
    if (::poll(&ready, 1, 2000) <= 0) return;
    const ssize_t n = ::recv(client, buffer, sizeof(buffer), 0);
    if (n <= 0) return;
    request.append(buffer, static_cast<std::size_t>(n));
  }
  const std::string line = request.substr(0, request.find("\r\n"));
  const std::size_t first_space = line.find(' ');
  const std::size_t second_space = line.find(' ', first_space + 1);
  if (first_space == std::string::npos || second_space == std::string::npos) {
    SendAll(client, Response(400, "Bad Request", "text/plain", "bad request\n", false));
    return;
  }
  const std::string method = line.substr(0, first_space);
  const bool head = method == "HEAD";
  if (method != "GET" && !head) {
    SendAll(client, Response(405, "Method Not Allowed", "text/plain", "GET or HEAD only\n", false));
    return;
  }
  const std::filesystem::path path =
      Resolve(folder, line.substr(first_space + 1, second_space - first_space - 1));
  if (path.empty()) {
    SendAll(client, Response(404, "Not Found", "text/plain", "not found\n", head));
    return;
  }
  std::ifstream file(path, std::ios::binary);
  const std::string body((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  SendAll(client, Response(200, "OK", ContentType(path), body, head));
}

}  // namespace

Status ServeFolder(const std::filesystem::path& folder, const ServeOptions& options) {
  if (options.port < 0 || options.port > 65535)
    return MakeError(ErrorCode::kInvalidArgument,
                     "port must be in [0, 65535], got " + std::to_string(options.port));
  const FileDescriptor listener(::socket(AF_INET, SOCK_STREAM, 0));
  if (listener.get() < 0)
    return MakeError(ErrorCode::kInvalidState, std::string("socket: ") + std::strerror(errno));
  const int reuse = 1;
  ::setsockopt(listener.get(), SOL_SOCKET, SO_REUSEADDR, &reuse, sizeof(reuse));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(options.port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(listener.get(), reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0 ||
      ::listen(listener.get(), 16) != 0)
    return MakeError(
        ErrorCode::kInvalidArgument,
        "cannot listen on 127.0.0.1:" + std::to_string(options.port) + ": " + std::strerror(errno));
  socklen_t length = sizeof(address);
  ::getsockname(listener.get(), reinterpret_cast<sockaddr*>(&address), &length);
  if (options.on_listening) options.on_listening(ntohs(address.sin_port));

  g_stop_requested.store(false);
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
  const auto end = std::chrono::steady_clock::now() + options.duration;
  while (!g_stop_requested.load()) {
    int wait_ms = 200;
    if (options.duration.count() > 0) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;
      wait_ms = static_cast<int>(std::min<std::int64_t>(left.count(), 200));
    }
    pollfd ready{listener.get(), POLLIN, 0};
    if (::poll(&ready, 1, wait_ms) <= 0) continue;
    const FileDescriptor client(::accept(listener.get(), nullptr, nullptr));
    if (client.get() >= 0) Handle(client.get(), folder);
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  return Status::Ok();
}

}  // namespace strata::view
