#include "records.hpp"
#include "scheduler.hpp"

#include <granstack/cluster/slurm.hpp>
#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/process.hpp>
#include <granstack/os/workers.hpp>

#include <fmt/format.h>
#include <algorithm>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <optional>

namespace granstack::cluster {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// run.json's status and, for a failed run, the first line of its error. A damaged record is
// failed (it never counts as done), naming why it cannot be read. A done run whose case was
// edited since, or whose outputs are not those it wrote (quick check: sizes and times, digests
// where those differ), is "changed": its results would not be the case's.
CaseState read_state(const std::string& dir) {
  // Most cases of a big sweep are told by their run.json alone (the name generate gives it): the
  // manifest is read only for a finished run whose files are not as it left them.
  const formats::CaseFiles files;
  const auto record = formats::read_run_record(dir, files);
  if (!record.exists()) {
    // A case whose manifest is not even JSON would never run: damaged, not pending. (Only a
    // validating pass, no document built: status reads thousands of pending cases; run checks the
    // rest of the manifest before it starts.)
    const auto manifest = fs::path(dir) / "manifest.json";
    std::string why;
    try {
      const auto text = formats::read_file(manifest);
      if (!json::accept(text)) {
        why = fmt::format("{}: not valid JSON", manifest.string());
      } else if (const auto j = json::parse(text); !j.is_object() || !j.contains("schema") || !j.contains("spec")) {
        why = fmt::format("{}: not a granstack manifest (no schema or spec)", manifest.string());
      }
    } catch (const std::exception& e) {
      why = e.what();
    }
    if (!why.empty()) return {dir, "damaged", why.substr(0, why.find('\n')) + "; generate the case again (granstack generate --force)"};
    std::error_code ec;
    if (fs::exists(fs::path(dir) / files.log, ec)) return {dir, "pending", "its deck was run outside granstack"};
    return {dir, "pending", ""};
  }
  if (!record.done()) return {dir, record.status == "damaged" ? "failed" : record.status, record.error_line()};
  if (formats::files_untouched_since_run(dir, record)) return {dir, "done", ""};
  std::string why;
  try {
    why = formats::files_not_as_run(formats::Case::open(dir), record, formats::DigestCheck::quick);
  } catch (const std::exception& e) {  // an edited or unreadable manifest
    why = e.what();
  }
  if (why.empty()) return {dir, "done", ""};
  return {dir, "changed", why.substr(0, why.find('\n'))};
}

std::vector<std::string> job_ids_of(const RecordedSubmission& s) {
  std::vector<std::string> ids;
  for (const auto& a : s.arrays) ids.push_back(a.job_id);
  if (!s.gather_job_id.empty()) ids.push_back(s.gather_job_id);
  return ids;
}

// What the batch system says of the last submission's tasks that have left the queue: a case its task never
// ran is failed (naming the task's log), and an interrupted one says why SLURM stopped it.
void explain_with_scheduler(StatusReport& r, const RecordedSubmission& last, const QueueView& queue,
                            const Scheduler& scheduler) {
  std::map<std::string, Task> task_of;
  const auto cases = last.cases();
  const auto tasks = last.case_tasks(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) task_of[cases[i]] = tasks[i];
  std::vector<CaseState*> asked;
  for (auto& c : r.cases) {
    const auto it = task_of.find(fs::absolute(c.dir).lexically_normal().string());
    if (it == task_of.end() || it->second.first.empty() || queue.tasks.count(it->second) != 0) continue;
    if (c.status == "pending" || c.status == "interrupted") asked.push_back(&c);
  }
  if (asked.empty()) return;
  std::vector<std::string> ids;
  for (const auto& a : last.arrays) ids.push_back(a.job_id);
  const auto states = scheduler.ended(ids);
  for (auto* c : asked) {
    const auto& task = task_of.at(fs::absolute(c->dir).lexically_normal().string());
    const auto state = states.find(task);
    const auto name = fmt::format("{}_{}", task.first, task.second);
    const auto log = (fs::path(last.directory) / scheduler.task_log(task)).string();
    if (c->status == "interrupted") {
      if (state != states.end()) c->error += fmt::format(" ({}: task {} {})", scheduler.name(), name, state->second);
      continue;
    }
    c->status = "failed";
    c->error = fmt::format("its {0} task {1} ended{2} before granstack ran the case; see {3}", scheduler.name(), name,
                           state == states.end() ? fmt::format(" (how, {} no longer says)", scheduler.name()) : " " + state->second,
                           log);
  }
}

}  // namespace

StatusReport status(const std::vector<std::string>& targets, const std::string& squeue, const std::string& sacct,
                    const std::string& scontrol) {
  StatusReport r;
  // Each case on its own (its run.json, and the manifest of one not run): thousands of them on every
  // usable CPU.
  const auto dirs = formats::expand_case_dirs(targets);
  r.cases.resize(dirs.size());
  os::for_shares(dirs.size(), os::usable_cpus(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) r.cases[i] = read_state(dirs[i]);
  });
  for (auto& c : r.cases) {
    // Running by its run.json, yet no granstack holds the case's lock (the kernel drops it when
    // its holder ends in any way): the run was killed outright, or could not write its record.
    if (c.status == "running" && !os::CaseLock::holder(c.dir)) {
      c.status = "interrupted";
      c.error = "run.json says running, but no granstack holds the case's lock: its run was killed (SIGKILL, a time "
                "limit, a node failure) or could not write its final record (a full disk?); run it again";
    }
  }
  const auto records = targets.empty() ? Records{} : read_records(targets.front());
  if (!records.damage.empty()) r.notes.push_back(records.damage + ": the cases' states come from their folders alone");
  if (!records.submissions.empty()) {
    const auto& last = records.submissions.back();
    r.job_ids = job_ids_of(last);
    const auto scheduler = make_scheduler({"sbatch", scontrol, squeue, sacct});
    if (scheduler->can_read_queue()) {
      const auto queue = scheduler->queue(r.job_ids);
      r.squeue_available = queue.answered;
      r.queue = queue.lines;
      if (!queue.answered) {
        r.notes.push_back(fmt::format("the queue could not be read: {}", queue.error));
      } else {
        explain_with_scheduler(r, last, queue, *scheduler);
      }
    }
  }
  for (const auto& c : r.cases) {
    if (c.status == "done") ++r.done;
    else if (c.status == "failed") ++r.failed;
    else if (c.status == "running") ++r.running;
    else if (c.status == "interrupted") ++r.interrupted;
    else if (c.status == "changed") ++r.changed;
    else if (c.status == "damaged") ++r.damaged;
    else ++r.pending;
  }
  const auto by_hand = std::count_if(r.cases.begin(), r.cases.end(), [](const CaseState& c) {
    return c.status == "pending" && !c.error.empty();
  });
  if (by_hand > 0) {
    const auto first = std::find_if(r.cases.begin(), r.cases.end(), [](const CaseState& c) {
      return c.status == "pending" && !c.error.empty();
    });
    r.notes.push_back(fmt::format("{} pending case(s) hold a log of LIGGGHTS run outside granstack ({}{}): 'granstack "
                                  "adopt' takes such a run as the case's, once its log shows the case's deck run whole",
                                  by_hand, first->dir, by_hand > 1 ? ", ..." : ""));
  }
  return r;
}

}  // namespace granstack::cluster
