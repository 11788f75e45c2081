#pragma once
// One run at a time per case directory: an OS-level lock (flock) on DIR/.granstack.lock, held
// while granstack works in the directory. The kernel drops it when the holder ends in any way,
// SIGKILL included, so a dead holder's lock is simply taken over.
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace granstack::os {

// Thrown when another process holds the lock; the message names it (pid, host, command, start).
class LockedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown when the lock file cannot be made or locked (a read-only case, a full disk): an I/O
// error, not bad input.
class LockFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CaseLock {
 public:
  // Takes the lock of `dir` for `what` (e.g. "granstack run"), or throws LockedError naming
  // the holder (LockFileError when the lock file cannot be made, e.g. a read-only case).
  CaseLock(const std::filesystem::path& dir, const std::string& what);
  ~CaseLock();
  CaseLock(const CaseLock&) = delete;
  CaseLock& operator=(const CaseLock&) = delete;
  CaseLock(CaseLock&& other) noexcept;
  CaseLock& operator=(CaseLock&& other) noexcept;

  static constexpr const char* kFileName = ".granstack.lock";

  // Who holds the lock of `dir` now ("granstack run by pid ... since ..."), or nullopt when nobody
  // does (a run.json that says running then speaks of a granstack that is gone). It probes with a
  // shared lock for an instant; a CaseLock being taken meanwhile waits for it.
  static std::optional<std::string> holder(const std::filesystem::path& dir);

 private:
  int fd_ = -1;
};

// A folder's own lock (flock on the folder itself: no file is made in it), waited for: the
// commands that replace a directory in `folder` take it so that checking what is there and
// renaming the new one into place are one step. Throws std::runtime_error when the folder cannot
// be opened.
class FolderLock {
 public:
  explicit FolderLock(const std::filesystem::path& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace granstack::os
