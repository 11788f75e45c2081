#pragma once
// The granstack subcommands: each file in app/ adds one to the CLI11 parser and says how it runs.
#include <granstack/postproc/reduce.hpp>
#include <granstack/runner/engines.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <type_traits>

#include <cmath>

#include <functional>
#include <map>
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

// A number in [lo, hi] (CLI11's Range lets NaN through: every comparison with it is false).
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](const std::string& text) {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || v < lo || v > hi) {
          return fmt::format("'{}' is not a number from {:g} to {:g}", text, lo, hi);
        }
        return std::string();
      },
      fmt::format("FLOAT in [{:g} - {:g}]", lo, hi));
}

// A whole number in [lo, hi] ("1.5" is refused as no whole number, not as out of range); `why` is
// said of a number below lo.
inline CLI::Validator whole_range(long lo, long hi, std::string why = "") {
  return CLI::Validator(
      [lo, hi, why](const std::string& text) {
        long v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return fmt::format("'{}' is not a whole number", text);
        if (v < lo || v > hi) {
          return fmt::format("{} is not from {} to {}{}", v, lo, hi, v < lo && !why.empty() ? " (" + why + ")" : "");
        }
        return std::string();
      },
      fmt::format("INT in [{} - {}]", lo, hi));
}

// A flag that belongs to some engines given where none of them runs: "" when it is not given or one
// of `engines` runs; else why it is refused (the flag is never silently ignored).
inline std::string flag_for_engines(const CLI::App& cmd, const std::string& flag, const std::vector<std::string>& engines,
                                    const std::vector<std::string>& running) {
  const auto* option = cmd.get_option_no_throw(flag);
  if (option == nullptr || option->count() == 0) return "";
  for (const auto& e : running) {
    if (std::find(engines.begin(), engines.end(), e) != engines.end()) return "";
  }
  return fmt::format("{} is for {} and none runs here ({}): leave it out, or choose the engine it is for", flag,
                     fmt::join(engines, " or "), fmt::join(running, ", "));
}

// The first option given to `cmd` that is some engines' own (runner::engine_table()) where none of
// them is `running`: why it is refused, or "" when there is none.
inline std::string other_engines_option(const CLI::App& cmd, const std::vector<std::string>& running) {
  for (const auto& option : runner::engine_options()) {
    if (auto why = flag_for_engines(cmd, option, runner::engines_owning(option), running); !why.empty()) return why;
  }
  return "";
}

// An option naming engines (--engine, validate's --engines), bound to the table: its help the
// table's (then `note`), its values the table's names, refused with the names listed; the default
// the value `engine` holds, printed by CLI11 (none where it is empty: `note` says what then). Bound
// to runner::Engine, a name becomes its row's engine (CLI11's CheckedTransformer would also take an
// enumerator's number, "--engine 1"); bound to text, the name is kept.
template <typename T>
CLI::Option* add_engine_option(CLI::App* cmd, const std::string& flag, T& engine, const std::string& note = "") {
  constexpr bool to_engine = std::is_same_v<T, runner::Engine> || std::is_same_v<T, std::vector<runner::Engine>>;
  const auto help = runner::engine_list(true);
  const CLI::Validator names(
      [](std::string& text) {
        for (const auto& row : runner::engine_table()) {
          if (row.name != text) continue;
          if constexpr (to_engine) text = std::to_string(static_cast<int>(row.engine));
          return std::string();
        }
        return fmt::format("'{}' is no engine: give {}", text, runner::engine_list());
      },
      fmt::format("{{{}}}", fmt::join(runner::engine_names(), ",")));
  auto* option = cmd->add_option(flag, engine, note.empty() ? help : help + "; " + note)->transform(names)->type_name("TEXT");
  if constexpr (std::is_same_v<T, runner::Engine>) {
    option->default_str(runner::to_string(engine));
  } else if constexpr (std::is_same_v<T, std::vector<runner::Engine>>) {
    std::vector<std::string> defaults;
    for (const auto e : engine) defaults.push_back(runner::to_string(e));
    option->default_str(fmt::format("{}", fmt::join(defaults, ",")));
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!engine.empty()) option->capture_default_str();
  } else {
    option->default_str(fmt::format("{}", fmt::join(engine, ",")));
  }
  return option;
}

// The option naming an engine's program (its row's `program`: --liggghts, --lammps), bound to
// `path`, whose value CLI11 prints as the default; `note` follows the help.
inline CLI::Option* add_program_option(CLI::App* cmd, runner::Engine e, std::string& path, const std::string& note = "") {
  const auto& program = runner::engine_row(e).program;
  auto help = fmt::format("The {} executable (a name is looked up on PATH)", program.what);
  return cmd->add_option(program.flag, path, note.empty() ? help : help + "; " + note)->capture_default_str();
}

// The option naming each engine's program that runs one (--liggghts, --lammps), in the table's
// order, bound to `programs[engine]`, which starts as the row's default; `note(row)` follows each
// help ("" for none).
inline void add_program_options(CLI::App* cmd, std::map<runner::Engine, std::string>& programs,
                                const std::function<std::string(const runner::EngineRow&)>& note = {}) {
  for (const auto& row : runner::engine_table()) {
    if (row.program.flag.empty()) continue;
    add_program_option(cmd, row.engine, programs[row.engine] = row.program.name, note ? note(row) : "");
  }
}

// A subcommand: its parser and what runs it once the command line is parsed.
struct Command {
  CLI::App* parser = nullptr;
  std::function<int()> run;
};

Command add_generate(CLI::App& app, const std::vector<std::string>& argv);
Command add_run(CLI::App& app);
Command add_adopt(CLI::App& app);
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
