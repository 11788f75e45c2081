#pragma once
// The engines granstack runs a case on, one row each: `--engine` is bound to this table, `run`'s
// help has a group of options per row, and a command-line option that is some engines' own is
// refused by name where none of them runs. A fourth engine is its file (a CaseEngine,
// runner/src/engine.hpp, with its options struct and group) and its row: in engine_table()
// (runner/src/engines.cpp) with an enumerator, or added from its own file by add_engine().
#include <granstack/model/contact.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/runner/runner.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace CLI {
class App;
}

namespace granstack::runner {

class CaseEngine;  // runner/src/engine.hpp

struct EngineRow {
  Engine engine;
  std::string name;   // as flags, run.json and folder names spell it
  std::string help;   // what it is, in --engine's help
  // The command-line options that are its own, in every command that has them (an option several
  // engines share, as --np, is in each of their rows; submit's --nodes is an MPI program's).
  std::vector<std::string> options;
  // The program it runs, where it runs one (LIGGGHTS, LAMMPS; refsim runs in granstack's process):
  // the option naming its executable, the name looked up on PATH by default, what it is.
  struct Program {
    std::string flag, name, what;
  } program;
  std::unique_ptr<CaseEngine> (*make)();  // its factory
  // What of a contact model it cannot run on any machine, by the contact rules it runs (its own;
  // refsim LIGGGHTS's, or LAMMPS's with `lammps_rules`), or "".
  std::string_view (*refusal)(const model::ContactModel& m, bool lammps_rules);
  // Adds its own options but its program's (those `options` lists) to `group`, `run`'s group for
  // it, bound to `o`'s own struct for the engine (RunOptions::own); nullptr: none.
  void (*add_options)(CLI::App& group, RunOptions& o) = nullptr;
  // Why the options `run` was given cannot run on it (LIGGGHTS's --grid against --np), said before
  // any case; "" where they can. It completes what needs several options (the grid from its text).
  // nullptr: nothing to check.
  std::string (*check_options)(RunOptions& o) = nullptr;
  // The CPUs each case of it takes, for the warning before an oversubscribed run.
  struct Cpus {
    int each = 1;
    std::string unit, flag;  // "MPI ranks", "--np"
  };
  Cpus (*cpus)(const RunOptions& o) = nullptr;
  // Whether it carries a protected plate on a mount under the stack (model::StackSpec::plate_mass);
  // an engine that does not refuses such a case (case_refusal).
  bool carries_plate = false;
};

// Every engine, in the order --engine's help lists them.
const std::vector<EngineRow>& engine_table();
// Adds an engine defined in a file of its own (`row.engine` is given the next enumerator's value,
// returned): called before any command line is read, from a static initialiser of that file.
Engine add_engine(EngineRow row);
// Their names as a sentence lists them: "liggghts, refsim or lammps"; `with_help`, each followed by
// what it is (--engine's help): "liggghts (the real DEM code), refsim (...) or lammps (...)".
std::string engine_list(bool with_help = false);
const EngineRow& engine_row(Engine e);
// The engines whose own `option` is (empty: every engine takes it).
std::vector<std::string> engines_owning(const std::string& option);
// Every option some engine owns.
std::vector<std::string> engine_options();
// What engine `e` cannot run of a contact model on any machine (its row's refusal), or "".
std::string_view model_refusal(Engine e, const model::ContactModel& m, bool lammps_rules = false);
// What engine `e` cannot run of a case's spec: its contact model (model_refusal), or a protected
// plate where its row does not carry one; "" where it can run it.
std::string case_refusal(Engine e, const model::StackSpec& s, bool lammps_rules = false);

}  // namespace granstack::runner
