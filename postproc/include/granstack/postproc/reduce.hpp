#pragma once
// `granstack reduce`: a case's dumps and in-situ series -> per-block energy table, peaks and
// the output fractions of physics.md section 4.
#include <granstack/model/yield.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/postproc/waves.hpp>

#include <functional>
#include <optional>
#include <stdexcept>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace granstack::formats {
class Case;
}

namespace granstack::postproc {

// A case whose run has not finished: none yet, one that failed, one running now, one killed.
struct NotRunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Throws NotRunError (naming the case and what to do) unless the case's run finished
// (`holding_lock`: this process holds the case's lock, so none can be running); a damaged run
// record is a FormatError. What reads a case's outputs (reduce, table, plot, export) asks first.
void require_finished_run(const formats::Case& c, bool holding_lock);

struct BlockPeak {
  int block = 0;           // 1 = top
  double peak_ke = 0.0;    // J, translational + rotational
  double peak_time = 0.0;  // s
  double normalised = 0.0; // peak_ke / peak_ke of block 1
};

struct CaseReduction {
  std::string case_dir;
  std::string case_name;
  std::string engine;                  // the engine that ran it, by its run.json (formats::run_engine)
  // The commands beyond granstack's deck that the run executed, as the spec's deck_additions let
  // them ("TEXT (FILE:LINE)"), by its run.json.
  std::vector<std::string> deck_additions;
  model::StackSpec spec;
  double e_in = 0.0;                   // J
  double output_fraction = 0.0;        // output sphere's KE after separation / E_in
  double output_fraction_bottom_row = 0.0;             // whole bottom row's final KE / E_in
  double output_fraction_bottom_row_per_sphere = 0.0;  // the same per bottom-row sphere
  double output_fraction_bottom_row_max = 0.0;         // the bottom row's most energetic sphere's final KE / E_in
  std::string output_definition;       // how output_fraction was taken
  bool output_separated = false;       // the output sphere touches nothing at the last frame
  double output_peak_fraction = 0.0;   // the output sphere's peak KE / E_in
  // With a bottom wall, the largest z force it exerted on the stack (the protected object's
  // peak load), N, over the in-situ series (every series_every steps), and when; none when the
  // case has no bottom wall or its deck predates the column.
  std::optional<double> peak_wall_force;
  double peak_wall_force_time = 0.0;   // s
  // ... and that force at every series sample, wall_force_interval (s) apart from one interval
  // after the start: what model::peak_window_impulse reads (the design's wall_impulse).
  std::vector<double> wall_force;
  double wall_force_interval = 0.0;
  // Over a protected plate (StackSpec::plate_mass), its acceleration at the same samples, m/s^2
  // (the series' plate_az); empty over a rigid wall.
  std::vector<double> plate_acceleration;
  // The stack's crush (its top surface's largest travel toward the wall over the footprint) and
  // the striker's penetration below the stack's initial top surface, the largest over the dump
  // frames (model::CrushMeter), m.
  double crush = 0.0;
  double penetration = 0.0;
  // The largest Hertz contact pressure over its first-yield pressure over the dump frames
  // (model::YieldMeter), none when the contacts are not judged (yield_not_judged says why), and
  // where (yield.id_a, id_b: spheres; id_b = 0: the wall yield.wall) and when (yield_time, s).
  // The materials with no yield strength (brittle), whose contacts with each other are not judged.
  std::optional<double> yield_ratio;
  model::YieldPeak yield;
  double yield_time = 0.0;
  std::string yield_contact;  // model::describe_contact
  std::string yield_not_judged;
  std::vector<std::string> yield_unjudged_materials;
  // When the blow ended (model::BlowEnd over the dump's frames: against a wall the stack no
  // longer moving down and off the wall, with a free bottom the output sphere touching nothing,
  // held for an estimated arrival of the pulse), or none within the run, and why not.
  std::optional<double> blow_end_time;  // s
  std::string blow_not_ended;
  // The dump frames after the blow's end, each of which held its condition (or the end would have
  // been taken back): a run stops only where every course to a striker is gone, those that run
  // through other spheres too (model::BlowEnd::stop_at), so it can go on past the blow's end.
  long frames_after_blow_end = 0;
  // The whole stack's momentum along z at the last frame over the striker's at the start, m v
  // (up positive: above 0 the bottom wall has stopped the blow and thrown the stack back).
  double final_momentum_ratio = 0.0;
  std::vector<BlockPeak> blocks;       // top first
  std::string peak_source;             // "series" (in-situ, every series_every steps) or "dump"
  long frames = 0;
  double final_time = 0.0;             // s, of the last dump frame
  // s: the last in-situ sample at which the output sphere's kinetic energy changed by more than
  // 1e-3 of its final value (a warning when it is late in the run).
  double output_last_change_time = 0.0;
  // max |KE + elastic - E_in| / E_in over the frames; only for a conservative case
  // (model::is_conservative), where it measures the integration error; with a law whose run
  // reports its contacts' energy (model::series_contact_columns) and nothing else dissipating
  // (model::only_the_law_dissipates), max |KE + elastic + dissipated work - E_in| / E_in over the
  // frames the series sampled.
  std::optional<double> energy_drift;
  // The friction study (physics.md section 4): peaks over the dump frames of the top row's
  // sideways (1/2 m vx^2 + vy^2) and downward (1/2 m vz^2) kinetic energy, in J.
  double top_row_sideways_peak = 0.0;
  double top_row_downward_peak = 0.0;
  // The striker's velocity along z at the last frame over the one it started with, -v: 1 when it
  // goes on at full speed, negative when it bounced back. The isolated collision of physics.md
  // section 5 (Eq. 3) has (1 - 2 kappa cos^2 theta) / (1 + 2 kappa cos^2 theta).
  double striker_velocity_ratio = 0.0;
  // E_in - kinetic - elastic at the last frame, / E_in: what damping, friction and yield took.
  // Not defined with gravity (its potential energy is not counted), nor for a path-dependent law
  // whose run does not report its contacts' elastic energy (LIGGGHTS's thornton_ning).
  std::optional<double> dissipated_fraction;
  // Where the run reports its contacts' energy (model::series_contact_columns), at the last
  // frame, / E_in: the work the contact law dissipated (yield), each block's share of it (top
  // first: half of a pair contact's to each sphere, all of a wall contact's) and the strikers'.
  std::optional<double> plastic_work_fraction;
  std::vector<double> block_plastic_work_fraction;
  std::optional<double> striker_plastic_work_fraction;
  std::vector<BlockWaves> waves;        // top block first
  // A container (geometry = panels), over the dump frames: each panel's kinetic energy at the
  // last frame and its peak, / E_in (index 0 = panel 1); the matrix's; and the leak, the kinetic
  // energy outside the impacted panel and the striker (the other panels and the matrix).
  std::vector<double> panel_final_fraction, panel_peak_fraction;
  double matrix_final_fraction = 0.0, matrix_peak_fraction = 0.0;
  double leaked_final_fraction = 0.0, leaked_peak_fraction = 0.0;
  // ... and per dump frame: the time (s), each panel's kinetic energy and the matrix's (J).
  std::vector<std::vector<double>> panel_frames;
  std::vector<std::string> warnings;
  std::string csv_path;                // the per-block energy table written (reduce/block_ke.csv)
};

struct ReduceOptions {
  // CASE/reduce/ (or output_dir): block_ke.csv, energy_parts.csv, row_ke.csv, column_ke.csv (and
  // for a 3D nest column_y_ke.csv, for a container panel_ke.csv), summary.json
  bool write_files = true;
  std::string output_dir;  // empty: CASE/reduce
  // Called after every frame read (frames so far), on the calling thread.
  std::function<void(long frames)> on_frame;
  // Threads that parse and analyse frames; 0 = one per core.
  int threads = 0;
  // The outputs must be those the case's run recorded in run.json (formats::require_files_as_run).
  // Only validate's comparison of the two copies it has just run leaves this off.
  bool verify_run_outputs = true;
};

// The results break a law they must obey (energy created, or not conserved where nothing
// dissipates): no result is taken from such a case.
class PhysicsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// The bound of reduce's energy checks, as a fraction of E_in (see require_energy_balance).
inline constexpr double kEnergyBalanceBound = 0.01;

// Throws formats::FormatError for unreadable or inconsistent files (NaN or inf anywhere, frames
// or series rows missing, a series or deck that is not the manifest's), PhysicsError for broken
// energy balance, std::runtime_error for a case that has not (successfully) run.
CaseReduction reduce_case(const std::string& case_dir, const ReduceOptions& options = {});

// Names for the cases `dirs` that tell them apart: the directory's name, or where two share it the
// shortest tail of their paths that differs (a/nb1_e1, b/nb1_e1).
std::vector<std::string> unique_case_labels(const std::vector<std::string>& dirs);

// The JSON object `reduce --json` prints for a case (one line per case).
nlohmann::json to_json(const CaseReduction& r);

// The readable tables: a row per case, then (for a single case) a row per block.
std::string format_table(const std::vector<CaseReduction>& reductions);

}  // namespace granstack::postproc
