// granstack status: how a sweep stands, from its case directories (and squeue).
#include "commands.hpp"

#include <granstack/cluster/slurm.hpp>

#include <fmt/format.h>

#include <memory>

namespace granstack::app {

namespace {

struct StatusFlags {
  std::vector<std::string> targets;
};

int status(const StatusFlags& f) {
  const auto r = cluster::status(f.targets);
  fmt::print("{} cases: {} done, {} failed, {} running, {} interrupted, {} pending", r.cases.size(), r.done, r.failed,
             r.running, r.interrupted, r.pending);
  fmt::print("{}{}\n", r.changed > 0 ? fmt::format(", {} changed since their run", r.changed) : "",
             r.damaged > 0 ? fmt::format(", {} damaged", r.damaged) : "");
  for (const auto& c : r.cases) {
    if (c.status == "failed" || c.status == "interrupted" || c.status == "changed" || c.status == "damaged") {
      fmt::print("{:<12} {}  {}\n", c.status, c.dir, c.error);
    }
  }
  if (!r.job_ids.empty()) {
    fmt::print("last submission: job{} {}", r.job_ids.size() == 1 ? "" : "s", fmt::join(r.job_ids, ", "));
    if (!r.squeue_available) fmt::print(" (the queue is not shown)\n");
    else if (r.queue.empty()) fmt::print(" (none in the queue)\n");
    else fmt::print("; in the queue:\n  {}\n", fmt::join(r.queue, "\n  "));
  }
  for (const auto& note : r.notes) fmt::print(stderr, "note: {}\n", note);
  return r.failed + r.interrupted + r.changed + r.damaged > 0 ? kCaseFailed : kOk;
}

}  // namespace

Command add_status(CLI::App& app) {
  auto f = std::make_shared<StatusFlags>();
  auto* cmd = app.add_subcommand("status", "Count the done, failed, running, interrupted and pending cases (and those changed since their run)");
  cmd->add_option("cases", f->targets, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  return {cmd, [f] { return status(*f); }};
}

}  // namespace granstack::app
