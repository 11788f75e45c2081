#pragma once
// The engines granstack runs a case on, one row each: `--engine` is bound to this table, and a
// command-line option that is some engines' own is refused by name where none of them runs. A
// fourth engine is its file (a CaseEngine, runner/src/engine.hpp), its enumerator and its row in
// runner/src/engines.cpp.
#include <granstack/model/contact.hpp>
#include <granstack/runner/runner.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::runner {

class CaseEngine;  // runner/src/engine.hpp

struct EngineRow {
  Engine engine;
  std::string name;   // as flags, run.json and folder names spell it
  std::string help;   // what it is, in --engine's help
  // The command-line options that are its own, in every command that has them (an option several
  // engines share, as --np, is in each of their rows).
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
};

// Every engine, in the order --engine's help lists them.
const std::vector<EngineRow>& engine_table();
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

}  // namespace granstack::runner
