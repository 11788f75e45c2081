#include "records.hpp"
#include "scheduler.hpp"

#include <granstack/cluster/slurm.hpp>

#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/workers.hpp>
#include <granstack/os/process.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/runner/engines.hpp>
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

// The cost estimate of each case, by its absolute path: each manifest is read once.
using Costs = std::map<std::string, model::Cost>;

model::Cost case_cost(const formats::Case& c) { return c.cost(); }

// Every case's manifest is read and checked (thousands in a sweep: on every usable CPU), its cost
// estimated and its run record read; the first case that cannot be opened, in order, is the error,
// and then the first pending case whose contact model the engine lacks (its tasks would all fail).
std::vector<std::string> pending_cases(const std::vector<std::string>& targets, const SubmitOptions& o, Costs& costs) {
  const auto dirs = formats::expand_case_dirs(targets);
  std::vector<model::Cost> cost(dirs.size());
  std::vector<char> pending(dirs.size(), 0);
  std::vector<std::string> refused(dirs.size());
  const auto engine = runner::parse_engine(o.engine);
  os::for_shares(dirs.size(), os::usable_cpus(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto c = formats::Case::open(dirs[i]);  // a case, or FormatError naming what is wrong
      cost[i] = case_cost(c);
      pending[i] = o.force || !c.run_record().done();
      // The tasks run refsim by LIGGGHTS's rules.
      refused[i] = runner::case_refusal(engine, c.spec());
    }
  });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const auto dir = fs::absolute(dirs[i]).lexically_normal().string();
    costs[dir] = cost[i];
    if (pending[i] == 0) continue;
    if (!refused[i].empty()) {
      throw SubmitError(fmt::format("{}: {} cannot run it: {}; nothing is submitted", dirs[i], o.engine, refused[i]));
    }
    out.push_back(dir);
  }
  return out;
}

}  // namespace

namespace {

// The pending cases that are already queued (a task of an earlier submission still in the
// queue) or running (a granstack holds the case's lock): submitted again they would run twice.
std::set<std::string> busy_cases(const std::vector<std::string>& targets, const std::vector<std::string>& pending,
                                 const Scheduler& scheduler, std::vector<std::string>& notes) {
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
  if (ids.empty() || !scheduler.can_read_queue()) return busy;
  const auto queue = scheduler.queue(ids);
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
  for (const auto& d : case_dirs) seconds.push_back(case_cost(formats::Case::open(d)).liggghts_seconds);
  return hms(task_seconds(seconds, ranks));
}

namespace {

// How many cases each task runs: as asked, or, when the controller has room for fewer tasks than
// the cases need (MaxJobCount), as many as fit, said in a note.
int cases_per_task(const SubmitOptions& o, std::size_t cases, const SiteLimits& limits, const Scheduler& scheduler,
                   std::vector<std::string>& notes) {
  const long tasks = (static_cast<long>(cases) + o.cases_per_task - 1) / o.cases_per_task;
  if (limits.max_job_count <= 0 || o.dry_run) return o.cases_per_task;
  const long room = limits.max_job_count - scheduler.jobs_held() - 1;  // the gather job too
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

void write_files(const Submission& sub, const std::vector<std::string>& targets, const SubmitOptions& o,
                 const Scheduler& scheduler) {
  const fs::path dir(sub.directory);
  // Everything is written (and every path checked for the scripts) before anything is submitted.
  std::vector<std::pair<fs::path, std::string>> files;
  std::string list;
  for (const auto& c : sub.cases) {
    if (c.find_first_of("\r\n") != std::string::npos) {  // a case list line cannot hold one
      throw SubmitError(fmt::format("'{}' holds a line break, which a case list cannot carry; rename it", c));
    }
    list += c + "\n";
  }
  files.emplace_back(dir / "cases.txt", list);
  for (std::size_t i = 0; i < sub.arrays.size(); ++i) files.emplace_back(sub.arrays[i].script, scheduler.array_script(sub, sub.arrays[i], i, o));
  if (o.gather) files.emplace_back(sub.gather_script, scheduler.gather_script(sub, targets, o));
  if (o.dry_run) fs::remove_all(dir);
  fs::create_directories(dir);
  for (const auto& [path, text] : files) formats::write_file_atomically(path, text);
}

}  // namespace

Submission submit(const std::vector<std::string>& targets, const SubmitOptions& o) {
  if (targets.empty()) throw SubmitError("name the cases or sweeps to submit");
  if (o.cases_per_task < 1) throw SubmitError("--cases-per-task must be at least 1");
  const auto scheduler = make_scheduler({o.sbatch, o.scontrol, o.squeue, "sacct"});
  const auto first = fs::absolute(targets.front()).lexically_normal().string();
  scheduler->check_directory(first);
  Submission sub;
  Costs costs;
  const auto pending = pending_cases(targets, o, costs);
  const auto busy = busy_cases(targets, pending, *scheduler, sub.notes);
  for (const auto& c : pending) (busy.count(c) != 0 ? sub.skipped : sub.cases).push_back(c);
  if (sub.cases.empty()) return sub;
  if (!o.dry_run) scheduler->require_submit();
  const auto limits = scheduler->limits(o.dry_run, sub.notes);
  sub.max_array_size = limits.max_array_size;
  SubmitOptions each = o;
  each.cases_per_task = cases_per_task(o, sub.cases.size(), limits, *scheduler, sub.notes);
  plan_arrays(sub, each, each.cases_per_task, costs);
  const auto dir = next_submission_dir(first, o.dry_run);
  sub.directory = dir.string();
  for (std::size_t i = 0; i < sub.arrays.size(); ++i) sub.arrays[i].script = (dir / fmt::format("array-{}.sbatch", i + 1)).string();
  if (o.gather) {
    sub.gather_script = (dir / "gather.sbatch").string();
    sub.gather_time = gather_time(o, costs);
  }
  write_files(sub, targets, each, *scheduler);
  if (o.dry_run) return sub;
  const auto name = job_name(first);
  std::vector<std::string> ids;
  try {
    for (auto& a : sub.arrays) {
      JobRequest job{a.script, name, scheduler->array_log(), {}};
      if (a.after_previous) job.after.push_back(ids.back());
      a.job_id = scheduler->submit(job, o);
      ids.push_back(a.job_id);
      save(sub, targets, each.cases_per_task, sub.notes);
    }
    if (o.gather) {
      sub.gather_job_id = scheduler->submit({sub.gather_script, name + "-gather", "gather.out", ids}, o);
      save(sub, targets, each.cases_per_task, sub.notes);
    }
  } catch (const SubmitError& e) {
    if (ids.empty()) {  // nothing accepted: nothing of this submission is left
      std::error_code ec;
      fs::remove_all(dir, ec);
      throw;
    }
    throw SubmitError(fmt::format("{}\nthe {} array(s) {} accepted before (job {}) run and are recorded in {}; the "
                                  "rest was not submitted: run 'granstack submit' again once the cause is gone (it "
                                  "skips the cases already queued)",
                                  e.what(), ids.size(), scheduler->name(), fmt::join(ids, ", "), sub.directory));
  }
  return sub;
}

}  // namespace granstack::cluster
