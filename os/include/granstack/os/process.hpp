#pragma once
// Starting external programs (LIGGGHTS, mpirun, gnuplot): always from an argument vector,
// never through a shell, so no character of a path or a flag can become a command.
#include <filesystem>
#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

namespace granstack::os {

// The executable `program` names: itself when it holds a '/' (relative to the current
// directory, checked to be an executable regular file), else the first executable regular
// file of that name on PATH; nullopt otherwise.
std::optional<std::string> find_program(const std::string& program);

struct StartOptions {
  std::filesystem::path cwd;                 // empty: granstack's own
  std::filesystem::path output;              // stdout and stderr go here (truncated); empty: /dev/null
  std::vector<std::string> extra_environment;  // NAME=VALUE added to granstack's environment (replacing its NAME)
  // Where the program (and all it starts) may write: beneath these folders (or files) alone,
  // where the kernel has Landlock (Linux 5.13 and later; Child::confined says); empty: anywhere.
  // Reading stays free.
  std::vector<std::filesystem::path> writable;
};

// A started child. It runs in a process group of its own (so a Ctrl-C at the terminal reaches
// granstack, which stops it, and not the child directly), and the kernel kills it with SIGKILL
// when the thread that started it ends, even when granstack itself is SIGKILLed.
struct Child {
  pid_t pid = -1;
  std::string error;      // why it could not start; pid is -1 then
  bool confined = false;  // it may write only where StartOptions::writable says
};

// Starts argv[0] (a path, as find_program returns) with the arguments exactly as given.
Child start(const std::vector<std::string>& argv, const StartOptions& options);

// SIGKILL to the child's whole process group (the child and whatever it started, e.g. mpirun's
// ranks).
void kill_group(const Child& child);

struct Exit {
  int code = -1;    // the exit code, or -1
  int signal = 0;   // the signal that ended it, or 0
  bool timed_out = false;  // run(): killed (with its process group) after its time
  bool stopped = false;    // run(): killed because granstack was asked to stop (interrupt_signal())
  bool ok() const { return code == 0 && signal == 0 && !timed_out && !stopped; }
};

// Waits for the child to end (restarting on EINTR).
Exit wait(const Child& child);
// The child's end if it has ended, else nullopt.
std::optional<Exit> poll(const Child& child);
// The same after waiting up to `seconds` for it to end: the wait ends as the child does (or on a
// signal), so a caller polling in a loop adds no latency to the child's end.
std::optional<Exit> poll_for(const Child& child, double seconds);

// Runs argv to completion (start + wait); output as in StartOptions. With `seconds` > 0 it
// waits at most that long; a program still running then, or when granstack is asked to stop
// (interrupt_signal()), is killed with everything it started (Exit::timed_out, Exit::stopped):
// no external program can hold granstack.
Exit run(const std::vector<std::string>& argv, const StartOptions& options, std::string* start_error = nullptr,
         double seconds = 0.0);

// How long granstack waits for a program that should answer at once (a version probe, a
// scheduler's command): 20 s, or GRANSTACK_PROBE_SECONDS where that is a number above 0.
double probe_seconds();

// The CPUs granstack may run on: its affinity mask's (what taskset or a SLURM allocation leaves
// it), at least 1.
int usable_cpus();

}  // namespace granstack::os
