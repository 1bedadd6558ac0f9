// FileDescriptor: owns a POSIX file descriptor (a file or a socket) and closes it on every path out of a
// scope. Not copyable. One owner; the descriptor's own thread rules are the system's.
#pragma once

#include <unistd.h>

namespace strata {

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  /// The descriptor, or a negative value when the call that made it failed.
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace strata
