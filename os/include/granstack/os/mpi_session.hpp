#pragma once
// Open MPI's session files, kept apart per start. Open MPI processes started at the same time
// share /tmp/ompi.HOST.UID by default, and one that ends can remove it while another is still
// creating its own part, or two create it at once ("mkdir ... File exists"): the second then fails
// in orte_init and exits with code 1 before the program prints anything (open-mpi/ompi#3818).
// A directory per start removes the race. LIGGGHTS and LAMMPS link Open MPI, so every start of
// either (granstack's runs and probes, and the tests' own hand runs) goes through here.
#include <granstack/os/process.hpp>

#include <string>
#include <vector>

namespace granstack::os {

// A private directory for Open MPI's session files in the temporary directory (TMPDIR), removed
// with everything in it at the end.
//
// A granstack killed outright (SIGKILL, a batch system's time limit) cannot remove its directory;
// the next one does. While a directory is in use its process holds a lock on it (flock, which the
// kernel drops however the holder ends; the program started, which gets SIGKILL when granstack
// ends, does not inherit it), and a marker file inside says granstack made it. A directory with
// the marker, of this user, that nobody holds is left over, and removed; any other is left alone.
class MpiSessionDir {
 public:
  static constexpr const char* kPrefix = "granstack-mpi-";
  static constexpr const char* kMarker = "made-by-granstack";

  MpiSessionDir();  // path() is empty where none could be made
  ~MpiSessionDir();
  MpiSessionDir(const MpiSessionDir&) = delete;
  MpiSessionDir& operator=(const MpiSessionDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

// The environment added for one start of `ranks` ranks with session files in `dir`; a variable
// the user has set is left as it is.
std::vector<std::string> mpi_environment(const std::string& dir, int ranks);

// Runs `argv`, one process started without mpirun (a program's probe, a deck run by hand), as
// os::run does, with a private directory for Open MPI's session files.
Exit run_open_mpi_program(const std::vector<std::string>& argv, StartOptions start, std::string* start_error = nullptr,
                          double seconds = 0.0);

}  // namespace granstack::os
