#include <granstack/os/mpi_session.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace granstack::os {

namespace fs = std::filesystem;

namespace {

// Removes the directories in `base` that a granstack of this user made and no granstack holds.
void remove_left_over(const fs::path& base) {
  std::error_code ec;
  for (fs::directory_iterator it(base, ec), end; !ec && it != end; it.increment(ec)) {
    const auto& dir = it->path();
    struct stat st {};
    if (dir.filename().string().rfind(MpiSessionDir::kPrefix, 0) != 0 || ::lstat(dir.c_str(), &st) != 0 ||
        !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid()) {
      continue;
    }
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) continue;
    std::error_code gone;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && fs::is_regular_file(dir / MpiSessionDir::kMarker, gone)) {
      fs::remove_all(dir, gone);
    }
    ::close(fd);
  }
}

}  // namespace

MpiSessionDir::MpiSessionDir() {
  std::error_code ec;
  const auto base = fs::temp_directory_path(ec);
  if (ec) return;
  remove_left_over(base);
  auto pattern = (base / (std::string(kPrefix) + "XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) return;
  fd_ = ::open(pattern.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC | O_NOFOLLOW);
  // The lock before the marker: a directory with the marker is either held or left over.
  if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0 || !std::ofstream(fs::path(pattern) / kMarker)) {
    fs::remove_all(pattern, ec);
    return;
  }
  path_ = pattern;
}

MpiSessionDir::~MpiSessionDir() {
  std::error_code ec;
  if (!path_.empty()) fs::remove_all(path_, ec);
  if (fd_ >= 0) ::close(fd_);
}

std::vector<std::string> mpi_environment(const std::string& dir, int ranks) {
  std::vector<std::string> env;
  const auto add = [&](const char* name, const std::string& value) {
    if (std::getenv(name) == nullptr && !value.empty()) env.push_back(std::string(name) + "=" + value);
  };
  add("OMPI_MCA_orte_tmpdir_base", dir);
  // A single rank started without mpirun need not launch Open MPI's daemon (0.1 s per start).
  if (ranks == 1) add("OMPI_MCA_ess_singleton_isolated", "1");
  return env;
}

Exit run_open_mpi_program(const std::vector<std::string>& argv, StartOptions start, std::string* start_error,
                          double seconds) {
  const MpiSessionDir dir;
  const auto env = mpi_environment(dir.path(), 1);
  start.extra_environment.insert(start.extra_environment.end(), env.begin(), env.end());
  return run(argv, start, start_error, seconds);
}

}  // namespace granstack::os
