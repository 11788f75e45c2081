#include <granstack/os/case_lock.hpp>

#include <fmt/chrono.h>
#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>
#include <utility>

namespace granstack::os {

namespace {
constexpr int kProbeWaits = 20;
constexpr unsigned kProbeWaitMicroseconds = 10000;

std::string read_all(int fd) {
  std::string text;
  char buf[512];
  off_t at = 0;
  ssize_t n;
  while ((n = ::pread(fd, buf, sizeof buf, at)) > 0 && text.size() < 4096) {
    text.append(buf, static_cast<std::size_t>(n));
    at += n;
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  return text;
}
}  // namespace

CaseLock::CaseLock(const std::filesystem::path& dir, const std::string& what) {
  const auto path = (dir / kFileName).string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) {
    // The directory may be a case, a sweep's or a design search's: named by its path alone.
    throw LockFileError(fmt::format("{}: cannot make the lock file: {}{}", path, std::strerror(errno),
                                    errno == EACCES || errno == EROFS ? " (is the directory read-only?)" : ""));
  }
  // A probe (holder()) holds a shared lock for an instant: wait that out before calling the case in use.
  int e = 0;
  for (int tries = 1;; ++tries) {
    if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) {
      e = 0;
      break;
    }
    e = errno;
    if (e != EWOULDBLOCK || tries == kProbeWaits) break;
    ::usleep(kProbeWaitMicroseconds);
  }
  if (e != 0) {
    const auto holder = read_all(fd_);
    ::close(fd_);
    fd_ = -1;
    if (e == EWOULDBLOCK) {
      throw LockedError(fmt::format("{} is in use by another granstack ({}); wait for it to end, or stop it first",
                                    dir.string(), holder.empty() ? "no details recorded" : holder));
    }
    throw LockFileError(fmt::format("{}: cannot lock: {}", path, std::strerror(e)));
  }
  char host[256] = "?";
  ::gethostname(host, sizeof host - 1);
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  const auto info = fmt::format("{} by pid {} on {} since {:%Y-%m-%dT%H:%M:%SZ}\n", what, ::getpid(), host, fmt::gmtime(now));
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const auto n = ::pwrite(fd_, info.data(), info.size(), 0);
  }
}

std::optional<std::string> CaseLock::holder(const std::filesystem::path& dir) {
  const auto path = (dir / kFileName).string();
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return std::nullopt;  // never locked
  std::optional<std::string> held;
  if (::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
    held = read_all(fd);
    if (held->empty()) *held = "another granstack";
  }
  ::close(fd);
  return held;
}

CaseLock::~CaseLock() {
  if (fd_ >= 0) ::close(fd_);  // closing drops the lock; the file stays (removing it would race)
}

CaseLock::CaseLock(CaseLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

CaseLock& CaseLock::operator=(CaseLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

FolderLock::FolderLock(const std::filesystem::path& folder) {
  const auto path = folder.empty() ? std::string(".") : folder.string();
  fd_ = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(fmt::format("{}: cannot open the folder: {}", path, std::strerror(errno)));
  while (::flock(fd_, LOCK_EX) != 0) {
    if (errno == EINTR) continue;
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error(fmt::format("{}: cannot lock the folder: {}", path, std::strerror(e)));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace granstack::os
