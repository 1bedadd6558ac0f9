#include "physics/core/OutputFile.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace strata {

namespace {

constexpr std::string_view kTemporarySuffix = ".strata-tmp";

Error OutputError(const std::filesystem::path& path, const std::string& why) {
  return {ErrorCode::kInvalidArgument, path.string() + ": " + why};
}

std::string SystemError(int error) {
  return std::strerror(error);
}

// ".<target>.<pid>-<random>.strata-tmp": the pid tells a later writer whether the one that made it is gone.
std::string TemporaryName(const std::string& target_name) {
  static std::atomic<std::uint64_t> counter{0};
  thread_local std::mt19937_64 random{std::random_device{}()};
  const std::uint64_t unique = random() ^ counter.fetch_add(1, std::memory_order_relaxed);
  char suffix[64];
  std::snprintf(suffix, sizeof(suffix), ".%ld-%016llx", static_cast<long>(::getpid()),
                static_cast<unsigned long long>(unique));
  return "." + target_name + suffix + std::string(kTemporarySuffix);
}

// Whether `name` is the name TemporaryName gives a temporary of a target named `target_name`.
bool IsTemporaryOf(std::string_view name, std::string_view target_name) {
  return name.size() > target_name.size() + 2 + kTemporarySuffix.size() && name[0] == '.' &&
         name.substr(1, target_name.size()) == target_name && name[target_name.size() + 1] == '.' &&
         name.substr(name.size() - kTemporarySuffix.size()) == kTemporarySuffix;
}

// The pid in a temporary's name, or 0 when the name has none.
long TemporaryOwner(std::string_view name, std::string_view target_name) {
  const std::string_view rest = name.substr(target_name.size() + 2);
  long pid = 0;
  for (const char c : rest) {
    if (c == '-') return pid;
    if (c < '0' || c > '9' || pid > 1'000'000'000) return 0;
    pid = pid * 10 + (c - '0');
  }
  return 0;
}

// Removes temporaries of `target` whose writer is no longer running (killed before it could clean up).
void RemoveStaleTemporaries(const std::filesystem::path& target) {
  const std::string target_name = target.filename().string();
  std::error_code error;
  const std::filesystem::path folder = target.parent_path().empty() ? "." : target.parent_path();
  for (std::filesystem::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!IsTemporaryOf(name, target_name)) continue;
    const long owner = TemporaryOwner(name, target_name);
    if (owner <= 0 || owner == ::getpid() || ::kill(static_cast<pid_t>(owner), 0) == 0 || errno != ESRCH)
      continue;
    struct stat info {};
    if (::lstat(it->path().c_str(), &info) == 0 && S_ISREG(info.st_mode)) ::unlink(it->path().c_str());
  }
}

}  // namespace

/// A stream buffer over a file descriptor that remembers the first failed write.
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int descriptor) : descriptor_(descriptor) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  ~DescriptorBuffer() override {
    if (descriptor_ >= 0) ::close(descriptor_);
  }
  DescriptorBuffer(const DescriptorBuffer&) = delete;
  DescriptorBuffer& operator=(const DescriptorBuffer&) = delete;

  int descriptor() const { return descriptor_; }
  /// errno of the first write that failed, 0 if none did.
  int failure() const { return failure_; }
  /// Closes the descriptor; false (with failure() set) if closing reported an error.
  bool Close() {
    const int descriptor = descriptor_;
    descriptor_ = -1;
    if (descriptor < 0 || ::close(descriptor) == 0) return true;
    if (failure_ == 0) failure_ = errno;
    return false;
  }

 protected:
  int_type overflow(int_type character) override {
    if (!Drain()) return traits_type::eof();
    if (traits_type::eq_int_type(character, traits_type::eof())) return traits_type::not_eof(character);
    *pptr() = traits_type::to_char_type(character);
    pbump(1);
    return character;
  }
  std::streamsize xsputn(const char* data, std::streamsize count) override {
    if (count >= static_cast<std::streamsize>(buffer_.size())) {
      if (!Drain() || !WriteAll(data, static_cast<std::size_t>(count))) return 0;
      return count;
    }
    return std::streambuf::xsputn(data, count);
  }
  int sync() override { return Drain() ? 0 : -1; }

 private:
  bool Drain() {
    const auto pending = static_cast<std::size_t>(pptr() - pbase());
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return WriteAll(buffer_.data(), pending);
  }
  bool WriteAll(const char* data, std::size_t count) {
    if (failure_ != 0) return false;
    while (count > 0) {
      const ssize_t written = ::write(descriptor_, data, count);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        failure_ = written < 0 ? errno : ENOSPC;
        return false;
      }
      data += written;
      count -= static_cast<std::size_t>(written);
    }
    return true;
  }

  int descriptor_;
  int failure_ = 0;
  std::array<char, 1 << 16> buffer_{};
};

OutputFile::OutputFile(std::filesystem::path path) : path_(std::move(path)), stream_(nullptr) {
  struct stat target {};
  const bool exists = ::stat(path_.c_str(), &target) == 0;
  if (exists && S_ISDIR(target.st_mode)) {
    status_ = OutputError(path_, "is a directory");
    return;
  }
  int descriptor = -1;
  if (exists && !S_ISREG(target.st_mode)) {
    // A device or pipe the user named (or linked to): written in place.
    descriptor = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
    if (descriptor < 0) {
      status_ = OutputError(path_, "cannot open for writing: " + SystemError(errno));
      return;
    }
  } else {
    if (path_.filename().empty()) {
      status_ = OutputError(path_, "names a folder, not a file");
      return;
    }
    RemoveStaleTemporaries(path_);
    const mode_t mode = exists ? (target.st_mode & 07777) : 0666;
    for (int attempt = 0; attempt < 16 && descriptor < 0; ++attempt) {
      temporary_ = path_.parent_path() / TemporaryName(path_.filename().string());
      // O_EXCL with O_CREAT never follows a link and never opens a file someone else made.
      descriptor = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
      if (descriptor < 0 && errno != EEXIST) break;
    }
    if (descriptor < 0) {
      status_ = OutputError(path_, "cannot create a file beside it: " + SystemError(errno));
      temporary_.clear();
      return;
    }
    if (exists) (void)::fchmod(descriptor, mode);  // keep the old file's permissions, whatever the umask
  }
  buffer_ = std::make_unique<DescriptorBuffer>(descriptor);
  stream_.rdbuf(buffer_.get());
}

OutputFile::~OutputFile() {
  stream_.rdbuf(nullptr);
  buffer_.reset();
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
}

Status OutputFile::Commit() {
  if (!status_) return status_;
  if (committed_) return Status::Ok();
  stream_.flush();
  const bool synced = temporary_.empty() || ::fsync(buffer_->descriptor()) == 0 || errno == EINVAL;
  const bool closed = buffer_->Close();
  if (buffer_->failure() != 0 || !stream_ || !synced || !closed) {
    const int failure = buffer_->failure() != 0 ? buffer_->failure() : errno;
    if (!temporary_.empty()) ::unlink(temporary_.c_str());
    temporary_.clear();
    return status_ = OutputError(path_, "cannot write the file: " + SystemError(failure));
  }
  committed_ = true;
  if (temporary_.empty()) return Status::Ok();
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const int failure = errno;
    ::unlink(temporary_.c_str());
    temporary_.clear();
    return status_ = OutputError(path_, "cannot replace the file: " + SystemError(failure));
  }
  temporary_.clear();
  // The rename itself reaches the disk with the folder's entry.
  const std::filesystem::path folder = path_.parent_path().empty() ? "." : path_.parent_path();
  if (const int directory = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); directory >= 0) {
    (void)::fsync(directory);
    ::close(directory);
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
