#pragma once
// What a run's deck may do, held to the deck granstack's own template gives for the case (the
// reference). Three kinds of command:
// - the reference's own: its time step, contact model, walls, materials, integrator, gravity,
//   groups, computes, dump and series, settings and runs. A deck runs each exactly as the
//   reference does (numbers compared by value), each once, and all of them before its first
//   run; a fix, compute, dump or group of the reference's name is its (never redefined, never
//   removed);
// - commands that change nothing the results are labelled with: variables, prints, ifs, jumps,
//   labels, includes, thermo output, regions, computes and groups of other names;
// - every other command (a fix, a dump, displace_atoms, ...) only where the spec lists it in
//   deck_additions ("fix viscous", "displace_atoms"): the run then names it.
// No command writes outside the case, or over a file of the case the reference's commands write.
#include <granstack/formats/case.hpp>
#include <granstack/formats/executed.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

struct DeckProblem {
  std::string where;  // "in.stack:57"
  std::string what;   // what the command does wrong
  std::string fix;    // what to do about it
  std::string text() const { return where + ": " + what + "; " + fix; }
};

struct DeckVerdict {
  std::vector<DeckProblem> problems;
  // The commands the spec's deck_additions let through, each "TEXT (WHERE)".
  std::vector<std::string> additions;
  bool ok() const { return problems.empty(); }
  // Each problem on a line of its own ("\n    WHERE: WHAT", at most `most`, then how many more),
  // then each different remedy ("\n  to mend: ...").
  std::string summary(std::size_t most = 8) const;
};

// The kind a spec's deck_additions names a command by: "fix STYLE", "compute STYLE" and
// "dump STYLE" for those three, the command word for any other.
std::string command_kind(const std::vector<std::string>& words);

// A run's executed commands (follow_log) held to `reference`, the text of the deck
// granstack's own template gives for the case and engine; every rule above, counts and order
// included. A reading that stopped before its end is itself a problem.
DeckVerdict hold_executed(const Case& c, const ExecutedScript& ran, std::string_view reference);

// A deck's own lines, before it runs (`name` names it in problems): each command without a
// substitution (and each command an if of it names) held as above, as far as one command can be
// judged alone; what runs through substitutions, includes and loops is held after the run.
DeckVerdict hold_literal(const Case& c, std::string_view deck, const std::string& name, std::string_view reference);

}  // namespace granstack::formats
