#pragma once
// Time step, duration and output cadences of a case: the automatic rules and what they are
// derived from (physics.md section 6). The constants are justified by the convergence study
// in docs/timestep.md.
#include <granstack/model/stack.hpp>

#include <string>

namespace granstack::model {

// dt = (shortest Hertz contact time of any contact in the stack at the striker speed) / this.
inline constexpr double kStepsPerContact = 100.0;
// Arrival of the pulse at the bottom face, in units of each block's equal-pair contact time
// t_c,k at the striker speed: sum over blocks of (kRowTransitPerContact * rows + kBlockEntryPerContact)
// t_c,k. Measured final-energy times of the output sphere (1 to 16 rows, 1 to 3 blocks, and
// physics.md section 6's 4-block figures) fit 0.55 rows + 0.5; these round the fit up.
inline constexpr double kRowTransitPerContact = 0.6;
inline constexpr double kBlockEntryPerContact = 0.6;
// Duration = this many times the estimated arrival time at the bottom face.
inline constexpr double kDurationPerArrival = 2.0;
// Automatic output: about this many dump frames and in-situ energy samples per run, and dump
// frames at least this often in units of the shortest contact time, so that the solitary wave
// crossing a row of the smallest spheres (about 0.45 t_c) is sampled at least twice.
inline constexpr long kAutoDumpFrames = 250;
inline constexpr double kDumpPerContact = 0.2;
inline constexpr long kAutoSeriesSamples = 20000;
inline constexpr long kAutoThermoLines = 200;

struct Resolution {
  double dt = 0.0;        // s
  double duration = 0.0;  // s (steps * dt)
  long steps = 0;
  int dump_every = 0;     // steps
  int series_every = 0;   // steps
  int thermo_every = 0;   // steps
  bool dt_auto = true;
  bool duration_auto = true;
  double min_contact_time = 0.0;    // s, shortest Hertz contact time at the striker speed
  std::string min_contact_pair;     // which contact gives it, e.g. "block 4 - block 4"
  double min_rayleigh_time = 0.0;   // s, of the smallest sphere (any block)
  double arrival_estimate = 0.0;    // s, estimated arrival of the pulse at the bottom face
  double skin = 0.0;                // m, neighbour-list skin
};

// Applies the spec's explicit values and the automatic rules for the rest. The number of steps
// is rounded up to a multiple of dump_every (a dump_every larger than the run becomes the whole
// run), so the final state is always in the dump.
Resolution resolve(const Stack& stack);

}  // namespace granstack::model
