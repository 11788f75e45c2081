// granstack submit: a sweep's pending cases as SLURM job arrays.
#include "commands.hpp"

#include <granstack/cluster/slurm.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include <filesystem>
#include <memory>

namespace granstack::app {

namespace {

struct SubmitFlags {
  std::vector<std::string> targets;
  cluster::SubmitOptions options;
  bool cases_per_task_given = false;
};

// What the nodes' PATH must hold for the engines that run a program, from the engines' rows:
// "programs on the nodes' PATH: liggghts (LIGGGHTS), lmp (LAMMPS)".
std::string programs_on_path() {
  std::vector<std::string> programs;
  for (const auto& row : runner::engine_table()) {
    if (!row.program.name.empty()) programs.push_back(fmt::format("{} ({})", row.program.name, row.program.what));
  }
  return fmt::format("programs on the nodes' PATH: {}", fmt::join(programs, ", "));
}

int submit(SubmitFlags& f, const CLI::App& cmd) {
  auto& o = f.options;
  o.granstack = std::filesystem::read_symlink("/proc/self/exe").string();
  o.cases_per_task_given = f.cases_per_task_given;
  if (o.nodes > o.ranks) {
    fmt::print(stderr, "error: --nodes {} with --np {}: a node would hold no rank; give at most as many nodes as ranks\n",
               o.nodes, o.ranks);
    return kBadInput;
  }
  // --np and --nodes are the options of the engines that run an MPI program (their rows'): an
  // engine in granstack's own process would have its tasks ask SLURM for ranks it never uses.
  if (const auto why = other_engines_option(cmd, {o.engine}); !why.empty()) {
    fmt::print(stderr, "error: {}\n", why);
    return kBadInput;
  }
  cluster::Submission s;
  try {
    s = cluster::submit(f.targets, o);
  } catch (const cluster::SubmitError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kCaseFailed;
  }
  for (const auto& note : s.notes) fmt::print(stderr, "note: {}\n", note);
  if (!s.skipped.empty()) {
    fmt::print(stderr, "skipped {} case(s) already queued or running (not submitted twice; scancel them to submit them "
                       "anew): {}{}\n",
               s.skipped.size(), fmt::join(s.skipped.begin(), s.skipped.begin() + std::min<std::ptrdiff_t>(5, static_cast<std::ptrdiff_t>(s.skipped.size())), ", "),
               s.skipped.size() > 5 ? ", ..." : "");
  }
  if (s.cases.empty()) {
    fmt::print("nothing to submit: every case is done{} (--force submits the done ones again)\n",
               s.skipped.empty() ? "" : ", queued or running");
    return kOk;
  }
  std::size_t tasks = 0;
  for (const auto& a : s.arrays) tasks += static_cast<std::size_t>(a.tasks);
  const auto per_task = (s.cases.size() + tasks - 1) / std::max<std::size_t>(tasks, 1);
  fmt::print("{} {} cases in {} tasks of up to {} ({} array{}, MaxArraySize {}), at most {} per task; scripts in {}\n",
             o.dry_run ? "would submit" : "submitted", s.cases.size(), tasks, per_task, s.arrays.size(),
             s.arrays.size() == 1 ? "" : "s", s.max_array_size, s.time, s.directory);
  for (const auto& a : s.arrays) {
    fmt::print("  {}  {}\n", a.job_id.empty() ? "(dry run)" : "job " + a.job_id, a.script);
  }
  if (!s.gather_script.empty()) {
    fmt::print("  {}  {} (after the arrays: the table into {}/table)\n",
               s.gather_job_id.empty() ? "(dry run)" : "job " + s.gather_job_id, s.gather_script, s.directory);
  }
  return kOk;
}

}  // namespace

Command add_submit(CLI::App& app) {
  auto f = std::make_shared<SubmitFlags>();
  auto& o = f->options;
  auto* cmd = app.add_subcommand("submit", "Submit the cases not yet done as SLURM job arrays");
  cmd->add_option("cases", f->targets, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  add_engine_option(cmd, "--engine", o.engine, programs_on_path());
  cmd->add_option("--np", o.ranks, "MPI ranks per case (the task's --ntasks)")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--nodes", o.nodes,
                  "Nodes per task (sbatch --nodes) for a case bigger than one node: its --np ranks spread over them, "
                  "started by mpirun inside the allocation [as SLURM places them]")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--cases-per-task", o.cases_per_task, "Cases each array task runs, one after the other")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--max-parallel", o.max_parallel, "At most this many tasks at once (the array's %K) [no limit]")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--partition", o.partition, "SLURM partition [the site's default]");
  cmd->add_option("--time", o.time, "Wall time per task, HH:MM:SS [estimated from the cases, 3x the estimate, at least 5 min]")
      ->check(CLI::Validator(
          [](const std::string& text) {
            return cluster::parse_slurm_time(text)
                       ? std::string()
                       : fmt::format("'{}' is not a wall time SLURM takes above zero and below a year: give HH:MM:SS, "
                                     "MM, MM:SS or D-HH:MM:SS (00:00:00 would mean no limit at all)",
                                     text);
          },
          "TIME"));
  cmd->add_option("--mem", o.mem_mb, "Memory per task: MB, or with SLURM's units M, G or T (4G = 4096 MB) [the site's default]")
      ->transform(CLI::Validator(
          [](std::string& text) {
            const auto mb = cluster::parse_memory_mb(text);
            if (!mb) {
              return fmt::format("'{}' is not a memory size: give megabytes (4000) or a size with M, G or T (4G), "
                                 "above zero and at most 1024 T",
                                 text);
            }
            text = std::to_string(*mb);
            return std::string();
          },
          "SIZE"));
  cmd->add_option("--account", o.account, "SLURM account [the site's default]");
  cmd->add_option("--sbatch-arg", o.sbatch_args, "An argument passed to sbatch as it is (repeatable)");
  cmd->add_flag("--gather", o.gather, "Add a job that runs `table` over the targets once the arrays end");
  cmd->add_flag("--dry-run", o.dry_run, "Write the scripts and say what would be submitted; submit nothing");
  cmd->add_flag("--force", o.force, "Submit every case, done or not");
  return {cmd, [f, cmd] {
            f->cases_per_task_given = cmd->count("--cases-per-task") > 0;
            return submit(*f, *cmd);
          }};
}

}  // namespace granstack::app
