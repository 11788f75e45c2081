#include <granstack/formats/batches.hpp>
#include <granstack/formats/case.hpp>
#include <granstack/formats/deck.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/energy.hpp>
#include <granstack/postproc/reduce.hpp>

#include "frame_pipeline.hpp"
#include "frame_tables.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <optional>
#include <set>
#include <thread>

namespace granstack::postproc {

namespace fs = std::filesystem;
using nlohmann::json;

// `holding_lock`: this process holds the case's lock (reduce writing its reduce/), so no run can.
void require_finished_run(const formats::Case& c, bool holding_lock) {
  const auto record = c.run_record();
  const auto& dir = c.dir();
  if (!record.exists()) {
    if (fs::exists(c.path(c.files().log))) {
      throw NotRunError(fmt::format("{}: the case has not been run by granstack, but its {} says LIGGGHTS ran its "
                                           "deck: take that run as the case's with 'granstack adopt {}' (it checks the "
                                           "log and outputs against the deck), or run it with 'granstack run {}'",
                                           dir, c.files().log, dir, dir));
    }
    throw NotRunError(fmt::format("{}: the case has not been run; run 'granstack run {}' first", dir, dir));
  }
  if (record.status == "damaged") throw formats::FormatError(c.path(c.files().run_record).string(), 0, record.error);
  if (record.status == "failed") {
    throw NotRunError(fmt::format("{}: the run failed ({}); fix it and run again with 'granstack run --force'",
                                         dir, record.error.empty() ? "no message" : record.error));
  }
  if (!record.done()) {
    if (const auto holder = holding_lock ? std::nullopt : os::CaseLock::holder(dir)) {  // running now: advice to rerun it would be refused
      throw NotRunError(fmt::format("{}: the case is being run now ({}); its outputs can be read when that run "
                                           "has ended", dir, *holder));
    }
    if (record.status == "running") {
      throw NotRunError(fmt::format("{}: its run was killed before it finished (run.json says running, but no "
                                           "granstack runs the case: SIGKILL, a time limit, a node failure?); run it again "
                                           "with 'granstack run --force {}'",
                                           dir, dir));
    }
    throw NotRunError(fmt::format("{}: the run did not finish (status '{}'); run 'granstack run --force {}'", dir,
                                         record.status, dir));
  }
}

namespace {



// Where the series keeps what reduce reads.
struct SeriesColumns {
  int step = -1;
  std::vector<int> trans, rot;  // per block
  int striker_t = -1, striker_r = -1, out_t = -1, out_r = -1;
  int bottom_t = -1, bottom_r = -1;  // the bottom row's, where the deck writes them
  int wall_force = -1;  // the bottom wall's force (model::kBottomWallForceColumn), when the deck writes it
  int plate_z = -1, plate_vz = -1, plate_az = -1;  // the protected plate's motion (model::kPlateColumns)
  // The contacts' elastic energy and dissipated work, each block's and the strikers' share of it
  // (model::series_contact_columns), where the law has its run report them.
  int contact_elastic = -1, contact_dissipated = -1, striker_dissipated = -1;
  std::vector<int> block_dissipated;
  bool has_contact_energy() const { return contact_elastic >= 0; }
  static double at(const std::vector<double>& row, int c) { return row[static_cast<std::size_t>(c)]; }
  double block_ke(const std::vector<double>& row, int k) const {
    return at(row, trans[static_cast<std::size_t>(k)]) + at(row, rot[static_cast<std::size_t>(k)]);
  }
  double striker_ke(const std::vector<double>& row) const { return at(row, striker_t) + at(row, striker_r); }
  double output_ke(const std::vector<double>& row) const { return at(row, out_t) + at(row, out_r); }
  double bottom_row_ke(const std::vector<double>& row) const { return at(row, bottom_t) + at(row, bottom_r); }
};

SeriesColumns series_columns(const formats::Series& series, const std::string& path, const model::Stack& stack) {
  const int nb = stack.spec().blocks;
  SeriesColumns c;
  std::vector<std::string> missing;
  auto find = [&](const std::string& name) {
    const int i = series.column(name);
    if (i < 0) missing.push_back(name);
    return i;
  };
  c.step = find("step");
  for (int k = 1; k <= nb; ++k) {
    c.trans.push_back(find(fmt::format("ke_trans_block{}", k)));
    c.rot.push_back(find(fmt::format("ke_rot_block{}", k)));
  }
  c.striker_t = find("ke_trans_striker");
  c.striker_r = find("ke_rot_striker");
  c.out_t = find("ke_trans_output_sphere");
  c.out_r = find("ke_rot_output_sphere");
  c.wall_force = series.column(model::kBottomWallForceColumn);
  if (stack.spec().has_plate()) {
    c.plate_z = find(model::kPlateColumns[0]);
    c.plate_vz = find(model::kPlateColumns[1]);
    c.plate_az = find(model::kPlateColumns[2]);
  }
  c.bottom_t = series.column("ke_trans_bottom_row");
  c.bottom_r = series.column("ke_rot_bottom_row");
  if (!model::series_contact_columns(stack).empty()) {
    c.contact_elastic = find(model::kContactElasticColumn);
    c.contact_dissipated = find(model::kContactDissipatedColumn);
    for (int k = 1; k <= nb; ++k) c.block_dissipated.push_back(find(fmt::format("dissipated_block{}", k)));
    c.striker_dissipated = find("dissipated_striker");
  }
  if (!missing.empty()) {
    throw formats::FormatError(path, 0, fmt::format("lacks the columns {} that the case's deck writes: it is not this "
                                                    "case's series", fmt::join(missing, ", ")));
  }
  for (std::size_t i = 0; i < series.rows.size(); ++i) {
    for (std::size_t j = 0; j < series.columns.size(); ++j) {
      if (!std::isfinite(series.rows[i][j])) {
        throw formats::FormatError(path, 0, fmt::format("{} in column '{}' of data row {} (step {}): the run blew up or "
                                                        "the file is damaged",
                                                        series.rows[i][j], series.columns[j], i + 1,
                                                        series.rows[i][static_cast<std::size_t>(c.step)]));
      }
    }
  }
  return c;
}

// Every series_every steps from the first multiple after the start (`fix print` writes at the
// end of a step) to the last step, nothing missing, nothing more.
void require_series_matches_run(const formats::Series& series, const SeriesColumns& c, const std::string& path,
                                const model::Resolution& res, long run_steps) {
  const long expected = run_steps / res.series_every;
  for (std::size_t i = 0; i < series.rows.size(); ++i) {
    const double step = SeriesColumns::at(series.rows[i], c.step);
    const long want = static_cast<long>(i + 1) * res.series_every;
    if (step != static_cast<double>(want)) {
      throw formats::FormatError(path, 0, fmt::format("data row {} is at step {}, where the run sampled step {} (every "
                                                      "{} steps): rows are missing, or it is another case's series",
                                                      i + 1, step, want, res.series_every));
    }
  }
  if (static_cast<long>(series.rows.size()) != expected) {
    throw formats::FormatError(path, 0, fmt::format("{} rows, the run wrote {} (steps {} to {} every {}): the series was "
                                                    "cut or damaged (run the case again with --force)",
                                                    series.rows.size(), expected, res.series_every, run_steps,
                                                    res.series_every));
  }
}

// A kinetic energy is never negative and never more than the energy the case holds: E_in, plus
// with gravity the potential energy of every sphere's fall to z = 0 (within kEnergyBalanceBound).
void require_series_physical(const formats::Series& series, const std::string& path, const model::Stack& stack) {
  double available = stack.incident_energy();
  for (const auto& sp : stack.spheres()) {
    const double mass = stack.mass(sp);
    available += stack.spec().gravity * mass * std::max(0.0, sp.z);
  }
  const double limit = available * (1.0 + kEnergyBalanceBound);
  for (std::size_t i = 0; i < series.rows.size(); ++i) {
    for (std::size_t j = 1; j < series.columns.size(); ++j) {
      if (model::series_column_unit(series.columns[j]) != "J") continue;  // a force or the plate's motion, of either sign
      const double v = series.rows[i][j];
      if (v < 0.0 || v > limit) {
        throw formats::FormatError(path, 0, fmt::format("{:.6g} J in column '{}' at step {}: a kinetic energy lies in "
                                                        "[0, {:.6g}] J (what the case holds); the file is damaged or "
                                                        "not this case's",
                                                        v, series.columns[j], series.rows[i][0], limit));
      }
    }
  }
}

// The series and the dumps come from one run: where both sampled a step, every block's and the
// striker's kinetic energy agree to kSeriesDumpAgreement of E_in (both are sums of the same
// doubles in another order: measured differences are below 1e-15 of E_in). The series has been
// checked to hold a row every series_every steps from series_every on.
constexpr double kSeriesDumpAgreement = 1e-9;

void require_frame_matches_series(const FrameEnergy& e, const formats::Series& series, const SeriesColumns& c,
                                  long series_every, const std::string& path, double e_in) {
  if (e.step == 0 || e.step % series_every != 0) return;
  const auto i = static_cast<std::size_t>(e.step / series_every - 1);
  if (i >= series.rows.size()) return;
  const auto& row = series.rows[i];
  auto differ = [&](double a, double b) { return !(std::fabs(a - b) <= kSeriesDumpAgreement * e_in); };
  for (std::size_t k = 0; k < e.block_ke.size(); ++k) {
    if (differ(c.block_ke(row, static_cast<int>(k)), e.block_ke[k])) {
      throw formats::FormatError(path, 0, fmt::format("at step {} block {}'s kinetic energy is {:.17g} J here and "
                                                      "{:.17g} J in the dump: the series is not this run's",
                                                      e.step, k + 1, c.block_ke(row, static_cast<int>(k)), e.block_ke[k]));
    }
  }
  // The striker, the output sphere and the bottom row, whose columns the output fraction and the
  // peaks are read from: a group the deck defined otherwise would give another sphere's energy.
  const auto check = [&](const char* what, double series_value, double dump_value) {
    if (!differ(series_value, dump_value)) return;
    throw formats::FormatError(path, 0, fmt::format("at step {} the {}'s kinetic energy is {:.17g} J here and {:.17g} J "
                                                    "in the dump: the series is not this run's, or its group is not "
                                                    "the case's",
                                                    e.step, what, series_value, dump_value));
  };
  check("striker", c.striker_ke(row), e.striker_ke);
  check("output sphere", c.output_ke(row), e.output_sphere_ke);
  if (c.bottom_t >= 0 && c.bottom_r >= 0) check("bottom row", c.bottom_row_ke(row), e.bottom_row_ke);
}


// A case that stops at the blow's end (StopRule::blow_end) ran to the frame where its run stops
// (model::BlowEnd::stop_at), as judged here from its dump, or to its cap. The deck is checked
// against the manifest before this, so another stop means the engine judged a frame otherwise than
// reduce does (a momentum within round-off of zero, summed in another order on several MPI ranks):
// said, and the measures read as reduce judges the blow (blow_end_time).
void warn_unless_stopped_at_blow_end(const model::BlowEnd& blow, long last_step, const model::Resolution& res,
                                     CaseReduction& r) {
  const auto at = blow.stop_at();
  if (at && *at == last_step) return;
  if (!at && last_step == res.steps) return;
  r.warnings.push_back(
      at ? fmt::format("the run went on to step {}, past the frame where reduce judges it should have stopped (step "
                       "{}): the engine judged the frames otherwise than reduce does",
                       last_step, *at)
         : fmt::format("the run stopped at step {}, before its cap of {} steps, where reduce finds that its condition "
                       "to stop ({}) had not held: the engine judged the frames otherwise than reduce does",
                       last_step, res.steps, blow.stop_rule()));
}

void warn_if_energy_still_arriving(const formats::Series& series, const SeriesColumns& c, const model::Resolution& res,
                                   CaseReduction& r) {
  std::vector<long> steps;
  std::vector<double> ke;
  for (const auto& row : series.rows) {
    steps.push_back(static_cast<long>(SeriesColumns::at(row, c.step)));
    ke.push_back(c.output_ke(row));
  }
  const auto last_step = static_cast<double>(model::last_output_change(steps, ke, r.e_in));
  r.output_last_change_time = last_step * res.dt;
  // Against a bottom wall the output sphere never leaves and its peak is the output: no warning.
  // A run that stops at the blow's end is final there, or says why not (blow_not_ended).
  if (r.spec.bottom == model::Boundary::free_surface && !res.stops_at_blow_end &&
      !model::output_settled(static_cast<long>(last_step), res.steps)) {
    r.warnings.push_back(fmt::format(
        "the output sphere's energy still changed at t = {:.4g} s, {:.2f} of the run (at most {:g} leaves room for "
        "later kicks): energy may still be on its way to the bottom; generate the case again with a longer "
        "--duration (at least {:.3g} s)",
        r.output_last_change_time, last_step / static_cast<double>(res.steps), model::kLastChangeFraction,
        r.output_last_change_time / model::kLastChangeFraction));
  }
}

// The contacts' elastic energy and dissipated work the series reports at `step` (a frame's),
// where the law has its run report them and the series sampled that step.
struct SeriesContactEnergy {
  double elastic, dissipated;
};
std::optional<SeriesContactEnergy> contact_energy_at(long step, const formats::Series& series, const SeriesColumns& c,
                                                     long series_every) {
  if (!c.has_contact_energy() || step == 0 || step % series_every != 0) return std::nullopt;
  const auto i = static_cast<std::size_t>(step / series_every - 1);
  if (i >= series.rows.size()) return std::nullopt;
  const auto& row = series.rows[i];
  return SeriesContactEnergy{SeriesColumns::at(row, c.contact_elastic), SeriesColumns::at(row, c.contact_dissipated)};
}

// The protected plate's displacement and velocity at `step` (a frame's), from the series' sample
// there: {0, 0} at the start, where it rests, and without a plate (the series samples every frame
// of a case with one).
std::array<double, 2> plate_at(long step, const formats::Series& series, const std::optional<SeriesColumns>& c,
                               long series_every, const model::StackSpec& spec, const std::string& path) {
  if (!spec.has_plate() || step == 0) return {0.0, 0.0};
  const auto i = static_cast<std::size_t>(step / series_every) - 1;
  if (!c || step % series_every != 0 || i >= series.rows.size()) {
    throw formats::FormatError(path, 0, fmt::format("no sample of the protected plate at step {} (a dump frame's), where "
                                                    "the frame is judged against it: the series is not the run's", step));
  }
  const auto& row = series.rows[i];
  return {SeriesColumns::at(row, c->plate_z), SeriesColumns::at(row, c->plate_vz)};
}

// What is over the footprint at frame `e` as the blow's end reads it: under an elastic-plastic law
// against a wall, whether the wall carries a force is the series' at the frame's step
// (model::blow_end_reads_wall_force; the resolution puts a sample on every frame; none at step 0,
// where nothing has touched the wall yet), not the overlaps.
model::OverFootprint judged_over(const FrameEnergy& e, const formats::Series& series, const SeriesColumns& c,
                                 long series_every, const model::StackSpec& spec, const std::string& path) {
  auto over = e.over_footprint;
  if (!model::blow_end_reads_wall_force(spec) || e.step == 0) {
    if (model::blow_end_reads_wall_force(spec)) over.pressing = false;
    return over;
  }
  const auto i = static_cast<std::size_t>(e.step / series_every) - 1;
  if (c.wall_force < 0 || e.step % series_every != 0 || i >= series.rows.size()) {
    throw formats::FormatError(path, 0, fmt::format("no sample of the wall's force at step {} (a dump frame's), where the "
                                                    "blow's end reads it under {}: the series is not the run's",
                                                    e.step, model::to_string(spec.normal_model)));
  }
  over.pressing = SeriesColumns::at(series.rows[i], c.wall_force) > 0.0;
  return over;
}

// Energy: without gravity, kinetic plus elastic energy never exceeds E_in (damping, friction and
// yield only remove energy), and where nothing dissipates it stays at E_in; both within
// kEnergyBalanceBound of E_in. Where the run reports its contacts' energy (`contact`), the
// elastic energy is the series' and the work the law dissipated is counted too: where nothing
// else dissipates, the sum stays at E_in. The bound sits above what the time-step guard lets
// through: the largest drift measured with refsim at the largest dt generate accepts (t_c/20) is
// 2.2e-3 of E_in (steel on Teflon; 9.4e-5 on the default stack, 4.3e-4 with walls), against
// 9.7e-5 and 3.8e-6 at the automatic dt (t_c/100); a broken integration gives orders of
// magnitude more.
void require_energy_balance(const FrameEnergy& e, const std::optional<SeriesContactEnergy>& contact, double plate,
                            const model::StackSpec& spec, CaseReduction& r, const std::string& dump_path) {
  if (spec.gravity != 0.0) return;  // gravity's potential energy is not counted
  const bool conservative = model::is_conservative(spec) || (contact && model::only_the_law_dissipates(spec));
  const double held = e.kinetic + (contact ? contact->elastic + contact->dissipated : e.elastic) + plate;
  const double error = (held - r.e_in) / r.e_in;
  if (conservative) r.energy_drift = std::max(r.energy_drift.value_or(0.0), std::fabs(error));
  if (error > kEnergyBalanceBound || (conservative && -error > kEnergyBalanceBound)) {
    const bool elastic_known = contact || model::has_overlap_energy(spec.contact_model());
    const char* why = conservative  ? (contact ? ", this case loses energy only by yield, which the run reports"
                                               : ", this case conserves energy")
                      : elastic_known ? ", damping, friction and yield only remove energy"
                                      : ", yield only removes energy (the elastic energy of an elastic-plastic contact "
                                        "is not in the dump: 0 counted)";
    throw PhysicsError(fmt::format(
        "{}: at step {} the kinetic plus elastic energy{} is {:.6g} J against E_in = {:.6g} J ({:+.3g} of E_in; at "
        "most {:g} allowed{}): the integration is broken (a time step too long for the contacts?) or the dump is "
        "not this case's; no result is taken from it",
        dump_path, e.step,
        std::string(contact ? " plus the contacts' dissipated work" : "") + (spec.has_plate() ? " plus the plate's" : ""),
        held, r.e_in, error,
        kEnergyBalanceBound, why));
  }
}
}  // namespace

namespace {
using detail::panel_energies;

// A container's leak: the kinetic energy of the panels no striker hit and of the matrix.
double leaked_energy(const std::vector<double>& panels, double matrix_ke, const model::Stack& stack) {
  double leaked = matrix_ke;
  for (std::size_t p = 0; p < panels.size(); ++p) {
    if (!stack.struck(static_cast<int>(p) + 1)) leaked += panels[p];
  }
  return leaked;
}

// The running maxima a frame may raise: the output sphere's, the top row's parts and, in a
// container, each panel's and the matrix's.
void track_peaks(const FrameEnergy& e, const model::Stack& stack, double time, CaseReduction& r) {
  r.output_peak_fraction = std::max(r.output_peak_fraction, e.output_sphere_ke / r.e_in);
  r.top_row_sideways_peak = std::max(r.top_row_sideways_peak, e.top_row_sideways);
  r.top_row_downward_peak = std::max(r.top_row_downward_peak, e.top_row_downward);
  if (!stack.container()) return;
  const auto panels = panel_energies(e);
  auto& frame = r.panel_frames.emplace_back(1, time);
  frame.insert(frame.end(), panels.begin(), panels.end());
  frame.push_back(e.matrix_ke);
  r.panel_peak_fraction.resize(panels.size(), 0.0);
  for (std::size_t p = 0; p < panels.size(); ++p) {
    r.panel_peak_fraction[p] = std::max(r.panel_peak_fraction[p], panels[p] / r.e_in);
  }
  r.matrix_peak_fraction = std::max(r.matrix_peak_fraction, e.matrix_ke / r.e_in);
  r.leaked_peak_fraction = std::max(r.leaked_peak_fraction, leaked_energy(panels, e.matrix_ke, stack) / r.e_in);
}
}  // namespace

// Where the run reports its contacts' energy and sampled the last frame's step: the work the law
// dissipated, in all, in each block and in the strikers, and (the elastic energy the series')
// the dissipated fraction.
void contact_work(const FrameEnergy& last, const formats::Series& series, const SeriesColumns& c, long series_every,
                  CaseReduction& r) {
  const auto at = contact_energy_at(last.step, series, c, series_every);
  if (!at) return;
  const auto& row = series.rows[static_cast<std::size_t>(last.step / series_every - 1)];
  r.plastic_work_fraction = at->dissipated / r.e_in;
  r.block_plastic_work_fraction.clear();
  for (const int column : c.block_dissipated) r.block_plastic_work_fraction.push_back(SeriesColumns::at(row, column) / r.e_in);
  r.striker_plastic_work_fraction = SeriesColumns::at(row, c.striker_dissipated) / r.e_in;
  if (r.spec.gravity == 0.0) r.dissipated_fraction = (r.e_in - last.kinetic - at->elastic) / r.e_in;
}

// The run's in-situ series, whole and physical, or FormatError naming what is wrong.
// `run_steps`: where the run ended (the resolution's steps, or the blow's end of a case that stops there).
formats::Series read_checked_series(const std::string& path, const model::Stack& stack, const model::Resolution& res,
                                    long run_steps) {
  if (!fs::exists(path)) {
    throw formats::FormatError(path, 0, "missing: the run's in-situ energy series is what the peaks are taken from; "
                                        "run the case again with --force");
  }
  auto series = formats::read_series(path);
  require_series_matches_run(series, series_columns(series, path, stack), path, res, run_steps);
  require_series_physical(series, path, stack);
  return series;
}

// Each block's peak kinetic energy and its time, and the output sphere's peak, from the series
// (sampled far more often than the dumps).
void series_peaks(const formats::Series& series, const SeriesColumns& cols, double dt, CaseReduction& r) {
  std::vector<BlockPeak> peaks(static_cast<std::size_t>(r.spec.blocks));
  for (const auto& row : series.rows) {
    const double t = row[static_cast<std::size_t>(cols.step)] * dt;
    for (int k = 0; k < r.spec.blocks; ++k) {
      const double ke = cols.block_ke(row, k);
      auto& p = peaks[static_cast<std::size_t>(k)];
      if (ke > p.peak_ke) p = {k + 1, ke, t, 0.0};
    }
    r.output_peak_fraction = std::max(r.output_peak_fraction, cols.output_ke(row) / r.e_in);
    if (cols.plate_az >= 0) r.plate_acceleration.push_back(SeriesColumns::at(row, cols.plate_az));
    if (cols.wall_force >= 0) {
      const double f = SeriesColumns::at(row, cols.wall_force);
      r.wall_force.push_back(f);
      if (!r.peak_wall_force || f > *r.peak_wall_force) {
        r.peak_wall_force = f;
        r.peak_wall_force_time = t;
      }
    }
  }
  r.blocks = peaks;
  r.peak_source = "series";
  for (auto& b : r.blocks) b.normalised = r.blocks.front().peak_ke > 0 ? b.peak_ke / r.blocks.front().peak_ke : 0.0;
}

// What the last frame gives: the output fractions (the output sphere's final energy, or its peak
// against a wall), the bottom row's, what was dissipated, the striker's rebound and, in a
// container, each panel's and the matrix's share.
void final_state(const FrameEnergy& last, const model::Stack& stack, CaseReduction& r) {
  const auto& spec = stack.spec();
  // An elastic-plastic law's elastic energy is not in the dump: what is not kinetic is then stored
  // and dissipated together, and no dissipated fraction is claimed.
  if (spec.gravity == 0.0 && model::has_overlap_energy(spec.contact_model())) {
    r.dissipated_fraction = (r.e_in - last.kinetic - last.elastic) / r.e_in;
  }
  r.striker_velocity_ratio = last.striker_vz / -spec.striker_speed;
  r.final_momentum_ratio = last.momentum_z / (stack.striker_mass() * spec.striker_speed * stack.strikers());
  r.output_fraction_bottom_row = last.bottom_row_ke / r.e_in;
  r.output_fraction_bottom_row_per_sphere =
      r.output_fraction_bottom_row / static_cast<double>(stack.bottom_row_ids().size());
  r.output_fraction_bottom_row_max = last.bottom_row_max_ke / r.e_in;
  if (spec.bottom == model::Boundary::wall) {
    // Against a wall the output sphere never leaves: its peak is the only defined output.
    r.output_fraction = r.output_peak_fraction;
    r.output_definition = "peak kinetic energy of the output sphere (bottom wall) / E_in";
  } else {
    r.output_fraction = last.output_sphere_ke / r.e_in;
    r.output_definition = "kinetic energy of the output sphere after it left the free bottom face / E_in";
    if (!r.output_separated) {
      r.warnings.push_back(fmt::format(
          "the output sphere (id {}) is still in contact at the last frame (t = {:.4g} s): it has not reached its "
          "final energy; generate the case again with a longer --duration",
          stack.output_sphere_id(), r.final_time));
    }
  }
  if (stack.container()) {
    const auto panels = panel_energies(last);
    for (const double ke : panels) r.panel_final_fraction.push_back(ke / r.e_in);
    r.matrix_final_fraction = last.matrix_ke / r.e_in;
    r.leaked_final_fraction = leaked_energy(panels, last.matrix_ke, stack) / r.e_in;
  }
}

// Frames are handed to threads in batches of about this many bytes: a text piece large enough to
// hold many frames (each reuses the previous frame's repeated numbers; the first of a piece has
// none to reuse, so a larger piece reuses more), a binary batch small, and a few batches per
// thread small in memory.
constexpr std::size_t kTextBatchBytes = std::size_t{4} << 20, kBinaryBatchBytes = std::size_t{1} << 20;

CaseReduction reduce_case(const std::string& case_dir, const ReduceOptions& options) {
  const fs::path dir(case_dir);
  const auto c = formats::Case::open(case_dir);
  const auto& manifest = c.manifest();
  // Writing into the case (its reduce/), reduce holds the case's lock, as every command that writes a case does.
  std::optional<os::CaseLock> lock;
  if (options.write_files && options.output_dir.empty()) lock.emplace(c.lock("granstack reduce"));
  require_finished_run(c, lock.has_value());
  const auto& stack = c.stack();
  // The derived dt and steps must be those its spec gives, and the deck's those of the manifest:
  // every time in the results is a step times dt.
  c.check_derived();
  formats::check_deck_matches_manifest(c);
  const auto res = c.resolution();
  const auto& spec = stack.spec();
  const auto dump_path = formats::find_dump(case_dir, manifest.files.dump);
  const bool binary = spec.dump_format == model::DumpFormat::binary;
  formats::FrameBatchSource source(dump_path, binary, manifest.files.dump_columns, FrameView::needed_columns(),
                                   binary ? kBinaryBatchBytes : kTextBatchBytes);
  // That the outputs are those this case's run wrote is checked beside the reading, on a thread of
  // its own; a plain text dump is digested from the pieces the parsing threads read (not read a
  // second time). The verdict is taken after the reading, so a damaged file gets the reader's own
  // message.
  std::future<std::string> outputs_check;
  std::set<std::string> digested_here;
  if (options.verify_run_outputs) {
    if (source.digest_content()) digested_here.insert(fs::path(dump_path).lexically_relative(c.dir()).string());
    outputs_check = std::async(std::launch::async, [&c, &digested_here] {
      return formats::files_not_as_run(c, c.run_record(), formats::DigestCheck::full, digested_here);
    });
  }

  CaseReduction r;
  r.case_dir = case_dir;
  r.case_name = manifest.case_name;
  const auto record = c.run_record();
  r.engine = formats::run_engine(record);
  r.deck_additions = formats::deck_additions_ran(record);
  r.spec = spec;
  r.e_in = stack.incident_energy();
  // The in-situ series gives the peaks. It must be the run's own and whole (checked here), and
  // agree with every dump frame where both have data (checked as the frames arrive).
  const auto series_path = formats::find_dump(case_dir, manifest.files.series);  // or its compressed copy
  const long expected_frames = formats::frames_written(c);
  // Read beside the dump's first frames (the frames wait for it, not the parsing threads); its
  // errors come before the dump's, as if it were read first.
  auto series_read = std::async(std::launch::async, [&] {
    return read_checked_series(series_path, stack, res, (expected_frames - 1) * res.dump_every);
  });
  formats::Series series;
  std::optional<SeriesColumns> series_cols;
  auto take_series = [&] {
    if (series_cols || !series_read.valid()) return;  // taken, or its error already thrown
    series = series_read.get();
    series_cols = series_columns(series, series_path, stack);
  };
  const WaveTracker wave_sampler(stack, res.dt);
  WaveTracker waves(stack, res.dt);
  const auto rdir = options.output_dir.empty() ? dir / "reduce" : fs::path(options.output_dir);
  detail::FrameTables tables(stack, rdir, options.write_files);

  // Each frame is analysed, and its table rows formatted, on whichever thread parsed it; the
  // results then arrive here in frame order.
  struct FrameResult {
    FrameEnergy e;
    std::vector<double> wave_samples;
    std::vector<fmt::memory_buffer> rows;  // one per table
    std::optional<bool> separated;  // for the last frame of a batch
  };
  const double e_in = r.e_in;
  // Over a protected plate, each frame is analysed where the plate stood then (the series' sample
  // at its step): the series is taken before any frame, and read alone by the threads.
  if (spec.has_plate()) take_series();
  auto analyse = [&](FrameAnalyser& a, const formats::DumpFrame& frame, FrameResult& fr, bool last_of_batch) {
    const auto plate = plate_at(frame.step, series, series_cols, res.series_every, spec, series_path);
    a.analyse(frame, fr.e, plate[0], plate[1]);
    wave_sampler.sample(frame, a.view(), fr.wave_samples);
    fr.separated.reset();
    if (last_of_batch) fr.separated = a.has_separated(frame, stack.output_sphere_id());
    tables.format(fr.e, static_cast<double>(frame.step) * res.dt, e_in, fr.rows);
  };
  FrameEnergy last_energy;
  long last_step = 0;
  model::CrushMeter crush(stack);
  model::YieldMeter yield(stack);
  model::BlowEnd blow(stack, res);
  auto take_result = [&](FrameResult& fr) {
    if (const int signal = os::interrupt_signal(); signal != 0) {
      throw std::runtime_error(fmt::format("{}: reduce stopped by signal {} at frame {}", case_dir, signal, r.frames + 1));
    }
    take_series();
    const auto& e = fr.e;
    if (r.frames >= expected_frames) {
      throw formats::FormatError(dump_path, 0, fmt::format("frame {} (step {}) comes after the run's last frame (step {}): "
                                                           "the run wrote {} frames, and more were added to its dump",
                                                           r.frames + 1, e.step, (expected_frames - 1) * res.dump_every,
                                                           expected_frames));
    }
    if (e.step != r.frames * res.dump_every) {
      throw formats::FormatError(dump_path, 0, fmt::format("frame {} is at step {}, where the run dumped step {} (every {} "
                                                           "steps): frames are missing or out of order",
                                                           r.frames + 1, e.step, r.frames * res.dump_every, res.dump_every));
    }
    const auto plate = plate_at(e.step, series, series_cols, res.series_every, spec, series_path);
    require_energy_balance(e, contact_energy_at(e.step, series, *series_cols, res.series_every),
                           model::plate_energy(spec, plate[0], plate[1]), spec, r, dump_path);
    require_frame_matches_series(e, series, *series_cols, res.series_every, series_path, r.e_in);
    track_peaks(e, stack, static_cast<double>(e.step) * res.dt, r);
    crush.add(e.crush);
    yield.add(e.yield);
    blow.frame(e.step, judged_over(e, series, *series_cols, res.series_every, spec, series_path), e.output_free,
               e.output_threatened, e.striker);
    waves.add(e.step, fr.wave_samples);
    tables.append(fr.rows);
    if (fr.separated) r.output_separated = *fr.separated;
    ++r.frames;
    if (options.on_frame) options.on_frame(r.frames);
    last_step = e.step;
    std::swap(last_energy, fr.e);
  };
  // By default one thread per CPU granstack may use (its affinity mask: taskset, a SLURM allocation), never more.
  const int threads = options.threads > 0 ? options.threads : os::usable_cpus();
  try {
    try {
      for_each_frame_in_order<FrameResult>(
          source, threads, [&] { return std::make_unique<FrameAnalyser>(stack, dump_path); }, analyse, take_result);
    } catch (...) {
      take_series();  // throws the series' error, which comes first
      throw;
    }
  } catch (const formats::TruncatedError& e) {
    throw formats::FormatError(e.file(), e.line(),
                               fmt::format("{}: the dump holds {} complete frames of the {} the run wrote; the file "
                                           "was cut or damaged after the run (run the case again with --force)",
                                           e.message(), r.frames, expected_frames));
  }
  if (r.frames != expected_frames) {
    throw formats::FormatError(dump_path, 0, fmt::format("{} frames, the run wrote {} (steps 0 to {} every {}): pieces or "
                                                         "frames are missing (run the case again with --force)",
                                                         r.frames, expected_frames, res.steps, res.dump_every));
  }
  r.final_time = static_cast<double>(last_step) * res.dt;
  if (res.stops_at_blow_end) warn_unless_stopped_at_blow_end(blow, last_step, res, r);

  r.crush = crush.crush();
  r.penetration = crush.penetration();
  r.yield_unjudged_materials = yield.unjudged_materials();
  if (yield.judged()) {
    r.yield = yield.largest();
    r.yield_ratio = r.yield.ratio;
    r.yield_time = static_cast<double>(r.yield.step) * res.dt;
    r.yield_contact = model::describe_contact(stack, r.yield);
  } else {
    r.yield_not_judged = yield.why_not_judged();
  }
  if (const auto at = blow.ended_at()) {
    r.blow_end_time = static_cast<double>(*at) * res.dt;
    r.frames_after_blow_end = (last_step - *at) / res.dump_every;
  }
  r.blow_not_ended = blow.why_not_ended();
  take_series();  // a dump of no frames
  const SeriesColumns& cols = *series_cols;
  series_peaks(series, cols, res.dt, r);
  r.wall_force_interval = static_cast<double>(res.series_every) * res.dt;
  warn_if_energy_still_arriving(series, cols, res, r);
  r.waves = waves.finish(series);
  final_state(last_energy, stack, r);
  contact_work(last_energy, series, cols, res.series_every, r);
  // Outputs that read cleanly must still be those this case's run wrote, never another case's
  // under its labels.
  if (outputs_check.valid()) formats::refuse_unless_as_run(c, outputs_check.get());
  for (const auto& name : digested_here) {
    formats::refuse_unless_as_run(c, formats::output_not_as_run(c, c.run_record(), name, source.content_xxh128()));
  }

  tables.finish();
  if (options.write_files) {
    fs::create_directories(rdir);
    r.csv_path = (rdir / "block_ke.csv").string();
    formats::write_file_atomically(rdir / "summary.json", to_json(r).dump(2) + "\n");
  }
  return r;
}

}  // namespace granstack::postproc
