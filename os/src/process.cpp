#include <granstack/os/process.hpp>

#include "write_confinement.hpp"

#include <granstack/os/interrupt.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <cmath>
#include <fcntl.h>
#include <poll.h>
#include <sys/syscall.h>
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace granstack::os {

namespace fs = std::filesystem;

namespace {
bool executable_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

// What the child does between its start and exec. It shares the parent's memory (CLONE_VM, the
// starting thread stopped until exec: CLONE_VFORK), so it may only make system calls: no
// allocation, no lock, nothing a signal handler of the parent's could see half done (the parent
// blocks every signal around the start; the child sets the ones granstack handles back to their
// default before it unblocks them). Reports a failure to the parent through `report`
// (close-on-exec) and exits 127.
struct Becoming {
  char* const* argv;
  char* const* envp;
  const char* cwd;
  const char* output;
  pid_t parent;
  int report;
  int confinement;
  const sigset_t* mask;  // the mask the program starts with: none blocked
};

int become(void* arg) {
  const auto& b = *static_cast<const Becoming*>(arg);
  auto fail = [&](int stage) {
    const int e[2] = {stage, errno};
    [[maybe_unused]] const auto n = ::write(b.report, e, sizeof e);
    ::_exit(127);
  };
  // SIGKILL when the starting thread ends; if the parent died before this took effect, go now.
  if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) fail(0);
  if (::getppid() != b.parent) ::_exit(127);
  ::setpgid(0, 0);
  // Signals granstack ignores or handles must reach the program in their default state.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT}) ::sigaction(s, &dfl, nullptr);
  ::sigprocmask(SIG_SETMASK, b.mask, nullptr);
  if (b.cwd[0] != '\0' && ::chdir(b.cwd) != 0) fail(1);
  const int in = ::open("/dev/null", O_RDONLY);
  if (in < 0 || ::dup2(in, STDIN_FILENO) < 0) fail(2);
  const int out = b.output[0] != '\0' ? ::open(b.output, O_WRONLY | O_CREAT | O_TRUNC, 0644) : ::open("/dev/null", O_WRONLY);
  if (out < 0 || ::dup2(out, STDOUT_FILENO) < 0 || ::dup2(out, STDERR_FILENO) < 0) fail(2);
  if (b.confinement >= 0 && !detail::apply_write_confinement(b.confinement)) fail(4);
  ::execve(b.argv[0], b.argv, b.envp);
  fail(3);
  return 127;
}

// Starts `become` as a new process sharing this one's memory until it executes: unlike fork, no
// page table is copied and no page of a large parent (reproduce's reductions beside its runs) is
// made copy-on-write, to fault again on the parent's next write.
pid_t start_process(Becoming& b) {
  constexpr std::size_t kStack = std::size_t{64} << 10;
  std::vector<char> stack(kStack);
  sigset_t all, old;
  sigfillset(&all);
  ::pthread_sigmask(SIG_SETMASK, &all, &old);
  sigset_t none;
  sigemptyset(&none);
  b.mask = &none;
  const pid_t pid = ::clone(become, stack.data() + stack.size(), CLONE_VM | CLONE_VFORK | SIGCHLD, &b);
  const int saved = errno;
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
  errno = saved;
  return pid;
}
}  // namespace

std::optional<std::string> find_program(const std::string& program) {
  if (program.empty()) return std::nullopt;
  if (program.find('/') != std::string::npos) {
    return executable_file(program) ? std::optional<std::string>(program) : std::nullopt;
  }
  const char* path = std::getenv("PATH");
  const std::string dirs = path != nullptr ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t begin = 0;
  while (begin <= dirs.size()) {
    const auto end = std::min(dirs.find(':', begin), dirs.size());
    const auto candidate = (fs::path(end > begin ? dirs.substr(begin, end - begin) : ".") / program).string();
    if (executable_file(candidate)) return candidate;
    begin = end + 1;
  }
  return std::nullopt;
}

Child start(const std::vector<std::string>& argv, const StartOptions& options) {
  Child child;
  if (argv.empty()) {
    child.error = "no program to start";
    return child;
  }
  const auto program = find_program(argv[0]);
  if (!program) {
    child.error = fmt::format("cannot start '{}': not an executable file{}", argv[0],
                              argv[0].find('/') == std::string::npos ? " on PATH" : "");
    return child;
  }
  // Everything the child needs is built before it starts: it may not allocate.
  std::vector<std::string> args = argv;
  args[0] = fs::absolute(*program).string();  // the child changes directory before exec
  std::vector<char*> arg_ptrs;
  for (auto& a : args) arg_ptrs.push_back(a.data());
  arg_ptrs.push_back(nullptr);
  std::vector<std::string> extra = options.extra_environment;
  // A NAME=VALUE given replaces the inherited NAME (getenv finds the first of two).
  auto overridden = [&](const char* e) {
    const std::string_view entry(e);
    for (const auto& x : extra) {
      const auto eq = x.find('=');
      if (eq != std::string::npos && entry.substr(0, eq + 1) == std::string_view(x).substr(0, eq + 1)) return true;
    }
    return false;
  };
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (!overridden(*e)) env.push_back(*e);
  }
  for (auto& e : extra) env.push_back(e.data());
  env.push_back(nullptr);
  // Absolute, since the child changes directory before it opens the output.
  const std::string cwd = options.cwd.empty() ? "" : fs::absolute(options.cwd).string();
  const std::string output = options.output.empty() ? "" : fs::absolute(options.output).string();
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) {
    child.error = fmt::format("cannot start {}: {}", argv[0], std::strerror(errno));
    return child;
  }
  const int confinement = options.writable.empty() ? -1 : detail::write_confinement(options.writable);
  Becoming b{arg_ptrs.data(), env.data(), cwd.c_str(), output.c_str(), ::getpid(), report[1], confinement, nullptr};
  const pid_t pid = start_process(b);
  ::close(report[1]);
  if (confinement >= 0) ::close(confinement);
  if (pid < 0) {
    child.error = fmt::format("cannot start {}: {}", argv[0], std::strerror(errno));
    ::close(report[0]);
    return child;
  }
  ::setpgid(pid, pid);  // also here, so the group exists before the parent may signal it
  int failure[2] = {0, 0};
  ssize_t got;
  do {
    got = ::read(report[0], failure, sizeof failure);
  } while (got < 0 && errno == EINTR);
  ::close(report[0]);
  if (got == static_cast<ssize_t>(sizeof failure)) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    static const char* const stages[] = {"set up its parent-death signal", "enter the directory", "redirect its output",
                                         "execute", "confine its writes (Landlock)"};
    const char* where = stages[failure[0] >= 0 && failure[0] <= 4 ? failure[0] : 3];
    child.error = fmt::format("cannot start {}: could not {}{}: {}", *program, where,
                              failure[0] == 1 ? " " + cwd : failure[0] == 2 ? " to " + output : "",
                              std::strerror(failure[1]));
    return child;
  }
  child.pid = pid;
  child.confined = confinement >= 0;
  return child;
}

void kill_group(const Child& child) {
  if (child.pid > 0) ::kill(-child.pid, SIGKILL);
}

namespace {
Exit decode(int status) {
  Exit e;
  if (WIFEXITED(status)) e.code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) e.signal = WTERMSIG(status);
  return e;
}
}  // namespace

Exit wait(const Child& child) {
  int status = 0;
  pid_t r;
  do {
    r = ::waitpid(child.pid, &status, 0);
  } while (r < 0 && errno == EINTR);
  return r == child.pid ? decode(status) : Exit{};
}

std::optional<Exit> poll(const Child& child) {
  int status = 0;
  pid_t r;
  do {
    r = ::waitpid(child.pid, &status, WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r == child.pid) return decode(status);
  if (r < 0) return Exit{};
  return std::nullopt;
}

std::optional<Exit> poll_for(const Child& child, double seconds) {
  if (auto end = poll(child)) return end;
  // A pidfd becomes readable when the child ends (Linux 5.3 and later): the wait ends then, not
  // at the period's end. Without one, the period is slept out.
  const int fd = static_cast<int>(::syscall(SYS_pidfd_open, child.pid, 0));
  const int ms = static_cast<int>(std::lround(seconds * 1e3));
  if (fd >= 0) {
    pollfd p{fd, POLLIN, 0};
    (void)::poll(&p, 1, ms);  // EINTR: a signal (granstack asked to stop) ends the wait early
    ::close(fd);
  } else {
    std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  }
  return poll(child);
}

Exit run(const std::vector<std::string>& argv, const StartOptions& options, std::string* start_error, double seconds) {
  const auto child = start(argv, options);
  if (child.pid < 0) {
    if (start_error != nullptr) *start_error = child.error;
    return Exit{};
  }
  if (seconds <= 0.0) return wait(child);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    if (const auto end = poll_for(child, 0.01)) return *end;
    const bool late = std::chrono::steady_clock::now() > deadline;
    if (late || interrupt_signal() != 0) {
      kill_group(child);
      auto end = wait(child);
      (late ? end.timed_out : end.stopped) = true;
      return end;
    }
  }
}

double probe_seconds() {
  const char* text = std::getenv("GRANSTACK_PROBE_SECONDS");
  char* end = nullptr;
  const double v = text != nullptr ? std::strtod(text, &end) : 0.0;
  return text != nullptr && end != text && *end == '\0' && v > 0.0 && v < 1e6 ? v : 20.0;
}

int usable_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return std::max(1, CPU_COUNT(&set));
}

}  // namespace granstack::os
