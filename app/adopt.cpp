// granstack adopt: the case's deck run by hand (`liggghts -in in.stack` in the case's folder) or
// by the user's own scripts, taken as the case's run once its outputs are shown to be that
// deck's (runner::adopt_cases).
#include "commands.hpp"

#include <granstack/formats/manifest.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <memory>

namespace granstack::app {

namespace {

struct AdoptFlags {
  std::vector<std::string> cases;
  bool force = false;
};

int adopt(const AdoptFlags& f) {
  int rc = kOk;
  for (const auto& r : runner::adopt_cases(formats::expand_case_dirs(f.cases), f.force)) {
    switch (r.status) {
      case runner::RunStatus::done:
        fmt::print("adopted  {}  (LIGGGHTS run by hand, loop {:.3g} s; its log shows the case's deck run whole)\n",
                   r.case_dir, r.loop_seconds);
        break;
      case runner::RunStatus::skipped:
        fmt::print("skipped  {}  ({})\n", r.case_dir, r.message);
        break;
      default:
        fmt::print(stderr, "REFUSED  {}  {}\n", r.case_dir, r.message);
        rc = kBadFile;
    }
    std::fflush(stdout);
  }
  return rc;
}

}  // namespace

Command add_adopt(CLI::App& app) {
  auto f = std::make_shared<AdoptFlags>();
  auto* cmd = app.add_subcommand("adopt", "Take a case's deck run outside granstack (liggghts -in in.stack in its "
                                          "folder, or your own scripts) as its run, once its log and outputs show "
                                          "that deck, whole");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_flag("--force", f->force, "Adopt the outputs of a case whose run.json says done (its record is replaced)");
  return {cmd, [f] { return adopt(*f); }};
}

}  // namespace granstack::app
