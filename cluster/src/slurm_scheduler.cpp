// SLURM behind the Scheduler interface: #SBATCH scripts, sbatch, scontrol's limits, squeue and
// sacct (slurm_commands.cpp runs them).
#include "scheduler.hpp"

#include <granstack/os/process.hpp>
#include <granstack/runner/engines.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace granstack::cluster {

namespace fs = std::filesystem;

std::optional<long> parse_memory_mb(const std::string& text) {
  constexpr long kMostMb = 1024L * 1024 * 1024;  // 1024 T
  const auto digits = text.find_first_not_of("0123456789");  // the unit's place, or npos
  const std::size_t count = digits == std::string::npos ? text.size() : digits;
  if (count == 0 || count > 10 || (digits != std::string::npos && digits != text.size() - 1)) return std::nullopt;
  long unit = 1;
  if (digits != std::string::npos) {
    switch (text[digits]) {
      case 'M': case 'm': unit = 1; break;
      case 'G': case 'g': unit = 1024; break;
      case 'T': case 't': unit = 1024L * 1024; break;
      default: return std::nullopt;
    }
  }
  const long n = std::stol(text.substr(0, count));
  if (n <= 0 || n > kMostMb / unit) return std::nullopt;
  return n * unit;
}

std::optional<long> parse_slurm_time(const std::string& text) {
  std::vector<long> parts;
  long days = 0;
  std::string rest = text;
  if (const auto dash = text.find('-'); dash != std::string::npos) {
    if (dash == 0 || text.find_first_not_of("0123456789") != dash) return std::nullopt;
    days = std::stol(text.substr(0, dash));
    rest = text.substr(dash + 1);
  }
  std::size_t at = 0;
  for (;;) {
    const auto colon = rest.find(':', at);
    const auto field = rest.substr(at, colon == std::string::npos ? std::string::npos : colon - at);
    if (field.empty() || field.size() > 7 || field.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    parts.push_back(std::stol(field));
    if (colon == std::string::npos) break;
    at = colon + 1;
  }
  if (parts.size() > 3) return std::nullopt;
  long seconds = 0;
  if (text.find('-') != std::string::npos) {  // D-HH[:MM[:SS]]
    const long units[] = {3600, 60, 1};
    for (std::size_t i = 0; i < parts.size(); ++i) seconds += parts[i] * units[i];
  } else if (parts.size() == 1) {  // minutes
    seconds = parts[0] * 60;
  } else if (parts.size() == 2) {  // MM:SS
    seconds = parts[0] * 60 + parts[1];
  } else {
    seconds = parts[0] * 3600 + parts[1] * 60 + parts[2];
  }
  seconds += days * 86400;
  if (seconds <= 0 || seconds > 366L * 86400) return std::nullopt;
  return seconds;
}

namespace {

// A word for a bash script: single-quoted, its own quotes escaped. Newlines cannot be carried.
std::string sh_quote(const std::string& s) {
  if (s.find('\n') != std::string::npos || s.find('\r') != std::string::npos) {
    throw SubmitError(fmt::format("'{}' holds a line break, which an sbatch script cannot carry; rename it", s));
  }
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// An #SBATCH value: one line, no spaces that would end it.
std::string sbatch_value(const std::string& what, const std::string& v) {
  if (v.empty() || v.find_first_of(" \t\r\n") != std::string::npos) {
    throw SubmitError(fmt::format("{} '{}' cannot stand in an #SBATCH line (empty, or with blanks)", what, v));
  }
  return v;
}

// A log path for --output: SLURM reads '%' as the start of a pattern ('%%' is a '%'), and a
// backslash anywhere as "no patterns at all" (refused before anything is written).
std::string output_pattern(const std::string& directory, const std::string& file) {
  std::string out;
  for (const char c : directory) out += c == '%' ? std::string("%%") : std::string(1, c);
  return out + "/" + file;
}

// The user's --dependency among the sbatch arguments (combined with granstack's own), and the rest.
std::pair<std::string, std::vector<std::string>> split_dependency(const std::vector<std::string>& args) {
  std::string dependency;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto& a = args[i];
    if (a.rfind("--dependency=", 0) == 0) {
      dependency = a.substr(13);
    } else if ((a == "--dependency" || a == "-d") && i + 1 < args.size()) {
      dependency = args[++i];
    } else if (a.rfind("-d", 0) == 0 && a.size() > 2 && a[2] != '-') {
      dependency = a.substr(2);
    } else {
      rest.push_back(a);
    }
  }
  return {dependency, rest};
}

class Slurm final : public Scheduler {
 public:
  explicit Slurm(SchedulerPrograms p) : p_(std::move(p)) {}
  std::string name() const override { return "SLURM"; }

  void check_directory(const std::string& directory) const override {
    if (directory.find('\\') != std::string::npos) {
      throw SubmitError(fmt::format("{} holds a backslash, which SLURM reads in a log path as 'no patterns' (every "
                                    "task's log would go to one file): rename it",
                                    directory));
    }
  }

  void require_submit() const override {
    if (os::find_program(p_.submit)) return;
    throw SubmitError(fmt::format("{} is not on PATH: install SLURM's client commands (Debian package slurm-client) or "
                                  "submit from a machine that has them; --dry-run writes the scripts without submitting",
                                  p_.submit));
  }

  SiteLimits limits(bool dry_run, std::vector<std::string>& notes) const override {
    // A dry run asks briefly: with no controller, scontrol waits (9 s and more) for nothing.
    const auto r = run_slurm({p_.config, "show", "config"}, dry_run ? 3.0 : 30.0);
    SiteLimits limits;
    if (dry_run && (!r.started || r.code != 0 || r.timed_out)) {  // no cluster here: SLURM's default
      notes.push_back(fmt::format("no SLURM answered ({}): assuming MaxArraySize = {}, SLURM's default",
                                  r.output.substr(0, 120), kDefaultMaxArraySize));
      return limits;
    }
    if (!r.started) {
      throw SubmitError(fmt::format("{}; SLURM's client commands come with the Debian package slurm-client", r.output));
    }
    if (r.code != 0 || r.timed_out) throw SubmitError(fmt::format("scontrol show config failed: {}", r.output));
    for (const auto& line : lines(r.output)) {
      const auto eq = line.find('=');
      if (eq == std::string::npos) continue;
      const auto value = line.substr(eq + 1);
      const auto number = [&] { return std::strtol(value.c_str(), nullptr, 10); };
      if (line.rfind("MaxArraySize", 0) == 0) limits.max_array_size = std::max(1L, number());
      if (line.rfind("MaxJobCount", 0) == 0) limits.max_job_count = number();
    }
    return limits;
  }
  
  // Job records the controller holds now (each queued or running array task counts once it runs).
  long jobs_in_controller(const SubmitOptions& o) {
    const auto r = run_slurm({o.squeue, "-h", "-r", "-o", "%i"}, 10.0);
    return r.started && r.code == 0 ? static_cast<long>(lines(r.output).size()) : 0;
  }

  long jobs_held() const override {
    const auto r = run_slurm({p_.queue, "-h", "-r", "-o", "%i"}, 10.0);
    return r.started && r.code == 0 ? static_cast<long>(lines(r.output).size()) : 0;
  }

  std::string array_script(const Submission& sub, const ArrayJob& a, std::size_t index, const SubmitOptions& o) const override {
    std::string head = fmt::format("#!/bin/bash\n#SBATCH --array=0-{}{}\n{}#SBATCH --ntasks={}\n#SBATCH --cpus-per-task=1\n"
                                   "#SBATCH --time={}\n",
                                   a.tasks - 1, a.throttle > 0 ? fmt::format("%{}", a.throttle) : "",
                                   o.nodes > 0 ? fmt::format("#SBATCH --nodes={}\n", o.nodes) : "", o.ranks,
                                   sbatch_value("--time", a.time));
    if (!o.partition.empty()) head += fmt::format("#SBATCH --partition={}\n", sbatch_value("--partition", o.partition));
    if (!o.account.empty()) head += fmt::format("#SBATCH --account={}\n", sbatch_value("--account", o.account));
    if (o.mem_mb) head += fmt::format("#SBATCH --mem={}\n", *o.mem_mb);
    // --np only for an engine that takes it (runner's engine table): refsim refuses it by name.
    const auto mpi = runner::engines_owning("--np");
    const bool ranks = std::find(mpi.begin(), mpi.end(), o.engine) != mpi.end();
    std::string run = fmt::format("exec {} run --engine {}{}{}", sh_quote(o.granstack), o.engine,
                                  ranks ? fmt::format(" --np {}", o.ranks) : "", o.force ? " --force" : "");
    return head + fmt::format(
                      "# granstack submit: array {} of {}: task i runs lines {} + i*{} + 1 .. {} + (i+1)*{} of cases.txt,\n"
                      "# with `granstack run`, so each case is locked and gets its run.json as on a laptop. The job name\n"
                      "# and the log (task-JOB_TASK.out, appended to when SLURM requeues a task) are given to sbatch.\n"
                      "set -euo pipefail\n"
                      "first=$(( {} + SLURM_ARRAY_TASK_ID * {} + 1 ))\n"
                      "last=$(( first + {} - 1 ))\n"
                      "mapfile -t cases < <(sed -n \"${{first}},${{last}}p\" {})\n"
                      "{} \"${{cases[@]}}\"\n",
                      index + 1, sub.directory, a.first_case, o.cases_per_task, a.first_case, o.cases_per_task, a.first_case,
                      o.cases_per_task, o.cases_per_task, sh_quote(sub.directory + "/cases.txt"), run);
  }
  
  std::string gather_script(const Submission& sub, const std::vector<std::string>& targets, const SubmitOptions& o) const override {
    std::string words;
    for (const auto& t : targets) {
      words += ' ';
      words += sh_quote(fs::absolute(t).lexically_normal().string());
    }
    return fmt::format("#!/bin/bash\n#SBATCH --ntasks=1\n#SBATCH --time={}\n{}{}"
                       "# granstack submit --gather: once the arrays have ended, the table of the targets.\n"
                       "exec {} table{} -o {}\n",
                       sbatch_value("--time", sub.gather_time),
                       o.partition.empty() ? "" : fmt::format("#SBATCH --partition={}\n", o.partition),
                       o.account.empty() ? "" : fmt::format("#SBATCH --account={}\n", o.account), sh_quote(o.granstack), words,
                       sh_quote(sub.directory + "/table"));
  }

  std::string array_log() const override { return "task-%A_%a.out"; }
  std::string task_log(const Task& task) const override { return fmt::format("task-{}_{}.out", task.first, task.second); }

  // sbatch --parsable; returns the job id. Never waits more than a minute: a controller at its
  // MaxJobCount keeps sbatch retrying for much longer.
  std::string submit(const JobRequest& job, const SubmitOptions& o) const override {
    const auto [user_dependency, user_args] = split_dependency(o.sbatch_args);
    std::vector<std::string> argv{p_.submit, "--parsable", "--job-name=" + job.name,
                                  "--output=" + output_pattern(fs::path(job.script).parent_path().string(), job.log),
                                  "--open-mode=append"};
    std::string dependency;
    for (const auto& id : job.after) dependency += (dependency.empty() ? "afterany:" : ":") + id;
    // Both must hold: SLURM's ',' joins dependencies with AND.
    const auto both = dependency.empty() ? user_dependency : user_dependency.empty() ? dependency : dependency + "," + user_dependency;
    if (!both.empty()) argv.push_back("--dependency=" + both);
    argv.insert(argv.end(), user_args.begin(), user_args.end());
    argv.push_back(job.script);
    const auto r = run_slurm(argv, 60.0);
    if (!r.started) throw SubmitError(fmt::format("{}; sbatch comes with the Debian package slurm-client", r.output));
    const auto out = lines(r.output);
    if (r.code != 0 || out.empty() || r.timed_out) throw SubmitError(fmt::format("sbatch refused {}: {}", job.script, r.output));
    return out.back().substr(0, out.back().find(';'));
  }

  bool can_read_queue() const override { return os::find_program(p_.queue).has_value(); }
  QueueView queue(const std::vector<std::string>& job_ids) const override { return read_queue(job_ids, p_.queue); }
  std::map<Task, std::string> ended(const std::vector<std::string>& job_ids) const override {
    return ended_states(job_ids, p_.accounts, p_.config);
  }

 private:
  SchedulerPrograms p_;
};

}  // namespace

std::unique_ptr<Scheduler> make_slurm_scheduler(const SchedulerPrograms& programs) { return std::make_unique<Slurm>(programs); }

}  // namespace granstack::cluster
