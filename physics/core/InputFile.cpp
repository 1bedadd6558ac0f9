#include "physics/core/InputFile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "physics/core/FileDescriptor.h"

namespace strata {

namespace {

Error InputError(const std::filesystem::path& path, const std::string& why) {
  return {ErrorCode::kParseError, path.string() + ": " + why};
}

Error OpenError(const std::filesystem::path& path, int error) {
  if (error == ENOENT) return InputError(path, "file not found");
  return InputError(path, std::string("cannot open: ") + std::strerror(error));
}

// What a file's type makes of it as an input: nothing when it is a regular file.
std::string RefusalFor(const struct stat& info) {
  if (S_ISREG(info.st_mode)) return {};
  if (S_ISDIR(info.st_mode)) return "is a directory, not a file";
  if (S_ISFIFO(info.st_mode)) return "is a pipe, not a regular file";
  if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode)) return "is a device, not a regular file";
  return "is not a regular file";
}

std::string Bytes(std::uint64_t bytes) {
  return std::to_string(bytes) + " bytes";
}

Status CheckSize(const std::filesystem::path& path, std::uint64_t size, std::uint64_t max_bytes) {
  if (size <= max_bytes) return Status::Ok();
  return InputError(
      path, "is " + Bytes(size) + ", more than the " + Bytes(max_bytes) + " this kind of file may have");
}

}  // namespace

Result<std::uint64_t> CheckInputFile(const std::filesystem::path& path, std::uint64_t max_bytes) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return OpenError(path, errno);
  if (const std::string refusal = RefusalFor(info); !refusal.empty()) return InputError(path, refusal);
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (Status fits = CheckSize(path, size, max_bytes); !fits) return fits.error();
  return size;
}

Result<std::string> ReadInputFile(const std::filesystem::path& path, std::uint64_t max_bytes) {
  // Non-blocking: opening a FIFO with no writer would otherwise wait forever before fstat could refuse it.
  const FileDescriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (file.get() < 0) return OpenError(path, errno);
  struct stat info {};
  if (::fstat(file.get(), &info) != 0)
    return InputError(path, std::string("cannot read: ") + std::strerror(errno));
  if (const std::string refusal = RefusalFor(info); !refusal.empty()) return InputError(path, refusal);
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (Status fits = CheckSize(path, size, max_bytes); !fits) return fits.error();
  std::string bytes(static_cast<std::size_t>(size), '\0');
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got = ::read(file.get(), bytes.data() + done, bytes.size() - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return InputError(path, std::string("read failed: ") + std::strerror(errno));
    if (got == 0) return InputError(path, "changed while being read (shorter than its size)");
    done += static_cast<std::size_t>(got);
  }
  return bytes;
}

}  // namespace strata
