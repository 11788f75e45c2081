#pragma once
// Pieces of an input deck that LIGGGHTS's and LAMMPS's decks share (deck_parts.cpp), in the
// words of each program (DeckDialect).
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <string>
#include <string_view>

namespace granstack::generator {

// Where the two programs' input languages differ in what the shared pieces use.
struct DeckDialect {
  const char* radius;          // an atom-style variable's radius: LIGGGHTS `r`, LAMMPS a compute's
  const char* radius_setup;    // the lines that define it
  const char* reduce_options;  // after `compute ID all reduce`: LIGGGHTS brings it up to date at a run's end
  bool judge_in_thermo;        // the judge's computes printed in thermo (so that they are current)
  // The judge's per-sphere products kept once a frame by a fix ave/atom (which thermo, printing
  // the judge at other steps too, cannot read): else each is evaluated where it is named.
  bool frame_cache;
};
inline constexpr DeckDialect kLiggghtsDialect{"r", "", " update_on_run_end yes", false, true};
// LAMMPS has no update_on_run_end: its deck prints the judge's computes in thermo, which every
// run's last step invokes, so the variables read them current between runs.
// Its atom-style variables have no radius: a property/atom compute gives it.
inline constexpr DeckDialect kLammpsDialect{"c_gs_r", "compute         gs_r all property/atom radius\n", "", true, false};

// The deck's `group` line of a series group.
std::string group_command(const model::SeriesGroup& g);

// The deck's run of a case that stops at the blow's end, one dump interval at a time, judged over
// the group `particles` (the spheres: "all" but where a plate's body is an atom too).
std::string blow_end_run(const model::Stack& stack, const model::Resolution& res, const DeckDialect& dialect,
                         std::string_view particles = "all");

// The deck's processor grid: -var gs_ranks_x/y/z from `granstack run --np N`, or the program's own.
// `program` names the engine that chooses when the deck is run by hand ("LIGGGHTS", "LAMMPS").
std::string processors_lines(const model::Stack& stack, std::string_view program);

}  // namespace granstack::generator
