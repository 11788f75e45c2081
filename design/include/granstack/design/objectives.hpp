#pragma once
// What a design is judged by: one table of measures (docs/design.md prints it from
// `granstack design objectives`). An entry names the measure, its unit and formula, the boundary
// it needs and how it is read from a run or from the geometry; the space parser, the store's
// columns, the report and confirm read the table, so a new measure costs one entry here.
#include <granstack/design/store.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::postproc {
struct CaseReduction;
}

namespace granstack::design {

struct Space;

// What one run of a design gave, in situ or by reduce of its case (the same values).
struct Outcome {
  double output_fraction = 0.0, bottom_row_fraction = 0.0;
  bool output_separated = false;
  std::optional<double> peak_wall_force;
  double output_last_change_time = 0.0;  // s
  bool output_settled = true;            // free bottom: the output's; wall: the load's (model::wall_load_settled)
  double peak_wall_force_time = 0.0;     // s
  double final_momentum_ratio = 0.0;     // the stack's z momentum at the end over m v
  double run_time = 0.0;                 // s
  double seconds = 0.0;
  std::vector<double> wall_force;        // N, at every series sample, wall_force_interval apart
  std::vector<double> plate_acceleration;  // m/s^2, the protected plate's at the same samples; empty: a rigid wall
  double wall_force_interval = 0.0;      // s
  double crush = 0.0;                    // m, model::CrushMeter over the dump's frames
  double penetration = 0.0;              // m, the same
  std::optional<double> yield_ratio;     // model::YieldMeter over the same frames; none: not Hertz contacts
  long steps = 0;                        // the run's
  std::optional<double> blow_end_time;   // s, model::BlowEnd; none: not ended within the run
  std::string blow_not_ended;            // why not
  // The search's shortcut stopped the run under way, its measures so far deciding the design
  // (why, with when; "" when it ran to its end): its measures are lower bounds of the whole run's.
  std::string settled;
};
// The fields refsim's in-situ result and reduce's reduction share by name, into an outcome. The
// series are extended, not copied: `o`'s must be a beginning of `r`'s (empty, or taken from the same
// run earlier), so that a run's shortcuts, asked every few samples, copy each sample once.
template <class Run>
void take_shared(Outcome& o, const Run& r) {
  o.output_fraction = r.output_fraction;
  o.output_separated = r.output_separated;
  o.peak_wall_force = r.peak_wall_force;
  o.output_last_change_time = r.output_last_change_time;
  o.peak_wall_force_time = r.peak_wall_force_time;
  o.final_momentum_ratio = r.final_momentum_ratio;
  const auto extend = [](std::vector<double>& to, const std::vector<double>& from) {
    to.insert(to.end(), from.begin() + static_cast<std::ptrdiff_t>(std::min(to.size(), from.size())), from.end());
  };
  extend(o.wall_force, r.wall_force);
  extend(o.plate_acceleration, r.plate_acceleration);
  o.wall_force_interval = r.wall_force_interval;
  o.crush = r.crush;
  o.penetration = r.penetration;
  o.yield_ratio = r.yield_ratio;
  o.blow_end_time = r.blow_end_time;
  o.blow_not_ended = r.blow_not_ended;
}
// A case's outcome from its reduction (`ran`: the spec it ran, for the finality rules).
Outcome outcome_of(const postproc::CaseReduction& r, const model::StackSpec& ran);

// The rules by which this granstack takes its run measures: raised whenever a measure's
// definition or a run's end changes what a stored value means, so that a store's evaluations are
// never mixed with ones taken by other rules (Store::open refuses to search on in such a store).
// 2: stroke split into crush (the stack's loss of height) and penetration; a blow ends only when
// no striker is still coming; designs confined by default. 1 (or none recorded): before.
inline constexpr int kMeasureRules = 2;
std::string_view measure_rules_changes();  // what rules 2 changed, in words

// The bottom a measure needs.
enum class Needs { any, free_bottom, wall };

struct ObjectiveDef {
  std::string_view name;
  std::string_view unit;
  std::string_view formula;  // what it is, in words and symbols (docs and report)
  Needs needs = Needs::any;
  // Drawn on a log axis (it spans decades across a space).
  bool log_axis = false;
  // Measured on the outgoing layer's spheres, whose mass falls as the bottom radius shrinks: a
  // space that varies the bottom radius (blocks or radius ratios) would win by shrinking them.
  bool gameable_by_bottom_radius = false;
  // From a run (nullptr: from the geometry, with `geometric`).
  std::optional<double> (*from_run)(const Outcome&, const Space&) = nullptr;
  double (*geometric)(const Evaluation&) = nullptr;
  // A run measure that is a largest value so far (over the series' samples or the dump's frames):
  // over the first part of a run it is at most its value over the whole run (the search's
  // shortcuts settle a design from it before its run ends). A filtered signal, a spectrum or a
  // final energy is not.
  bool grows = false;
};
using Objective = const ObjectiveDef*;

const std::vector<ObjectiveDef>& objective_table();
Objective find_objective(std::string_view name);  // nullptr when unknown
// What replaced a measure granstack no longer takes (a space that names it is refused with this),
// or empty: `stroke`, the striker's travel from first touch, counted its indentation into a top
// sphere as the stack's crush.
std::string_view retired_measure(std::string_view name);
// The names of the table's run measures (each a column of the store's evaluations).
std::vector<std::string> run_measure_names();
inline std::string_view to_string(Objective o) { return o->name; }
inline std::string_view unit_of(Objective o) { return o->unit; }
std::string_view to_string(Needs n);

// The value of objective `o` for an evaluation (nullopt when the design was not run).
std::optional<double> objective_value(const Evaluation& e, Objective o);
// A growing measure's value over the run so far (`so_far`: an outcome of a run under way), a lower
// bound of its value over the whole run; none for a measure that does not grow, or not yet (the
// windowed impulse until the run is longer than its window, whose windows are then whole).
std::optional<double> value_so_far(Objective o, const Outcome& so_far, const Space& space);
// Every run measure the space's bottom allows, by name, from one outcome (Evaluation::measures);
// a value that is not finite is left out, and so are the shock measures where the run's series does
// not resolve what they read (shock_measures_unresolved).
std::map<std::string, double> run_measures(const Space& space, const Outcome& o);
// Why the space's shock measures (the channel filter's design frequency, the SRS band's top) cannot
// be taken from a series sampled every `interval` s (model::unresolved), or "".
std::string shock_measures_unresolved(const Space& space, double interval);

}  // namespace granstack::design
