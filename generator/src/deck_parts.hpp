#pragma once
// Pieces of an input deck that LIGGGHTS's and LAMMPS's decks share (case_writer.cpp), in the
// words of each program (DeckDialect).
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <string>

namespace granstack::generator {

// Where the two programs' input languages differ in what the shared pieces use.
struct DeckDialect {
  const char* radius;          // an atom-style variable's radius: LIGGGHTS `r`, LAMMPS `radius`
  const char* reduce_options;  // after `compute ID all reduce`: LIGGGHTS brings it up to date at a run's end
};
inline constexpr DeckDialect kLiggghtsDialect{"r", " update_on_run_end yes"};
// LAMMPS has no update_on_run_end: its deck prints the judge's computes in thermo, which every
// run's last step invokes, so the variables read them current between runs.
inline constexpr DeckDialect kLammpsDialect{"radius", ""};

// The deck's `group` line of a series group.
std::string group_command(const model::SeriesGroup& g);

// The deck's run of a case that stops at the blow's end, one dump interval at a time.
std::string blow_end_run(const model::Stack& stack, const model::Resolution& res, const DeckDialect& dialect);

// The deck's processor grid: -var gs_ranks_x/y/z from `granstack run --np N`, or the program's own.
std::string processors_lines(const model::Stack& stack);

}  // namespace granstack::generator
