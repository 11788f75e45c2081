// granstack reproduce: the study's figures and numbers in one command, with a report.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/runner/runner.hpp>
#include <granstack/study/engines.hpp>
#include <granstack/study/report.hpp>
#include <granstack/study/reproduce.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <map>
#include <memory>
#include <mutex>

namespace granstack::app {

namespace {

struct ReproduceFlags {
  study::ReproduceOptions options;
  std::map<runner::Engine, std::string> programs;  // each engine's program option (its row's)
};

int reproduce(ReproduceFlags& f) {
  auto& o = f.options;
  try {
    study::select(study::builtin_catalogue(), o.experiments, o.quick, o.full);
  } catch (const study::UnknownExperiment& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  }
  if (!o.against.empty()) {
    try {
      (void)study::read_other_report(o.against);
    } catch (const study::ReproduceError& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return kBadInput;
    }
  }
  StatusLine status;
  std::mutex mutex;
  if (status.active()) {
    o.on_progress = [&](const std::string& line) {
      const std::lock_guard lock(mutex);
      status.show("reproduce: " + line);
    };
  }
  o.on_event = [&](const std::string& line) {
    const std::lock_guard lock(mutex);
    status.clear();
    fmt::print("{}\n", line);
    std::fflush(stdout);
  };
  study::StudyResult result;
  try {
    result = study::reproduce(study::builtin_catalogue(), o);
  } catch (const study::AgainstError& e) {
    status.clear();
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  } catch (const study::ReproduceError& e) {
    status.clear();
    fmt::print(stderr, "error: {}\n", e.what());
    return kExists;
  }
  status.clear();
  if (result.report_kept) {
    fmt::print(stderr, "interrupted: {} case(s) stopped or not begun; the report in {} (of an earlier complete run) is "
                       "kept as it was; run the same command again to finish\n",
               result.interrupted_cases, o.output);
    return kCaseFailed;
  }
  if (result.validated) fmt::print("\n{}\n", study::validation_summary(result));
  fmt::print("\n{}\nreport: {}/report.md, {}/report.html, {}/report.json ({:.1f} s)\n", study::summary_text(result), o.output,
             o.output, o.output, result.wall_seconds);
  if (result.interrupted) {
    fmt::print(stderr, "interrupted: {} case(s) stopped or not begun (the report says so); run the same command again "
                       "to finish\n", result.interrupted_cases);
  }
  if (result.failed_cases > 0) {
    fmt::print(stderr, "{} case(s) failed or could not be reduced (see the report's case tables); run the same command "
                       "again to retry them\n",
               result.failed_cases);
    return kCaseFailed;
  }
  return kOk;
}

}  // namespace

Command add_reproduce(CLI::App& app) {
  auto f = std::make_shared<ReproduceFlags>();
  auto& o = f->options;
  auto* cmd = app.add_subcommand("reproduce", "Reproduce the study's figures and numbers, with a report");
  cmd->add_option("experiments", o.experiments, "Experiments to run [all: listed below]");
  // The list from the catalogue only when help is shown: parsing it costs every command's start.
  cmd->footer([] { return fmt::format("Experiments: {}", fmt::join(study::builtin_catalogue().names(), ", ")); });
  cmd->add_option("-o,--output", o.output, "The reproduction's directory (its cases are reused on a rerun)")
      ->check(output_directory())->required();
  cmd->add_option("-j,--jobs", o.jobs, "Cases run at the same time")->check(CLI::Range(1, 256))->capture_default_str();
  add_engine_option(cmd, "--engine", o.engine,
                    "by default the engine the directory's cases ran on, liggghts for a new reproduction");
  cmd->add_flag("--validate", o.validate, "Also run every case with the other engine and report the agreement");
  auto* quick = cmd->add_flag("--quick", o.quick, "The small subset CI runs (the experiments marked quick)");
  cmd->add_flag("--full", o.full,
                "Also the longer runs: the convergence study of the block height and the material sensitivity runs")
      ->excludes(quick);
  cmd->add_flag("--force", o.force, "Generate and run every case again");
  add_program_options(cmd, f->programs, [](const runner::EngineRow& row) {
    return row.engine == runner::RunOptions{}.engine ? "" : "for --engine " + row.name;  // but the default's
  });
  cmd->add_option("--against", o.against,
                  "Another engine's reproduction (its directory) to set this one beside: the report says which "
                  "statements change between the engines, by how much, and why")
      ->check(CLI::ExistingDirectory);
  return {cmd, [f, cmd] {
    // The engines that run (refsim checks a DEM code with --validate, LIGGGHTS checks refsim) are
    // known once the engine is chosen: --engine, else the directory's finished cases, else LIGGGHTS.
    f->options.refuse_engine_options = [cmd](const std::vector<std::string>& running) {
      return other_engines_option(*cmd, running);
    };
    for (const auto& [engine, program] : f->programs) f->options.programs[runner::to_string(engine)] = program;
    return reproduce(*f);
  }};
}

}  // namespace granstack::app
