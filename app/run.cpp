// granstack run: LIGGGHTS (or refsim) in each case directory.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/formats/manifest.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/refsim/system.hpp>
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
  std::string engine = "liggghts";
  int jobs = 1;
  int ranks = 1;
  std::string grid;
  int threads = 1;
  std::string kernel = "auto";
  bool force = false;
  std::string liggghts = default_program(runner::Engine::liggghts);
  std::string lammps = default_program(runner::Engine::lammps);
  std::string lammps_template;
  std::string contact_rules = "liggghts";
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
  const bool refsim = o.engine == runner::Engine::refsim;
  const int each = refsim ? o.threads : o.ranks;
  const int wanted = std::min(o.jobs, std::max(cases, 1)) * each;
  const int cpus = os::usable_cpus();
  if (wanted <= cpus) return;
  fmt::print(stderr, "warning: {} case(s) at once x {} {} = {} on the {} CPU(s) granstack may use: oversubscribed runs "
                     "are many times slower; lower -j or {}\n",
             std::min(o.jobs, std::max(cases, 1)), each, refsim ? "threads" : "MPI ranks", wanted, cpus,
             refsim ? "--threads" : "--np");
}

// --kernel's values: auto, reference and the vector instruction sets this CPU runs.
std::vector<std::string> kernel_choices() {
  std::vector<std::string> choices{"auto", "reference"};
  for (const auto& k : refsim::vector_kernels()) choices.push_back(k);
  return choices;
}

// "4,4,1" or "4x4x1": ranks along x, y and z.
std::optional<std::array<int, 3>> parse_grid(const std::string& text) {
  std::array<int, 3> g{};
  std::size_t at = 0;
  for (std::size_t d = 0; d < 3; ++d) {
    std::size_t used = 0;
    try {
      g[d] = std::stoi(text.substr(at), &used);
    } catch (const std::exception&) {
      return std::nullopt;
    }
    at += used;
    if (g[d] < 1 || (d < 2 && (at >= text.size() || (text[at] != ',' && text[at] != 'x')))) return std::nullopt;
    ++at;
  }
  if (at != text.size() + 1) return std::nullopt;
  return g;
}

int run(const RunFlags& f, const CLI::App& cmd) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  runner::RunOptions o;
  o.jobs = f.jobs;
  o.ranks = f.ranks;
  if (!f.grid.empty()) {
    const auto grid = parse_grid(f.grid);
    if (!grid || (*grid)[0] * (*grid)[1] * (*grid)[2] != f.ranks) {
      fmt::print(stderr, "error: --grid {}: give three whole numbers of ranks along x, y and z whose product is --np ({}), "
                 "e.g. --grid 4,4,1 with --np 16\n", f.grid, f.ranks);
      return kBadInput;
    }
    o.grid = *grid;
  }
  o.threads = f.threads;
  o.kernel = f.kernel;
  o.force = f.force;
  o.liggghts = f.liggghts;
  o.lammps = f.lammps;
  o.lammps_template = f.lammps_template;
  o.engine = runner::parse_engine(f.engine);
  if (const auto why = other_engines_option(cmd, {f.engine}); !why.empty()) {
    fmt::print(stderr, "error: {}\n", why);
    return kBadInput;
  }
  o.lammps_rules = f.contact_rules == "lammps";
  warn_if_oversubscribed(o, static_cast<int>(dirs.size()));
  StatusLine status;
  std::mutex mutex;
  int rc = kOk;
  show_progress(o, status, mutex, rc);
  runner::run_cases(dirs, o);
  status.clear();
  return rc;
}

}  // namespace

// The options every engine takes, then each engine's own in its group of the help (the table's
// rows: a group's option given with another --engine is refused by name).
Command add_run(CLI::App& app) {
  auto f = std::make_shared<RunFlags>();
  auto* cmd = app.add_subcommand("run", "Run LIGGGHTS (or refsim, or LAMMPS) on case directories (or sweep directories)");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  add_engine_option(cmd, "--engine", f->engine);
  cmd->add_option("-j,--jobs", f->jobs, "Cases run at the same time")->check(CLI::Range(1, 256))->capture_default_str();
  cmd->add_flag("--force", f->force, "Run cases again even if they finished");
  auto* mpi = cmd->add_option_group("MPI", "For --engine liggghts and lammps");
  mpi->add_option("--np", f->ranks, "MPI ranks per case (mpirun when > 1)")->check(CLI::Range(1, 4096))->capture_default_str();
  auto* liggghts = cmd->add_option_group("liggghts", "For --engine liggghts");
  add_program_option(liggghts, runner::Engine::liggghts, f->liggghts);
  liggghts->add_option("--grid", f->grid,
                       "LIGGGHTS's MPI processor grid, ranks along x,y,z (product --np), e.g. 4,4,1; by default the grid "
                       "whose busiest rank holds the fewest spheres, owned and ghost (run.json's \"decomposition\")");
  auto* refsim = cmd->add_option_group("refsim", "For --engine refsim");
  refsim->add_option("--threads", f->threads,
                     "Threads per case (results do not depend on it; where a CPU is left over, refsim writes its outputs "
                     "on one more)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  refsim->add_option("--kernel", f->kernel,
                     fmt::format("refsim's kernels: auto (the best vector instruction set this CPU runs), reference "
                                 "(scalar) or one of this CPU's: {}; all give the same bits",
                                 fmt::join(refsim::vector_kernels(), ", ")))
      ->check(CLI::IsMember(kernel_choices()))
      ->capture_default_str();
  refsim->add_option("--contact-rules", f->contact_rules,
                     "liggghts (the case's deck, LIGGGHTS's contact law to the bit) or lammps (the same spec as LAMMPS "
                     "runs it: docs/explanation/lammps.md)")
      ->check(CLI::IsMember({"liggghts", "lammps"}))
      ->capture_default_str();
  auto* lammps = cmd->add_option_group("lammps", "For --engine lammps");
  add_program_option(lammps, runner::Engine::lammps, f->lammps);
  lammps->add_option("--lammps-template", f->lammps_template,
                     "A template of yours for the LAMMPS deck instead of templates/in.lammps.tmpl")
      ->check(CLI::ExistingFile);
  return {cmd, [f, cmd] { return run(*f, *cmd); }};
}

int unless_interrupted(int rc) {
  const int signal = os::interrupt_signal();
  return signal != 0 ? os::exit_code_for_signal(signal) : rc;
}

}  // namespace granstack::app
