#pragma once
// refsim's fast evaluation mode: a case run start to end with no files at all, reporting the
// quantities reduce takes from the same run's dump and series (the output fraction and the
// bottom wall's peak force), equal to them to round-off (tests/refsim/test_in_situ.cpp). The
// design search evaluates thousands of stacks this way.
#include <granstack/model/protection.hpp>
#include <granstack/model/yield.hpp>
#include <granstack/refsim/system.hpp>

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace granstack::model {
class Stack;
}

namespace granstack::refsim {

struct InSituResult;

struct InSituOptions {
  int threads = 1;
  std::string kernel = "auto";
  // Asked between the series' samples (every series_every steps): true stops the run, which then
  // throws InSituStopped (a signal: the design search abandons the design and ends).
  std::function<bool()> stop;
  // Run on past the resolution's steps, up to model::blow_end_cap_steps, and stop at the dump
  // frame where the blow ended (model::BlowEnd): the run is then exactly what a case of
  // duration steps x dt with the same dump_every and series_every gives (the design search).
  bool stop_at_blow_end = false;
  double cap_durations = model::kBlowEndCapDurations;  // the cap, in automatic durations
  // Stopping at the blow's end: stop as soon as the blow can no longer end by the cap, which is
  // certain at a frame where the condition's earliest hold (from the frame it began holding, or the
  // next frame when it does not hold) would end past the cap. The run is censored either way; its
  // measures are then taken to that frame, not to the cap (the design search's shortcut, #50).
  bool abandon_when_censored = false;
  // Asked every kSettleEvery series samples with the result so far (peak_wall_force, wall_force,
  // wall_force_interval, crush, penetration, yield_ratio and output_peak_fraction over the run up to
  // then): true stops the run there, settled (InSituResult::settled_at; the design search's
  // shortcut when the measures so far already decide the design, #50).
  std::function<bool(const InSituResult& so_far)> settle;
};
inline constexpr long kSettleEvery = 64;

class InSituStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct InSituResult {
  double e_in = 0.0;             // J
  // As reduce's output_fraction: with a free bottom the output sphere's kinetic energy at the
  // last step / E_in; against a bottom wall its peak over the series' samples / E_in.
  double output_fraction = 0.0;
  double output_peak_fraction = 0.0;        // the output sphere's peak over the samples / E_in
  // reduce's output_fraction_bottom_row: the whole bottom row's kinetic energy in the last dump
  // frame / E_in (what crosses the bottom face, not one sphere's share of it).
  double bottom_row_fraction = 0.0;
  // At the end of the run the output sphere touches no sphere (and with a free bottom has
  // left the lattice): its output fraction is final. reduce warns where it is not.
  bool output_separated = false;
  // When the output sphere's energy last changed (model::last_output_change, as reduce takes it
  // from the series), and whether that leaves it final (model::output_settled; always with a wall).
  double output_last_change_time = 0.0;  // s
  bool output_settled = true;
  // The stack's momentum along z at the last dump step over the striker's m v (reduce's
  // final_momentum_ratio); with a wall, output_settled is model::wall_load_settled.
  double final_momentum_ratio = 0.0;
  double run_time = 0.0;                 // s, steps x dt
  std::optional<double> peak_wall_force;    // N: reduce's peak_wall_force (bottom wall only)
  double peak_wall_force_time = 0.0;        // s
  // The bottom wall's force at every series sample (every series_every steps from series_every
  // on, wall_force_interval apart): what model::peak_window_impulse reads, as reduce does.
  std::vector<double> wall_force;
  std::vector<double> plate_acceleration;  // over a protected plate, at the same samples (m/s^2)
  double wall_force_interval = 0.0;         // s
  // model::CrushMeter over the dump's frames (step 0 to the last, every dump_every), as reduce:
  // the stack's crush and the striker's penetration below its initial top surface.
  double crush = 0.0;                       // m
  double penetration = 0.0;                 // m
  // model::YieldMeter over the same frames, as reduce: the largest contact pressure over first
  // yield (none: the contacts are not Hertz's), and where and when.
  std::optional<double> yield_ratio;
  model::YieldPeak yield;
  // When the blow ended (model::BlowEnd, judged at every dump frame), or none within the run; and
  // why not.
  std::optional<double> blow_end_time;      // s
  std::string blow_not_ended;
  // abandon_when_censored: the frame's step at which the run stopped, its blow certain not to end
  // by the cap (none: it ran to its end or its cap).
  std::optional<long> abandoned_at;
  // settle: the step at which it stopped the run (none: it did not). Its measures are then over the
  // run up to that step.
  std::optional<long> settled_at;
  // Where the energy is at the run's last frame, J: the strikers' kinetic energy, each block's
  // (index 0 = block 1; a container's matrix in none) and the part of those blocks' that moves
  // sideways (1/2 m (vx^2 + vy^2)). With e = 1 and no friction, E_in less their sum is the elastic
  // energy left in the contacts.
  double end_striker_ke = 0.0;
  std::vector<double> end_block_ke;
  double end_sideways_ke = 0.0;
  // Where the law keeps each contact's energy (refsim's thornton: System::contact_energies), at that
  // frame, J: the work the contacts have dissipated, each block's share (half of a pair contact's
  // to each sphere, all of a wall contact's) and in all; empty and 0 otherwise.
  std::vector<double> end_block_dissipated;
  double end_dissipated = 0.0;
  // And how fast the first striker moves back up and the output sphere moves, at that frame (m/s):
  // a stack that throws the striker back, or kicks its output sphere off faster than it was struck.
  double end_striker_vz = 0.0;
  double end_output_speed = 0.0;
  long steps = 0;                           // the run's (with stop_at_blow_end: where it stopped)
  int dump_every = 0, series_every = 0;     // the resolution's
  long atoms = 0;
  double seconds = 0.0;                     // wall time of the run
  std::string kernel;
};

// Runs `stack` (its case's derived dt, steps and series_every, model::resolve) from
// `particles`, the case's data file as particles_from reads it. Samples the series' quantities
// every series_every steps, as the deck does.
InSituResult run_in_situ(const model::Stack& stack, std::vector<Particle> particles, const InSituOptions& options = {});

}  // namespace granstack::refsim
