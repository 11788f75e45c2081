#include "slurm_commands.hpp"

#include <granstack/cluster/slurm.hpp>
#include "records.hpp"

#include <granstack/formats/files.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/process.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <filesystem>

namespace granstack::cluster {

namespace fs = std::filesystem;
using nlohmann::json;

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

// The cost estimate of each case, by its absolute path: each manifest is read once.
using Costs = std::map<std::string, model::Cost>;

model::Cost case_cost(const std::string& dir) {
  const auto stack = model::Stack::build(formats::read_manifest(dir).spec);  // a case, or FormatError naming what is wrong
  return model::estimate_cost(stack, model::resolve(stack));
}

std::vector<std::string> pending_cases(const std::vector<std::string>& targets, bool force, Costs& costs) {
  std::vector<std::string> out;
  for (const auto& d : formats::expand_case_dirs(targets)) {
    const auto dir = fs::absolute(d).lexically_normal().string();
    costs[dir] = case_cost(d);
    if (force || runner::recorded_status(d) != "done") out.push_back(dir);
  }
  return out;
}

}  // namespace

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

// The site's limits that shape a submission, from `scontrol show config`.
struct SiteLimits {
  long max_array_size = kDefaultMaxArraySize;
  long max_job_count = 0;  // 0: not said
};

SiteLimits site_limits(const SubmitOptions& o, std::vector<std::string>& notes) {
  // A dry run asks briefly: with no controller, scontrol waits (9 s and more) for nothing.
  const auto r = run_slurm({o.scontrol, "show", "config"}, o.dry_run ? 3.0 : 30.0);
  SiteLimits limits;
  if (o.dry_run && (!r.started || r.code != 0 || r.timed_out)) {  // no cluster here: SLURM's default
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

// The pending cases that are already queued (a task of an earlier submission still in the
// queue) or running (a granstack holds the case's lock): submitted again they would run twice.
std::set<std::string> busy_cases(const std::vector<std::string>& targets, const std::vector<std::string>& pending,
                                 const SubmitOptions& o, std::vector<std::string>& notes) {
  std::set<std::string> busy;
  for (const auto& c : pending) {
    if (os::CaseLock::holder(c)) busy.insert(c);
  }
  std::vector<RecordedSubmission> earlier;
  std::vector<std::string> ids;
  for (const auto& t : targets) {
    for (const auto& sub : read_records(t).submissions) {
      for (const auto& a : sub.arrays) ids.push_back(a.job_id);
      earlier.push_back(sub);
    }
  }
  if (ids.empty() || !os::find_program(o.squeue)) return busy;
  const auto queue = read_queue(ids, o.squeue);
  if (!queue.answered) {
    notes.push_back(fmt::format("the queue could not be read ({}): cases an earlier submission still has queued "
                                "cannot be told apart",
                                queue.error));
    return busy;
  }
  const std::set<std::string> wanted(pending.begin(), pending.end());
  for (const auto& sub : earlier) {
    const auto cases = sub.cases();
    const auto tasks = sub.case_tasks(cases.size());
    for (std::size_t i = 0; i < cases.size(); ++i) {
      if (queue.tasks.count(tasks[i]) != 0 && wanted.count(cases[i]) != 0) busy.insert(cases[i]);
    }
  }
  return busy;
}

fs::path next_submission_dir(const std::string& first_target, bool dry_run) {
  const auto base = fs::path(first_target) / "slurm";
  if (dry_run) return base / "dry-run";  // rewritten by every dry run: no numbered folder is spent
  for (int n = 1;; ++n) {
    const auto d = base / fmt::format("submit-{}", n);
    if (!fs::exists(d)) return d;
  }
}

std::string hms(double seconds) {
  const long s = static_cast<long>(std::ceil(seconds));
  return fmt::format("{:02}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
}

double task_seconds(const std::vector<double>& liggghts_seconds, int ranks) {
  double seconds = 0.0;
  for (const double s : liggghts_seconds) seconds += s;
  return std::max(kMinTaskSeconds, kTimeSafety * seconds / std::max(1, ranks));
}

// The job name: granstack and the sweep's name, in the characters SLURM shows plainly.
std::string job_name(const std::string& first_target) {
  auto name = fs::absolute(first_target).lexically_normal().filename().string();
  for (auto& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  }
  return "granstack-" + name.substr(0, 48);
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

std::string array_script(const Submission& sub, const ArrayJob& a, std::size_t index, const SubmitOptions& o) {
  std::string head = fmt::format("#!/bin/bash\n#SBATCH --array=0-{}{}\n#SBATCH --ntasks={}\n#SBATCH --cpus-per-task=1\n"
                                 "#SBATCH --time={}\n",
                                 a.tasks - 1, a.throttle > 0 ? fmt::format("%{}", a.throttle) : "", o.ranks,
                                 sbatch_value("--time", a.time));
  if (!o.partition.empty()) head += fmt::format("#SBATCH --partition={}\n", sbatch_value("--partition", o.partition));
  if (!o.account.empty()) head += fmt::format("#SBATCH --account={}\n", sbatch_value("--account", o.account));
  if (o.mem_mb) head += fmt::format("#SBATCH --mem={}\n", *o.mem_mb);
  std::string run = fmt::format("exec {} run --engine {} --np {}{}", sh_quote(o.granstack), o.engine, o.ranks, o.force ? " --force" : "");
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

std::string gather_script(const Submission& sub, const std::vector<std::string>& targets, const SubmitOptions& o) {
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

// sbatch --parsable; returns the job id. Never waits more than a minute: a controller at its
// MaxJobCount keeps sbatch retrying for much longer.
std::string sbatch(const std::string& script, const std::vector<std::string>& extra, const SubmitOptions& o) {
  const auto [user_dependency, user_args] = split_dependency(o.sbatch_args);
  std::vector<std::string> argv{o.sbatch, "--parsable"};
  std::string dependency;
  for (const auto& e : extra) {
    if (e.rfind("--dependency=", 0) == 0) dependency = e.substr(13);
  }
  for (const auto& e : extra) {
    if (e.rfind("--dependency=", 0) != 0) argv.push_back(e);
  }
  // Both must hold: SLURM's ',' joins dependencies with AND.
  const auto both = dependency.empty() ? user_dependency : user_dependency.empty() ? dependency : dependency + "," + user_dependency;
  if (!both.empty()) argv.push_back("--dependency=" + both);
  argv.insert(argv.end(), user_args.begin(), user_args.end());
  argv.push_back(script);
  const auto r = run_slurm(argv, 60.0);
  if (!r.started) throw SubmitError(fmt::format("{}; sbatch comes with the Debian package slurm-client", r.output));
  const auto out = lines(r.output);
  if (r.code != 0 || out.empty() || r.timed_out) throw SubmitError(fmt::format("sbatch refused {}: {}", script, r.output));
  return out.back().substr(0, out.back().find(';'));
}

json record(const Submission& s, int cases_per_task) {
  json arrays = json::array();
  for (const auto& a : s.arrays) {
    if (a.job_id.empty()) continue;  // not (yet) accepted
    arrays.push_back({{"script", a.script}, {"job_id", a.job_id}, {"first_case", a.first_case}, {"tasks", a.tasks},
                      {"time", a.time}, {"throttle", a.throttle}});
  }
  return {{"directory", s.directory}, {"submitted", formats::utc_timestamp()}, {"cases", s.cases.size()},
          {"cases_per_task", cases_per_task}, {"arrays", arrays}, {"gather_job_id", s.gather_job_id},
          {"time", s.time}, {"max_array_size", s.max_array_size}};
}

// Records the submission as it stands (in its directory and in every target), so an array
// SLURM accepted is never running unrecorded.
void save(const Submission& s, const std::vector<std::string>& targets, int cases_per_task, std::vector<std::string>& notes) {
  const auto entry = record(s, cases_per_task);
  formats::write_file_atomically(fs::path(s.directory) / "submission.json", entry.dump(2) + "\n");
  for (auto& moved : record_submission(targets, entry)) notes.push_back(std::move(moved));
}

}  // namespace

std::string estimate_task_time(const std::vector<std::string>& case_dirs, int ranks) {
  std::vector<double> seconds;
  for (const auto& d : case_dirs) seconds.push_back(case_cost(d).liggghts_seconds);
  return hms(task_seconds(seconds, ranks));
}

namespace {

// How many cases each task runs: as asked, or, when the controller has room for fewer tasks than
// the cases need (MaxJobCount), as many as fit, said in a note.
int cases_per_task(const SubmitOptions& o, std::size_t cases, const SiteLimits& limits, std::vector<std::string>& notes) {
  const long tasks = (static_cast<long>(cases) + o.cases_per_task - 1) / o.cases_per_task;
  if (limits.max_job_count <= 0 || o.dry_run) return o.cases_per_task;
  const long room = limits.max_job_count - jobs_in_controller(o) - 1;  // the gather job too
  if (tasks <= room) return o.cases_per_task;
  if (room <= 0) {
    throw SubmitError(fmt::format("the controller holds MaxJobCount = {} jobs already: nothing is submitted; wait for "
                                  "jobs to end and submit again",
                                  limits.max_job_count));
  }
  const int packed = static_cast<int>((static_cast<long>(cases) + room - 1) / room);
  if (o.cases_per_task_given) {
    throw SubmitError(fmt::format("{} tasks of {} cases exceed the {} jobs the controller has room for (MaxJobCount = "
                                  "{}): nothing is submitted; pass --cases-per-task {} or more",
                                  tasks, o.cases_per_task, room, limits.max_job_count, packed));
  }
  notes.push_back(fmt::format("{} cases in one-case tasks exceed the {} jobs the controller has room for (MaxJobCount = "
                              "{}): {} cases per task",
                              cases, room, limits.max_job_count, packed));
  return packed;
}

// The arrays: at most MaxArraySize tasks each, each task's time its own cases' estimate and the
// array's the longest; --max-parallel shared among the arrays, or the arrays run one after
// another where there are more arrays than it allows tasks.
void plan_arrays(Submission& sub, const SubmitOptions& o, int per_task, const Costs& costs) {
  const long tasks = (static_cast<long>(sub.cases.size()) + per_task - 1) / per_task;
  for (long first_task = 0; first_task < tasks; first_task += sub.max_array_size) {
    ArrayJob a;
    a.first_case = static_cast<int>(first_task * per_task);
    a.tasks = static_cast<int>(std::min(sub.max_array_size, tasks - first_task));
    double longest = 0.0;
    for (int t = 0; t < a.tasks && o.time.empty(); ++t) {
      std::vector<double> seconds;
      const long first = a.first_case + static_cast<long>(t) * per_task;
      for (long i = first; i < std::min<long>(first + per_task, static_cast<long>(sub.cases.size())); ++i) {
        seconds.push_back(costs.at(sub.cases[static_cast<std::size_t>(i)]).liggghts_seconds);
      }
      longest = std::max(longest, task_seconds(seconds, o.ranks));
    }
    a.time = o.time.empty() ? hms(longest) : o.time;
    sub.arrays.push_back(a);
  }
  const int n = static_cast<int>(sub.arrays.size());
  for (int i = 0; i < n; ++i) {
    auto& a = sub.arrays[static_cast<std::size_t>(i)];
    if (o.max_parallel <= 0) continue;
    a.throttle = o.max_parallel >= n ? o.max_parallel / n + (i < o.max_parallel % n ? 1 : 0) : o.max_parallel;
    a.after_previous = o.max_parallel < n && i > 0;
  }
  sub.time = sub.arrays.empty() ? "" : sub.arrays.front().time;
  for (const auto& a : sub.arrays) sub.time = std::max(sub.time, a.time);
}

// The gather's time: as given, else reading every dump at 100 MB/s, three times over, at least
// 10 minutes.
std::string gather_time(const SubmitOptions& o, const Costs& costs) {
  if (!o.time.empty()) return o.time;
  double bytes = 0.0;  // the table reads every case of the targets
  for (const auto& [dir, cost] : costs) bytes += cost.dump_bytes + cost.series_bytes;
  return hms(std::max(600.0, kTimeSafety * bytes / 100e6));
}

void write_files(const Submission& sub, const std::vector<std::string>& targets, const SubmitOptions& o) {
  const fs::path dir(sub.directory);
  // Everything is written (and every path checked for the scripts) before anything is submitted.
  std::vector<std::pair<fs::path, std::string>> files;
  std::string list;
  for (const auto& c : sub.cases) {
    sh_quote(c);  // a case list line holds no line break either
    list += c + "\n";
  }
  files.emplace_back(dir / "cases.txt", list);
  for (std::size_t i = 0; i < sub.arrays.size(); ++i) files.emplace_back(sub.arrays[i].script, array_script(sub, sub.arrays[i], i, o));
  if (o.gather) files.emplace_back(sub.gather_script, gather_script(sub, targets, o));
  if (o.dry_run) fs::remove_all(dir);
  fs::create_directories(dir);
  for (const auto& [path, text] : files) formats::write_file_atomically(path, text);
}

}  // namespace

Submission submit(const std::vector<std::string>& targets, const SubmitOptions& o) {
  if (targets.empty()) throw SubmitError("name the cases or sweeps to submit");
  if (o.cases_per_task < 1) throw SubmitError("--cases-per-task must be at least 1");
  const auto first = fs::absolute(targets.front()).lexically_normal().string();
  if (first.find('\\') != std::string::npos) {
    throw SubmitError(fmt::format("{} holds a backslash, which SLURM reads in a log path as 'no patterns' (every task's "
                                  "log would go to one file): rename it",
                                  first));
  }
  Submission sub;
  Costs costs;
  const auto pending = pending_cases(targets, o.force, costs);
  const auto busy = busy_cases(targets, pending, o, sub.notes);
  for (const auto& c : pending) (busy.count(c) != 0 ? sub.skipped : sub.cases).push_back(c);
  if (sub.cases.empty()) return sub;
  if (!o.dry_run && !os::find_program(o.sbatch)) {
    throw SubmitError(fmt::format("{} is not on PATH: install SLURM's client commands (Debian package slurm-client) or "
                                  "submit from a machine that has them; --dry-run writes the scripts without submitting",
                                  o.sbatch));
  }
  const auto limits = site_limits(o, sub.notes);
  sub.max_array_size = limits.max_array_size;
  SubmitOptions each = o;
  each.cases_per_task = cases_per_task(o, sub.cases.size(), limits, sub.notes);
  plan_arrays(sub, each, each.cases_per_task, costs);
  const auto dir = next_submission_dir(first, o.dry_run);
  sub.directory = dir.string();
  for (std::size_t i = 0; i < sub.arrays.size(); ++i) sub.arrays[i].script = (dir / fmt::format("array-{}.sbatch", i + 1)).string();
  if (o.gather) {
    sub.gather_script = (dir / "gather.sbatch").string();
    sub.gather_time = gather_time(o, costs);
  }
  write_files(sub, targets, each);
  if (o.dry_run) return sub;
  const auto name = job_name(first);
  std::vector<std::string> ids;
  try {
    for (auto& a : sub.arrays) {
      std::vector<std::string> extra{"--job-name=" + name, "--output=" + output_pattern(sub.directory, "task-%A_%a.out"),
                                     "--open-mode=append"};
      if (a.after_previous) extra.push_back("--dependency=afterany:" + ids.back());
      a.job_id = sbatch(a.script, extra, o);
      ids.push_back(a.job_id);
      save(sub, targets, each.cases_per_task, sub.notes);
    }
    if (o.gather) {
      sub.gather_job_id = sbatch(sub.gather_script, {"--job-name=" + name + "-gather", "--output=" + output_pattern(sub.directory, "gather.out"),
                                 "--open-mode=append", fmt::format("--dependency=afterany:{}", fmt::join(ids, ":"))}, o);
      save(sub, targets, each.cases_per_task, sub.notes);
    }
  } catch (const SubmitError& e) {
    if (ids.empty()) {  // nothing accepted: nothing of this submission is left
      std::error_code ec;
      fs::remove_all(dir, ec);
      throw;
    }
    throw SubmitError(fmt::format("{}\nthe {} array(s) SLURM accepted before (job {}) run and are recorded in {}; the "
                                  "rest was not submitted: run 'granstack submit' again once the cause is gone (it "
                                  "skips the cases already queued)",
                                  e.what(), ids.size(), fmt::join(ids, ", "), sub.directory));
  }
  return sub;
}

}  // namespace granstack::cluster
