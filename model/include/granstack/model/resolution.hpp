#pragma once
// Time step, duration and output cadences of a case: the automatic rules and what they are
// derived from (physics.md section 6). The constants are justified by the convergence study
// in docs/timestep.md.
#include <granstack/model/contact.hpp>
#include <granstack/model/stack.hpp>

#include <string>
#include <vector>

namespace granstack::model {

// dt = (shortest Hertz contact time of any contact in the stack at the striker speed) / this.
inline constexpr double kStepsPerContact = 100.0;  // the exact laws' (NormalLaw::steps_per_contact)
// Arrival of the pulse at the bottom face, in units of each block's equal-pair contact time
// t_c,k at the striker speed: sum over blocks of (kRowTransitPerContact * rows + kBlockEntryPerContact)
// t_c,k. Measured final-energy times of the output sphere (1 to 16 rows, 1 to 3 blocks, and
// physics.md section 6's 4-block figures) fit 0.55 rows + 0.5; these round the fit up.
inline constexpr double kRowTransitPerContact = 0.6;
inline constexpr double kBlockEntryPerContact = 0.6;
// Duration = this many times the estimated arrival time at the bottom face. The output sphere's
// last change of energy comes by 1.2 arrivals in single-material stacks and 0.73 to 0.89 in
// mixed ones without a soft cavity (1 to 16 rows, 1 to 4 blocks; measured with refsim).
inline constexpr double kDurationPerArrival = 2.0;
// With a soft cavity (has_soft_cavity: a softer block under a stiffer one and over a stiffer one)
// the pulse rattles in the soft block and leaves it in bursts: the last kick of the output sphere
// came at up to 3.74 arrivals (steel/Teflon/steel/Teflon, 8 rows; steel/Teflon/steel: 1.50, 1.84,
// 2.62 for 4, 8, 16 rows; 18 stacks of 3 and 4 blocks measured with refsim, 12 arrivals long,
// docs/timestep.md). This keeps the 1.67 margin over the worst.
inline constexpr double kCavityDurationPerArrival = 7.0;
// Automatic output: about this many dump frames and in-situ energy samples per run, and dump
// frames at least this often in units of the shortest contact time, so that the solitary wave
// crossing a row of the smallest spheres (about 0.45 t_c) is sampled at least twice.
inline constexpr long kAutoDumpFrames = 250;
inline constexpr double kDumpPerContact = 0.2;
inline constexpr long kAutoSeriesSamples = 20000;
// Over a bottom wall (the protected object) the series samples the wall's force at least this
// often per contact time of a bottom sphere on the wall (at the striker speed: the shortest such
// contact), whatever the run's length: its peak force and its filters need the pulse resolved.
inline constexpr double kSeriesPerWallContact = 20.0;
inline constexpr long kAutoThermoLines = 200;

// Physics guards on what the spec and the rules give (refused by `generate`, listed in docs/reference/spec.md):
// - dt at most the shortest contact time / kMinStepsPerContact. Velocity Verlet's energy error
//   on Hertz contacts grows as dt^2: measured with refsim (e = 1, mu = 0), 3.8e-6 of E_in on the
//   default stack and 9.7e-5 for steel on Teflon at t_c/100 (the automatic dt), 9.4e-5 and
//   2.2e-3 at t_c/20; beyond that the error grows fast and a contact of the smallest spheres
//   is resolved by too few steps to time its wave.
inline constexpr double kMinStepsPerContact = 20.0;
// - at most this many steps, whatever the flags (a typo such as --dt 1e-20 or --duration 1e9).
inline constexpr long kMaxSteps = 10'000'000'000;
// - the striker's Hertz overlap on the top spheres at most this fraction of their radius: Hertz
//   theory is a small-strain theory, and a steel sphere yields long before (about 0.1 m/s).
inline constexpr double kMaxOverlapPerRadius = 0.05;
// - and at least this fraction: the overlap is the difference of two distances of order R held
//   to about 1e-16 of R (double precision), so below 1e-9 R it keeps fewer than 7 digits and the
//   contact forces are round-off (at 1e-30 m/s the automatic run lasted 68 s of nothing).
inline constexpr double kMinOverlapPerRadius = 1e-9;

// The deck's neigh_modify contact_distance_factor: a pair is in the neighbour list within
// (R_i + R_j) x this + skin, and its tangential history is reset as soon as it separates by more
// than the factor. refsim and the MPI decomposition's ghost reach use the same value.
constexpr double kContactDistanceFactor = 1.01;

struct Resolution {
  double dt = 0.0;        // s
  double duration = 0.0;  // s (steps * dt)
  long steps = 0;
  double steps_asked = 0.0;  // duration / dt before rounding (or holding at kMaxSteps + 1)
  int dump_every = 0;     // steps
  int series_every = 0;   // steps
  double wall_contact_time = 0.0;  // s, a bottom sphere's on the bottom wall (0: no bottom wall)
  int thermo_every = 0;   // steps
  bool dt_auto = true;
  bool duration_auto = true;
  double min_contact_time = 0.0;    // s, shortest Hertz contact time at the striker speed
  std::string min_contact_pair;     // which contact gives it, e.g. "block 4 - block 4"
  double min_rayleigh_time = 0.0;   // s, of the smallest sphere (any block)
  double arrival_estimate = 0.0;    // s, estimated arrival of the pulse at the bottom face
  bool soft_cavity = false;         // has_soft_cavity: the automatic duration is longer
  double skin = 0.0;                // m, neighbour-list skin
  // StopRule::blow_end: `steps` is the cap (blow_end_cap_steps of the automatic duration, whose
  // dump and series cadences the run keeps), and the run stops at the blow's end before it.
  bool stops_at_blow_end = false;
};

// Applies the spec's explicit values and the automatic rules for the rest. The number of steps
// is rounded up to a multiple of dump_every (a dump_every larger than the run becomes the whole
// run), so the final state is always in the dump.
Resolution resolve(const Stack& stack);
// The striker's contact with a top sphere (its radius and material against the top block's).
ContactPair striker_contact(const Stack& stack);
// Whether the stack holds a soft cavity: a block of a softer material (a longer contact time
// for equal spheres at equal speed, slowness) resting on a stiffer one, with a stiffer material
// somewhere above it (a block or the striker). Steel/Teflon/steel has one; Teflon over steel,
// steel over Teflon and steel/steel/Teflon/Teflon do not.
bool has_soft_cavity(const Stack& stack);

// What is physically or numerically out of bounds in a resolved case (see the guards above), as
// spec issues naming the field and the bound; empty when the case is sound.
std::vector<SpecIssue> check_resolution(const Stack& stack, const Resolution& res);
// Whether the in-situ series samples every dump frame: where the blow's end reads the wall's force
// (blow_end_reads_wall_force), and in a run to the blow's end whose series carries its contacts'
// energies (NormalLaw::series_energy), where reduce reads the work dissipated at the frame the
// blow ends on; and with a protected plate, whose energy reduce counts at every frame.
bool series_on_every_frame(const StackSpec& spec);

// What a case will cost: its size, its outputs, and the time LIGGGHTS needs on one core at
// kLiggghtsParticleStepsPerSecond, the slowest loop rate measured on the project's 2-core machine
// (`bash bench/engine_rates.sh 3`, text dumps, the default case, a 961-sphere frictional stack
// and a 673-sphere nest: the slowest run of three runs of the script was 2.52e6, 3.3e6 and
// 2.75e6, medians 3.3e6 to 3.8e6; bench/results/trust-2026-11-26.md). Another machine may be
// slower: the estimate gives the order of the time, not a bound.
inline constexpr double kLiggghtsParticleStepsPerSecond = 2.5e6;
// Bytes a dumped atom line takes: 147 in text (the default case's 28.8 MB over 811 frames of 241
// atoms, measured) and 19 doubles in binary; bytes per value of the series (the default case's
// 3.05 MB over 16200 rows of 15 values, measured).
inline constexpr double kTextDumpBytesPerAtom = 147.0;
inline constexpr double kBinaryDumpBytesPerAtom = 152.0;
inline constexpr double kSeriesBytesPerValue = 12.6;
struct Cost {
  long spheres = 0;
  long steps = 0;
  long frames = 0;
  double dump_bytes = 0.0;
  double series_bytes = 0.0;
  double liggghts_seconds = 0.0;  // one core
};
Cost estimate_cost(const Stack& stack, const Resolution& res);
// The same from the counts a case's manifest holds, with no stack to build (submit over thousands
// of cases).
Cost estimate_cost(const StackSpec& spec, long spheres, long steps, long dump_every, long series_every);
// A case larger than this needs the user's confirmation (`generate --large`).
inline constexpr double kLargeDumpBytes = 20e9;
inline constexpr double kLargeLiggghtsSeconds = 24 * 3600.0;
// Why the case is large (empty when it is not).
std::string why_large(const Cost& cost);

// Whether a run was long enough for the output sphere's energy to be final. The automatic
// duration leaves its last change of energy at most kLastChangeFraction of the run (it is 2
// estimated arrivals, and the last change comes by 1.2 arrivals in single-material stacks,
// measured). A later change means energy may still have been on its way to the bottom: in the
// steel/Teflon/steel sandwich the output sphere is kicked four times, the last at 1.84 arrivals
// (8 rows) and 2.62 (16 rows), measured with refsim.
inline constexpr double kLastChangeFraction = 0.6;
// The step of the last in-situ sample (steps[i], its kinetic energy ke[i]) at which the output
// sphere's energy changed by more than 1e-3 of its final value and 1e-12 of E_in; 0 if none.
long last_output_change(const std::vector<long>& steps, const std::vector<double>& ke, double e_in);
// The output is final: its last change came at most kLastChangeFraction of the run's steps.
inline bool output_settled(long last_change_step, long steps) {
  return static_cast<double>(last_change_step) <= kLastChangeFraction * static_cast<double>(steps);
}
// Against a bottom wall, the peak load is final when the wall has taken the whole blow by the end
// of the run (the stack's momentum along z is no longer downward: final_momentum_ratio >= 0, in
// units of the striker's m v) and its peak came at most kLastChangeFraction of the run.
inline bool wall_load_settled(double peak_time, double run_time, double final_momentum_ratio) {
  return final_momentum_ratio >= 0.0 && peak_time <= kLastChangeFraction * run_time;
}

}  // namespace granstack::model
