#pragma once
// The granstack subcommands: each file in app/ adds one to the CLI11 parser and says how it runs.
#include <granstack/postproc/reduce.hpp>

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace granstack::app {

// Exit codes (docs/reference/commands.md, "Exit codes").
constexpr int kOk = 0;
constexpr int kCaseFailed = 1;  // a run failed, a case is in use, or a case could not be reduced
constexpr int kBadInput = 2;    // invalid spec, flag or value
constexpr int kExists = 3;      // an output exists: not replaced without --force, or never (not granstack's)
constexpr int kBadFile = 4;     // an input file is missing, malformed or inconsistent
constexpr int kDisagree = 5;    // validate: the engines differ by more than the tolerance
constexpr int kPhysics = 6;     // reduce: the results break a physical law they must obey
constexpr int kIoError = 7;     // a file or directory could not be read or written (a full disk, permissions)

// -o DIR: an empty name is no directory (refused as invalid input, not met as an I/O error).
inline CLI::Validator output_directory() {
  return CLI::Validator(
      [](const std::string& text) {
        return text.empty() ? std::string("the output directory's name is empty: name a directory, e.g. -o runs/a")
                            : std::string();
      },
      "DIR");
}

// A subcommand: its parser and what runs it once the command line is parsed.
struct Command {
  CLI::App* parser = nullptr;
  std::function<int()> run;
};

Command add_generate(CLI::App& app, const std::vector<std::string>& argv);
Command add_run(CLI::App& app);
Command add_decompose(CLI::App& app);
Command add_reduce(CLI::App& app);
Command add_table(CLI::App& app);
Command add_plot(CLI::App& app);
Command add_validate(CLI::App& app);
Command add_reproduce(CLI::App& app);
Command add_submit(CLI::App& app);
Command add_status(CLI::App& app);
Command add_export(CLI::App& app);
Command add_fields(CLI::App& app);
Command add_design(CLI::App& app);

// Reduces every case, with frame progress on a terminal; a failing case is reported on stderr
// and left out. Case names are made unique among `dirs` (the shortest distinguishing tail of
// their paths). Returns the exit code so far.
int reduce_all(const std::vector<std::string>& dirs, std::vector<postproc::CaseReduction>& results,
               const postproc::ReduceOptions& base = {});

// `rc`, or 128 + the signal when granstack was asked to stop (130 for SIGINT, 143 for SIGTERM).
int unless_interrupted(int rc);

}  // namespace granstack::app
