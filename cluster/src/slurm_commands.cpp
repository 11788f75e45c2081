#include "slurm_commands.hpp"

#include <granstack/formats/files.hpp>
#include <granstack/os/process.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <thread>
#include <filesystem>
#include <sstream>
#include <unistd.h>

namespace granstack::cluster {

namespace fs = std::filesystem;

SlurmResult run_slurm(const std::vector<std::string>& argv, double timeout_seconds) {
  SlurmResult r;
  const auto program = os::find_program(argv.front());
  if (!program) {
    r.output = fmt::format("{} is not on PATH", argv.front());
    return r;
  }
  auto temp = (fs::temp_directory_path() / "granstack-slurm-XXXXXX").string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) throw std::runtime_error("cannot make a temporary file for SLURM's output");
  ::close(fd);
  std::vector<std::string> args = argv;
  args.front() = *program;
  os::StartOptions o;
  o.output = temp;
  std::string error;
  const auto end = os::run(args, o, &error, timeout_seconds);
  r.started = error.empty();
  r.timed_out = end.timed_out || end.stopped;
  r.code = r.timed_out ? -1 : end.code;
  try {
    r.output = formats::read_file(temp);
  } catch (const std::exception&) {
  }
  std::error_code ec;
  fs::remove(temp, ec);
  if (!r.started) r.output = error;
  if (end.stopped) r.output = fmt::format("{} was stopped: granstack was asked to stop", argv.front());
  else if (r.timed_out) r.output = fmt::format("{} did not answer within {:.0f} s (is the SLURM controller up?)", argv.front(), timeout_seconds);
  while (!r.output.empty() && (r.output.back() == '\n' || r.output.back() == ' ')) r.output.pop_back();
  return r;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

namespace {
std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (;;) {
    const auto next = text.find(sep, at);
    out.push_back(text.substr(at, next == std::string::npos ? std::string::npos : next - at));
    if (next == std::string::npos) return out;
    at = next + 1;
  }
}

// The value of NAME=VALUE among scontrol's one-line fields.
std::string field(const std::string& line, const std::string& name) {
  const auto at = line.find(" " + name + "=");
  if (at == std::string::npos) return "";
  const auto start = at + name.size() + 2;
  return line.substr(start, line.find(' ', start) - start);
}
}  // namespace

QueueView read_queue(const std::vector<std::string>& job_ids, const std::string& squeue) {
  QueueView q;
  if (job_ids.empty()) {
    q.answered = true;
    return q;
  }
  const auto r = run_slurm({squeue, "-h", "-r", "-j", fmt::format("{}", fmt::join(job_ids, ",")), "-o", "%A|%a|%i|%T|%M|%R"}, 10.0);
  // squeue exits non-zero when none of the jobs is known any more: an empty queue.
  if (r.started && !r.timed_out && (r.code == 0 || r.output.find("Invalid job id") != std::string::npos)) {
    q.answered = true;
    if (r.code != 0) return q;
    for (const auto& line : lines(r.output)) {
      const auto f = split(line, '|');
      if (f.size() < 6) continue;
      // %i is JOB_TASK for an array task, pending or running (%a says "(null)" while it is pending).
      const auto under = f[2].find('_');
      q.tasks[{f[2].substr(0, under), under == std::string::npos ? "" : f[2].substr(under + 1)}] = f[3];
      q.lines.push_back(fmt::format("{} {} {} {}", f[2], f[3], f[4], f[5]));
    }
    return q;
  }
  q.error = r.output.empty() ? fmt::format("{} exited with code {}", squeue, r.code) : r.output;
  return q;
}

std::map<Task, std::string> ended_states(const std::vector<std::string>& job_ids, const std::string& sacct,
                                         const std::string& scontrol) {
  std::map<Task, std::string> states;
  if (job_ids.empty()) return states;
  const auto acct = run_slurm({sacct, "-n", "-P", "-X", "-j", fmt::format("{}", fmt::join(job_ids, ",")), "-o", "JobID,State"}, 10.0);
  if (acct.started && !acct.timed_out && acct.code == 0 && acct.output.find("disabled") == std::string::npos) {
    for (const auto& line : lines(acct.output)) {
      const auto f = split(line, '|');
      const auto under = f[0].find('_');
      if (f.size() < 2 || under == std::string::npos || f[0].find('[') != std::string::npos) continue;
      states[{f[0].substr(0, under), f[0].substr(under + 1)}] = f[1].substr(0, f[1].find(' '));  // "CANCELLED by 0"
    }
    return states;
  }
  for (const auto& id : job_ids) {
    const auto r = run_slurm({scontrol, "-o", "show", "job", id}, 10.0);
    if (!r.started || r.timed_out || r.code != 0) continue;
    for (const auto& line : lines(r.output)) {
      const auto job = field(line, "ArrayJobId"), task = field(line, "ArrayTaskId"), state = field(line, "JobState");
      if (!job.empty() && !task.empty() && task.find_first_not_of("0123456789") == std::string::npos) states[{job, task}] = state;
    }
  }
  return states;
}

}  // namespace granstack::cluster
