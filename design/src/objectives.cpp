#include <granstack/design/objectives.hpp>
#include <granstack/design/space.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/shock.hpp>
#include <granstack/postproc/reduce.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace granstack::design {

namespace {
std::optional<double> output_fraction(const Outcome& o, const Space&) { return o.output_fraction; }
std::optional<double> bottom_row_fraction(const Outcome& o, const Space&) { return o.bottom_row_fraction; }
std::optional<double> peak_wall_force(const Outcome& o, const Space&) { return o.peak_wall_force; }
std::optional<double> wall_impulse(const Outcome& o, const Space& s) {
  if (!o.peak_wall_force || s.impulse_window <= 0.0) return std::nullopt;
  return model::peak_window_impulse(o.wall_force, o.wall_force_interval, s.impulse_window);
}
std::optional<double> crush(const Outcome& o, const Space&) { return o.crush; }
std::optional<double> penetration(const Outcome& o, const Space&) { return o.penetration; }
std::optional<double> yield_ratio(const Outcome& o, const Space&) { return o.yield_ratio; }
// A series at the wall force's samples through the space's channel filter, or none without one,
// or where the series does not resolve the filter's design frequency (shock_measures_unresolved
// says so).
std::optional<std::vector<double>> filtered(const std::vector<double>& series, const Outcome& o, const Space& s) {
  if (!o.peak_wall_force || s.cfc == 0) return std::nullopt;
  if (!model::unresolved("", model::channel_design_frequency(s.cfc), o.wall_force_interval).empty()) return std::nullopt;
  return model::channel_filter(series, o.wall_force_interval, s.cfc).values;
}
std::optional<std::vector<double>> filtered_force(const Outcome& o, const Space& s) { return filtered(o.wall_force, o, s); }
std::optional<double> filtered_wall_force(const Outcome& o, const Space& s) {
  const auto f = filtered_force(o, s);
  if (!f) return std::nullopt;
  return f->empty() ? 0.0 : *std::max_element(f->begin(), f->end());
}
// The protected object's acceleration at the series' samples: over a protected plate in the
// dynamics (StackSpec::plate_mass) the plate's own; over a rigid wall the wall's force over the
// space's protected_mass M (the wall holds still in the run: M much heavier than the stack). None
// where neither is given.
std::optional<std::vector<double>> protected_acceleration_series(const Outcome& o, const Space& s) {
  if (!o.peak_wall_force) return std::nullopt;
  if (!o.plate_acceleration.empty()) return o.plate_acceleration;
  if (s.protected_mass <= 0.0) return std::nullopt;
  auto a = o.wall_force;
  for (double& v : a) v /= s.protected_mass;
  return a;
}
// The peak acceleration of the protected object, as an accelerometer on it reads it: through the
// space's channel filter (over a rigid wall the filtered force over M, the filter being linear).
std::optional<double> protected_acceleration(const Outcome& o, const Space& s) {
  const bool plate = !o.plate_acceleration.empty();
  if (!plate && s.protected_mass <= 0.0) return std::nullopt;
  const auto f = filtered(plate ? o.plate_acceleration : o.wall_force, o, s);
  if (!f) return std::nullopt;
  double peak = 0.0;
  for (const double v : *f) peak = std::max(peak, std::fabs(v));
  return plate ? peak : peak / s.protected_mass;
}
// The shock response spectrum of the protected object's acceleration as the run gives it (a
// causal input: the phaseless filter's output starts before the blow).
std::optional<double> srs_peak(const Outcome& o, const Space& s) {
  const auto a = protected_acceleration_series(o, s);
  if (!a || s.srs_high <= 0.0) return std::nullopt;
  if (!model::unresolved("", s.srs_high, o.wall_force_interval).empty()) return std::nullopt;
  return model::shock_response_peak(*a, o.wall_force_interval, s.srs_low, s.srs_high, s.srs_damping).acceleration;
}
double areal_mass(const Evaluation& e) { return e.areal_mass; }
double height(const Evaluation& e) { return e.height; }

const std::vector<ObjectiveDef> kTable{
    {"output_fraction", "of E_in",
     "E_out / E_in: the output sphere's (the bottom row's middle sphere) kinetic energy once it has left the free bottom "
     "face, over the striker's",
     Needs::free_bottom, true, true, output_fraction, nullptr},
    {"bottom_row_fraction", "of E_in", "the whole bottom row's kinetic energy at the end of the run, over E_in",
     Needs::free_bottom, true, true, bottom_row_fraction, nullptr},
    {"peak_wall_force", "N",
     "max over t of F(t), the bottom wall's force on the stack along z, at the in-situ series' samples (every "
     "series_every steps)",
     Needs::wall, true, false, peak_wall_force, nullptr, true},
    {"wall_impulse", "N s",
     "max over the series' sample times t of the integral of F from t to t + tau, tau = [measures] impulse_window, F "
     "linear between the samples: the sustained load, where peak_wall_force is the instant one",
     Needs::wall, true, false, wall_impulse, nullptr, true},
    {"crush", "m",
     "max over the dump's frames and the stack's spheres over the footprint of z(0) - z(t): the stack's largest loss "
     "of height (its stroke; the top surface's travel while the stack crushes as a whole, the layers' under a top row "
     "that sprang back), what a soft stack pays for a low force; the striker's indentation into a top sphere is not "
     "in it. Bound it with [constraints] max_crush",
     Needs::wall, false, false, crush, nullptr, true},
    {"penetration", "m",
     "max over the dump's frames of H - (z_s(t) - R_s): the depth of the striker's lowest point below the stack's "
     "initial top surface z = H; from the seat depth at first touch ((2 - sqrt 3) R_1 for the study's striker), grown "
     "by the striker's indentation and its descent between spheres pushed aside. Bound it with [constraints] "
     "max_penetration",
     Needs::wall, false, false, penetration, nullptr, true},
    {"yield_ratio", "of first yield",
     "max over the dump's frames and every touching pair (and sphere on a wall) of p0 / (1.6 Y): Hertz's peak contact "
     "pressure p0 = 3F / (2 pi a^2) = (2 Y* / pi) sqrt(d / R*) over the pressure at which the pair starts to yield, 1.6 "
     "times the lower yield strength Y of its materials (model/data/materials.toml; Johnson, Contact Mechanics, 6.2); "
     "above 1 a contact yields and the elastic result is a model there. Brittle materials (no Y) are not judged "
     "against each other. Bound it with [constraints] max_yield_ratio",
     Needs::any, true, false, yield_ratio, nullptr, true},
    {"filtered_wall_force", "N",
     "max over t of F(t) through the channel filter of SAE J211-1 / ISO 6487, class [measures] cfc (a phaseless 4-pole "
     "Butterworth, 3 dB down at 5/3 cfc Hz): the peak a load cell under the stack would report",
     Needs::wall, true, false, filtered_wall_force, nullptr},
    {"protected_acceleration", "m/s^2",
     "max over t of |a_cfc(t)|: the peak acceleration of the protected object through the same filter; over a "
     "protected plate in the run (plate_mass, on its mount) the plate's own, over a rigid wall F(t) / M for a mass M = "
     "[measures] protected_mass (kg) rigidly mounted on it (the wall holds still in the run: M much heavier than the "
     "stack)",
     Needs::wall, true, false, protected_acceleration, nullptr},
    {"srs_peak", "m/s^2",
     "the largest value over [measures] srs_band (Hz, 12 natural frequencies an octave) of the maximax shock response "
     "spectrum of the protected object's acceleration (the plate's, or F(t) / M over a rigid wall; unfiltered: the "
     "oscillator is the filter, and a phaseless filter's output starts before the blow), damping ratio [measures] "
     "srs_damping (0.05 unless set): the most a component of any natural frequency in the band, mounted on the "
     "protected mass, would feel",
     Needs::wall, true, false, srs_peak, nullptr},
    {"areal_mass", "kg/m^2", "the lattice's mass over its footprint (Stack::areal_mass: in the strip one top-sphere diameter deep)",
     Needs::any, false, false, nullptr, areal_mass},
    {"height", "m", "the lattice's height, from its bottom face (z = 0) to the top of block 1's top row", Needs::any,
     false, false, nullptr, height},
};
}  // namespace

const std::vector<ObjectiveDef>& objective_table() { return kTable; }

Objective find_objective(std::string_view name) {
  for (const auto& o : kTable) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

std::string_view retired_measure(std::string_view name) {
  if (name == "stroke") {
    return "stroke (the striker's travel from first touch) is no longer measured: it counted the striker's indentation "
           "into a top sphere as the stack's crush. Name crush (the stack's loss of height, max_crush to bound it) or "
           "penetration (the striker's depth below the stack's initial top surface)";
  }
  return {};
}

std::optional<double> value_so_far(Objective o, const Outcome& so_far, const Space& space) {
  if (!o->grows) return std::nullopt;
  const double span = so_far.wall_force_interval * static_cast<double>(so_far.wall_force.size());
  if (o->from_run == wall_impulse && !(span > space.impulse_window + so_far.wall_force_interval)) return std::nullopt;
  return o->from_run(so_far, space);
}

std::string_view measure_rules_changes() {
  return "stroke became crush (the stack's loss of height) and penetration; a blow ends only when no striker is still "
         "coming";
}

std::vector<std::string> run_measure_names() {
  std::vector<std::string> names;
  for (const auto& o : objective_table()) {
    if (o.from_run != nullptr) names.emplace_back(o.name);
  }
  return names;
}

std::string_view to_string(Needs n) {
  switch (n) {
    case Needs::any: return "any";
    case Needs::free_bottom: return "free bottom";
    case Needs::wall: return "bottom wall";
  }
  return "?";
}

std::optional<double> objective_value(const Evaluation& e, Objective o) {
  if (o->geometric != nullptr) return o->geometric(e);
  const auto it = e.measures.find(std::string(o->name));
  if (it == e.measures.end()) return std::nullopt;
  return it->second;
}

std::string shock_measures_unresolved(const Space& space, double interval) {
  if (space.cfc > 0) {
    if (auto why = model::unresolved(fmt::format("the channel filter (cfc = {}, its design frequency)", space.cfc),
                                     model::channel_design_frequency(space.cfc), interval);
        !why.empty()) {
      return why;
    }
  }
  if (space.srs_high > 0.0) return model::unresolved("srs_band (its top)", space.srs_high, interval);
  return "";
}

std::map<std::string, double> run_measures(const Space& space, const Outcome& o) {
  const bool wall = space.fixed.bottom == model::Boundary::wall;
  std::map<std::string, double> out;
  for (const auto& def : kTable) {
    if (def.from_run == nullptr) continue;
    if ((def.needs == Needs::wall && !wall) || (def.needs == Needs::free_bottom && wall)) continue;
    // A value that is not a number is no measure: the design's record says which is missing.
    if (const auto v = def.from_run(o, space); v && std::isfinite(*v)) out.emplace(std::string(def.name), *v);
  }
  return out;
}

Outcome outcome_of(const postproc::CaseReduction& r, const model::StackSpec& ran) {
  const auto res = model::resolve(model::Stack::build(ran));
  const auto last_change = std::llround(r.output_last_change_time / res.dt);
  const double run_time = static_cast<double>(res.steps) * res.dt;
  const bool settled = ran.bottom == model::Boundary::wall
                           ? model::wall_load_settled(r.peak_wall_force_time, run_time, r.final_momentum_ratio)
                           : model::output_settled(last_change, res.steps);
  Outcome o;
  take_shared(o, r);
  o.bottom_row_fraction = r.output_fraction_bottom_row;
  o.output_settled = settled;
  o.run_time = run_time;
  o.steps = res.steps;
  return o;
}

}  // namespace granstack::design
