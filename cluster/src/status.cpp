#include "slurm_commands.hpp"

#include <granstack/cluster/slurm.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/process.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace granstack::cluster {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// run.json's status and, for a failed run, the first line of its error.
CaseState read_state(const std::string& dir) {
  CaseState s{dir, "pending", ""};
  const auto path = fs::path(dir) / "run.json";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return s;
  try {
    const auto j = json::parse(formats::read_file(path));
    s.status = j.value("status", "pending");
    const auto error = j.value("error", std::string());
    s.error = error.substr(0, error.find('\n'));
  } catch (const std::exception& e) {
    s.status = "failed";
    s.error = fmt::format("run.json cannot be read: {}", e.what());
  }
  return s;
}

// The job ids of the last submission recorded under the first target.
std::vector<std::string> last_job_ids(const std::string& target) {
  const auto path = fs::path(target) / "slurm" / "submissions.json";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return {};
  const auto all = json::parse(formats::read_file(path));
  if (!all.is_array() || all.empty()) return {};
  std::vector<std::string> ids;
  for (const auto& a : all.back().at("arrays")) ids.push_back(a.at("job_id").get<std::string>());
  const auto gather = all.back().value("gather_job_id", std::string());
  if (!gather.empty()) ids.push_back(gather);
  return ids;
}

}  // namespace

StatusReport status(const std::vector<std::string>& targets, const std::string& squeue) {
  StatusReport r;
  for (const auto& d : formats::expand_case_dirs(targets)) r.cases.push_back(read_state(d));
  if (!targets.empty()) r.job_ids = last_job_ids(targets.front());
  if (!r.job_ids.empty() && os::find_program(squeue)) {
    const auto q = run_slurm({squeue, "-h", "-j", fmt::format("{}", fmt::join(r.job_ids, ",")), "-o", "%i %T %M %R"});
    // squeue exits non-zero when none of the jobs is known any more: an empty queue.
    r.squeue_available = q.started;
    if (q.code == 0) r.queue = lines(q.output);
  }
  for (auto& c : r.cases) {
    // Running by its run.json, yet no granstack holds the case's lock (the kernel drops it when
    // its holder ends in any way): the run was killed outright, or could not write its record.
    if (c.status == "running" && !os::CaseLock::holder(c.dir)) {
      c.status = "interrupted";
      c.error = "run.json says running, but no granstack holds the case's lock: its run was killed (SIGKILL, a time "
                "limit, a node failure) or could not write its final record (a full disk?); run it again";
    }
    if (c.status == "done") ++r.done;
    else if (c.status == "failed") ++r.failed;
    else if (c.status == "running") ++r.running;
    else if (c.status == "interrupted") ++r.interrupted;
    else ++r.pending;
  }
  return r;
}

}  // namespace granstack::cluster
