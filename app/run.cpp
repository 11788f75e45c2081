// granstack run: LIGGGHTS (or refsim) in each case directory.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/formats/manifest.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>

namespace granstack::app {

namespace {

struct RunFlags {
  std::vector<std::string> cases;
  runner::RunOptions options;  // the engine, the common options, and each engine's own (its row's group)
};

// The status line (on a terminal) and a line per case as it ends, flushed, so a log followed
// with tail -f shows each case when it finishes. Both write under `mutex`.
void show_progress(runner::RunOptions& o, StatusLine& status, std::mutex& mutex, int& rc) {
  if (status.active()) {
    o.on_progress = [&status, &mutex](const runner::ProgressSnapshot& s) {
      std::string line = fmt::format("run: {}/{} cases finished", s.finished, s.total);
      for (const auto& c : s.running) {
        const double frac = c.total_steps > 0 ? static_cast<double>(c.step) / static_cast<double>(c.total_steps) : 0.0;
        line += fmt::format(" | {} step {}/{} ({:.0f}%) ETA {}", c.name, c.step, c.total_steps, 100 * frac,
                            eta(c.elapsed, frac));
      }
      const std::lock_guard lock(mutex);
      status.show(line);
    };
  }
  o.on_case_done = [&status, &mutex, &rc](const runner::RunOutcome& r) {
    const std::lock_guard lock(mutex);
    status.clear();
    switch (r.status) {
      case runner::RunStatus::done:
        fmt::print("done     {}  ({:.1f} s wall, loop {:.3g} s, {:.3g} particle-steps/s)\n", r.case_dir, r.wall_seconds,
                   r.loop_seconds, r.particle_steps_per_second);
        break;
      case runner::RunStatus::skipped:
        fmt::print("skipped  {}  ({})\n", r.case_dir, r.message);
        break;
      case runner::RunStatus::failed:
        fmt::print(stderr, "FAILED   {}  {}\n", r.case_dir, r.message);
        rc = kCaseFailed;
        break;
      case runner::RunStatus::interrupted:
        fmt::print(stderr, "STOPPED  {}  ({}; run.json says interrupted: run it again to redo it)\n", r.case_dir,
                   r.message);
        break;
      case runner::RunStatus::not_started:
        fmt::print(stderr, "not run  {}  (granstack was asked to stop first)\n", r.case_dir);
        break;
    }
    std::fflush(stdout);
    std::fflush(stderr);
  };
}

// More threads or ranks than granstack's CPUs run far slower, not faster (measured by
// bench/oversubscription.sh, its record in bench/results/): said before the run.
void warn_if_oversubscribed(const runner::RunOptions& o, int cases) {
  const auto& row = runner::engine_row(o.engine);
  if (row.cpus == nullptr) return;
  const auto each = row.cpus(o);
  const int at_once = std::min(o.jobs, std::max(cases, 1));
  const int wanted = at_once * each.each;
  const int cpus = os::usable_cpus();
  if (wanted <= cpus) return;
  fmt::print(stderr, "warning: {} case(s) at once x {} {} = {} on the {} CPU(s) granstack may use: oversubscribed runs "
                     "are many times slower; lower -j or {}\n",
             at_once, each.each, each.unit, wanted, cpus, each.flag);
}

int run(RunFlags& f, const CLI::App& cmd) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  auto& o = f.options;
  for (const auto& row : runner::engine_table()) {
    if (row.check_options == nullptr) continue;
    if (const auto why = row.check_options(o); !why.empty()) {
      fmt::print(stderr, "error: {}\n", why);
      return kBadInput;
    }
  }
  if (const auto why = other_engines_option(cmd, {runner::to_string(o.engine)}); !why.empty()) {
    fmt::print(stderr, "error: {}\n", why);
    return kBadInput;
  }
  warn_if_oversubscribed(o, static_cast<int>(dirs.size()));
  StatusLine status;
  std::mutex mutex;
  int rc = kOk;
  show_progress(o, status, mutex, rc);
  runner::run_cases(dirs, o);
  status.clear();
  return rc;
}

// The options of the engines that run a program through MPI (--np), in one group: those rows
// that own the option.
void add_mpi_options(CLI::App* cmd, runner::RunOptions& o) {
  const auto owners = runner::engines_owning("--np");
  auto* mpi = cmd->add_option_group("MPI", fmt::format("For --engine {}", fmt::join(owners, " and ")));
  mpi->add_option("--np", o.ranks, "MPI ranks per case (mpirun when > 1)")->check(CLI::Range(1, 4096))->capture_default_str();
}

}  // namespace

// The options every engine takes, then each engine's own in its group of the help (the table's
// rows: its program, then what its row adds; a group's option given with another --engine is
// refused by name).
Command add_run(CLI::App& app) {
  auto f = std::make_shared<RunFlags>();
  auto& o = f->options;
  auto* cmd = app.add_subcommand("run", "Run LIGGGHTS (or refsim, or LAMMPS) on case directories (or sweep directories)");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  add_engine_option(cmd, "--engine", o.engine);
  cmd->add_option("-j,--jobs", o.jobs, "Cases run at the same time")->check(CLI::Range(1, 256))->capture_default_str();
  cmd->add_flag("--force", o.force, "Run cases again even if they finished");
  add_mpi_options(cmd, o);
  for (const auto& row : runner::engine_table()) {
    auto* group = cmd->add_option_group(row.name, "For --engine " + row.name);
    if (!row.program.flag.empty()) add_program_option(group, row.engine, o.programs[row.engine] = row.program.name);
    if (row.add_options != nullptr) row.add_options(*group, o);
  }
  return {cmd, [f, cmd] { return run(*f, *cmd); }};
}

int unless_interrupted(int rc) {
  const int signal = os::interrupt_signal();
  return signal != 0 ? os::exit_code_for_signal(signal) : rc;
}

}  // namespace granstack::app
