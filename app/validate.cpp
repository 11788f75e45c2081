// granstack validate: two engines (LIGGGHTS and refsim unless --engines says otherwise) on copies
// of each case, compared.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/formats/case.hpp>
#include <granstack/formats/deck.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/runner/engine_options.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

namespace granstack::app {

namespace {

struct ValidateFlags {
  std::vector<std::string> cases;
  double tolerance = postproc::kDefaultTolerance;
  int jobs = 1;
  std::map<runner::Engine, std::string> programs;  // each engine's program option (its row's)
  std::vector<runner::Engine> engines{runner::Engine::liggghts, runner::Engine::refsim};
};

// Runs the two engines on copies of each case (CASE/validate/ENGINE), each case locked for the
// whole comparison, and compares them.
int validate(const ValidateFlags& f) {
  if (f.engines.size() != 2 || f.engines[0] == f.engines[1]) {
    const auto names = runner::engine_names();
    fmt::print(stderr, "error: --engines takes two different engines of {}, e.g. --engines {},{}\n", runner::engine_list(),
               names.front(), names.back());
    return kBadInput;
  }
  const std::array engines{f.engines[0], f.engines[1]};
  // refsim beside LAMMPS runs LAMMPS's rules; beside LIGGGHTS, LIGGGHTS's.
  const bool lammps_rules = std::find(engines.begin(), engines.end(), runner::Engine::lammps) != engines.end();
  const auto dirs = formats::expand_case_dirs(f.cases);
  std::vector<os::CaseLock> locks;
  for (const auto& d : dirs) {
    const auto c = formats::Case::open(d);
    try {
      locks.push_back(c.lock("granstack validate"));
    } catch (const os::LockedError& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return kCaseFailed;
    }
    // refsim and LAMMPS run the manifest's physics, LIGGGHTS the deck: only granstack's own deck
    // is sure to be the same (see runner); say so before an engine spends its time.
    const auto& m = c.manifest();
    formats::check_rendered_files(d, m);  // an edited case would be validated as the manifest's
    if (!generator::has_default_deck(d, m)) {
      fmt::print(stderr, "error: {}/{} is not the deck granstack's own template gives for this case (a --template of "
                         "yours, or edited): the engines cannot be sure to run the same physics, so it cannot be validated; "
                         "generate the case without --template\n", d, m.files.deck);
      return kCaseFailed;
    }
    // A contact model one of the engines lacks: refused before anything is copied.
    for (const auto engine : engines) {
      if (const auto why = runner::case_refusal(engine, c.spec(), lammps_rules); !why.empty()) {
        fmt::print(stderr, "error: {}: {} cannot run it: {}\n", d, runner::to_string(engine), why);
        return kCaseFailed;
      }
    }
    // Both copies' places are checked before either engine spends its time.
    for (const auto engine : engines) {
      const auto copy = runner::copy_dir(d, engine);
      if (const auto why = formats::why_not_replaceable(copy, formats::kGenerate); !why.empty()) {
        throw formats::RefusedError(fmt::format("cannot make the copy {}: {}; move it away first", copy, why));
      }
    }
  }
  runner::RunOptions o;
  o.jobs = f.jobs;
  o.programs = f.programs;
  StatusLine status;
  int rc = kOk;
  o.own<runner::RefsimOptions>().lammps_rules = lammps_rules;
  for (const auto engine : engines) {
    const auto what = "validate: " + runner::to_string(engine) + " runs";
    o.on_progress = [&status, what](const runner::ProgressSnapshot& s) { status.count(what, s.finished, s.total); };
    for (const auto& r : runner::run_copies(dirs, engine, o)) {
      if (r.status == runner::RunStatus::failed) {
        status.clear();
        fmt::print(stderr, "FAILED   {}  {}\n", r.case_dir, r.message);
        rc = kCaseFailed;
      }
    }
    if (os::interrupt_signal() != 0) break;
  }
  status.clear();
  if (const int signal = os::interrupt_signal(); signal != 0) {
    fmt::print(stderr, "validate: stopped by signal {} before the engines were compared; the copies made so far are in "
                       "each case's validate/ folder, and 'granstack validate' makes them anew\n",
               signal);
    return rc;
  }
  if (rc != kOk) return rc;
  for (const auto& d : dirs) {
    const auto c = postproc::compare_runs(runner::copy_dir(d, engines[0]), runner::copy_dir(d, engines[1]));
    fmt::print("{}", postproc::format_comparison(c, runner::to_string(engines[0]), runner::to_string(engines[1]), f.tolerance));
    if (!c.disagreement(f.tolerance).empty()) rc = kDisagree;
  }
  return rc;
}

}  // namespace

Command add_validate(CLI::App& app) {
  auto f = std::make_shared<ValidateFlags>();
  auto* cmd = app.add_subcommand("validate", "Run two engines (LIGGGHTS and refsim by default) on the same cases and "
                                             "compare them");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--tolerance", f->tolerance,
                  "Largest accepted difference of any dumped column, series column or the output fraction, "
                  "relative to max(|first|, |second|, a physical floor) [1e-7: round-off, see docs/reference/commands.md]")
      ->check(CLI::Validator(
          [](const std::string& text) {
            double t = 0.0;
            const bool number = CLI::detail::lexical_cast(text, t);
            return number && std::isfinite(t) && t > 0.0 && t < 1.0
                       ? std::string()
                       : fmt::format("'{}' is not a relative tolerance: give a number above 0 and below 1 (1e-7 is "
                                     "round-off; a difference is relative to the larger value)",
                                     text);
          },
          "TOLERANCE"));
  cmd->add_option("-j,--jobs", f->jobs, "Cases run at the same time")->check(CLI::Range(1, 256))->capture_default_str();
  add_program_options(cmd, f->programs);
  add_engine_option(cmd, "--engines", f->engines, "the two compared, separated by a comma")->delimiter(',')->expected(2);
  return {cmd, [f, cmd] {
    if (const auto why = other_engines_option(*cmd, {runner::to_string(f->engines[0]), runner::to_string(f->engines[1])});
        !why.empty()) {
      fmt::print(stderr, "error: {}\n", why);
      return kBadInput;
    }
    return validate(*f);
  }};
}

}  // namespace granstack::app
