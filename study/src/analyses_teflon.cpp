// The Teflon experiments (Fig. 4's stack and the sandwich): the output read every way, the
// restitution scan of the Teflon contacts, the output against the block height, and the
// hypotheses that fit both figures at once. The read-outs are the blow's end (each run stops
// there) and a fixed time, two estimated arrivals of the pulse at the bottom face.
#include "analyses.hpp"
#include "analysis_text.hpp"
#include "curves.hpp"
#include "figures.hpp"

#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace granstack::study::analyses {

namespace {

// The fixed read-out time, in estimated arrivals of the pulse at the bottom face: the study's
// automatic duration for a stack without a soft cavity.
constexpr double kReadoutArrivals = 2.0;

// The output sphere of a case: its energy curve and its energy over E_in at the fixed read-out
// time (none when the run stopped before that time without its blow having ended).
struct OutputReadings {
  Curve curve;
  double readout_time = 0.0;  // s
  std::optional<double> at_readout;
  // The run had stopped at its blow's end before the read-out time: at_readout is the output
  // sphere's final energy (nothing reaches it after the blow's end), not a reading at that time.
  bool after_stop = false;
};

OutputReadings output_readings(const postproc::CaseReduction& r) {
  OutputReadings o{series_energy(r, "output_sphere"), 0.0, std::nullopt};
  const auto stack = model::Stack::build(r.spec);
  o.readout_time = kReadoutArrivals * model::resolve(stack).arrival_estimate;
  if (!o.curve.t.empty() && (o.readout_time <= o.curve.t.back() || r.blow_end_time)) {
    // After the blow's end the sphere flies free and its energy stays what it was.
    const auto it = std::upper_bound(o.curve.t.begin(), o.curve.t.end(), o.readout_time);
    const auto i = it == o.curve.t.begin() ? 0 : static_cast<std::size_t>(it - o.curve.t.begin()) - 1;
    o.at_readout = o.curve.y[i] / r.e_in;
    o.after_stop = o.readout_time > o.curve.t.back();
  }
  return o;
}

// The output readings of the cases the Teflon analysis reads (the main case, the restitution
// scan's and the heights'), each case's series read once.
using ReadingsByCase = std::map<std::string, std::pair<const postproc::CaseReduction*, OutputReadings>>;
ReadingsByCase readings_of(const AnalysisInput& in, const std::string& main_name) {
  ReadingsByCase out;
  for (const auto& c : in.experiment.cases) {
    if (c.name != main_name && c.name.rfind("teflon_e", 0) != 0 && c.name.rfind("rows", 0) != 0) continue;
    if (const auto* r = in.own(c.name)) out.emplace(c.name, std::pair{r, output_readings(*r)});
  }
  return out;
}

// The restitution of the Teflon contacts of a case (1 for the main case).
double teflon_restitution(const model::StackSpec& s) {
  for (int k = 1; k <= s.blocks; ++k) {
    if (s.block_material(k) == "teflon") return s.restitution.get("steel", "teflon");
  }
  return s.restitution.value;
}

// A value of the restitution scan, scan.e<E>.<end|arrivals2>: E and the read-out; none for another value.
std::optional<std::pair<double, std::string>> scan_key(const std::string& key) {
  if (key.rfind("scan.e", 0) != 0) return std::nullopt;
  const auto last = key.rfind('.');
  return std::pair{std::stod(key.substr(6, last - 6)), key.substr(last + 1)};
}

// The read-outs' names in values (scan.eE.NAME) and in words.
const std::pair<const char*, const char*> kReadouts[] = {{"end", "at the blow's end"}, {"arrivals2", "at 2 arrivals"}};

// A censored blow's output is no final reading: none.
std::optional<double> end_reading(const postproc::CaseReduction& r) {
  if (r.spec.stop == model::StopRule::blow_end && !r.blow_end_time) return std::nullopt;
  return r.output_fraction;
}

// The fixed-time read-out in a table cell: said to be the final value where the run had stopped.
std::string readout_cell(const OutputReadings& o) {
  if (!o.at_readout) return "-";
  return o.after_stop ? fmt::format("{} (the run had stopped: its final value)", pct(*o.at_readout)) : pct(*o.at_readout);
}

// Each scanned e's output at the blow's end and at the fixed time, as values scan.eE.end and
// scan.eE.arrivals2 (scan_key), with a table.
void restitution_scan(const ReadingsByCase& cases, ExperimentResult& out, const std::string& main_name) {
  Table t{"Restitution of the contacts involving Teflon against the read-out: the output at the blow's end (where each "
          "run stopped, and when) and at a fixed time, 2 estimated arrivals of the pulse at the bottom face",
          {"e (Teflon contacts)", "at the blow's end", "the blow ended at (µs)", "at 2 arrivals", "2 arrivals (µs)"}, {}};
  std::map<double, std::vector<std::string>> rows;
  for (const auto& [name, case_readings] : cases) {
    if (name != main_name && name.rfind("teflon_e", 0) != 0) continue;
    const auto& [r, o] = case_readings;
    const double e = teflon_restitution(r->spec);
    const auto end = end_reading(*r);
    if (end) out.values[fmt::format("scan.e{:g}.end", e)] = *end;
    if (o.at_readout) out.values[fmt::format("scan.e{:g}.arrivals2", e)] = *o.at_readout;
    if (o.after_stop) out.values[fmt::format("readout_after_stop.e{:g}", e)] = 1.0;
    rows[e] = {fmt::format("{:g}", e), end ? pct(*end) : "censored",
               r->blow_end_time ? fmt::format("{:.0f}", *r->blow_end_time * 1e6) : "-", readout_cell(o),
               fmt::format("{:.0f}", o.readout_time * 1e6)};
  }
  for (auto& [e, row] : rows) t.rows.push_back(std::move(row));
  out.tables.push_back(t);
}

// The output against the block height (cases rowsN beside the main case), at the blow's end and
// at the fixed time, as values output.rowsN.
void height_table(const ReadingsByCase& cases, ExperimentResult& out, const std::string& main_name) {
  std::map<int, const std::pair<const postproc::CaseReduction*, OutputReadings>*> by_rows;
  for (const auto& [name, case_readings] : cases) {
    if (name == main_name || name.rfind("rows", 0) == 0) by_rows[case_readings.first->spec.rows] = &case_readings;
  }
  if (by_rows.size() < 2) return;
  Table t{"The output against the block height (every block the same height; 16 and 32 rows with --full)",
          {"rows", "at the blow's end", "at 2 arrivals", "the blow ended at (µs)"}, {}};
  for (const auto& [n, case_readings] : by_rows) {
    const auto& [r, o] = *case_readings;
    const auto end = end_reading(*r);
    if (end) out.values[fmt::format("output.rows{}", n)] = *end;
    t.rows.push_back({std::to_string(n), end ? pct(*end) : "censored", readout_cell(o),
                      r->blow_end_time ? fmt::format("{:.0f}", *r->blow_end_time * 1e6) : "-"});
  }
  out.tables.push_back(t);
}

// The main case's output read other ways: at the blow's end, at the fixed time, its peak and per
// bottom-row sphere.
void main_readings(ExperimentResult& out, const postproc::CaseReduction& main, const OutputReadings& o, double paper) {
  Table d{"The output of the main case read other ways", {"reading", "value", "over the paper's"}, {}};
  auto add = [&](const std::string& key, const std::string& label, std::optional<double> v) {
    if (v) out.values[key] = *v;
    d.rows.push_back({label, v ? pct(*v) : "-", v ? num(*v / paper) : "-"});
  };
  add("output_def.end",
      main.blow_end_time ? fmt::format("output sphere at the blow's end, {:.0f} µs (granstack's output_fraction; primary)",
                                       *main.blow_end_time * 1e6)
                         : "output sphere at the run's end (granstack's output_fraction; primary)",
      end_reading(main));
  add("output_def.at_arrivals2",
      o.after_stop ? fmt::format("output sphere at 2 estimated arrivals of the pulse, {:.0f} µs: after the run had stopped "
                                 "at its blow's end, so its final value, not a reading at that time",
                                 o.readout_time * 1e6)
                   : fmt::format("output sphere at 2 estimated arrivals of the pulse, {:.0f} µs", o.readout_time * 1e6),
      o.at_readout);
  add("output_def.peak", "output sphere, peak kinetic energy", main.output_peak_fraction);
  add("output_def.bottom_row_per_sphere", "bottom row's final energy per sphere", main.output_fraction_bottom_row_per_sphere);
  out.tables.push_back(d);
}

// The cases that change Teflon's modulus or Poisson ratio, against the main case (--full).
void material_sensitivity(const AnalysisInput& in, ExperimentResult& out, const postproc::CaseReduction& main, double paper) {
  Table s{"Sensitivity to Teflon's modulus and Poisson ratio (nominal 1.46 GPa and 0.46)",
          {"case", "changed", "output", "over the main case's", "over the paper's"}, {}};
  for (const auto& c : in.experiment.cases) {
    const auto* r = in.own(c.name);
    if (r == nullptr || c.spec.custom_materials.empty()) continue;
    const auto& m = c.spec.custom_materials.front();
    out.values["output." + c.name] = r->output_fraction;
    s.rows.push_back({c.name, fmt::format("{}: Y = {:g} GPa, nu = {}", m.name, m.youngs_modulus / 1e9, m.poisson_ratio),
                      pct(r->output_fraction), num(r->output_fraction / main.output_fraction), num(r->output_fraction / paper)});
  }
  if (!s.rows.empty()) out.tables.push_back(s);
}

}  // namespace

void teflon_outputs(const AnalysisInput& in, ExperimentResult& out, const std::string& main_name) {
  const auto* main = in.own(main_name);
  if (main == nullptr) return;
  const double paper = in.paper("output." + main_name);
  if (const auto end = end_reading(*main)) out.values["output." + main_name] = *end;
  const auto cases = readings_of(in, main_name);
  const auto& o = cases.at(main_name).second;
  main_readings(out, *main, o, paper);
  material_sensitivity(in, out, *main, paper);
  height_table(cases, out, main_name);
  restitution_scan(cases, out, main_name);
  OutputFigure f{teflon_restitution(main->spec), o.readout_time, paper, {}};
  // e = 0.95: the restitution the note's hypotheses select; 0.9 and 0.5 beside it.
  for (const auto* name : {"teflon_e0.95", "teflon_e0.9", "teflon_e0.5"}) {
    if (const auto it = cases.find(name); it != cases.end()) {
      f.damped.emplace_back(fmt::format("e = {:g} (Teflon contacts)", teflon_restitution(it->second.first->spec)), it->second.second.curve);
    }
  }
  out.figures.push_back(output_figure(*main, o.curve, f, in.figures_dir, main_name + "_output", in.gnuplot,
                                      "The output sphere's kinetic energy over E_in against time, elastic and with the "
                                      "Teflon contacts damped; dotted, where the elastic run's blow ended; dashed, the "
                                      "fixed read-out time (2 estimated arrivals of the pulse) and the paper's value"));
}

namespace {

// Which scanned e values and read-outs put an experiment's output within its claim's band.
struct Fits {
  std::map<double, std::set<std::string>> by_e;  // e -> read-outs within ("final", "kick N")
};

Fits fits_of(const ExperimentResult& r, const Claim& claim) {
  Fits f;
  for (const auto& [key, v] : r.values) {
    const auto scanned = scan_key(key);
    if (!scanned) continue;
    const auto& [e, readout] = *scanned;
    auto& set = f.by_e[e];
    for (const auto& [name, words] : kReadouts) {
      if (readout == name && v >= claim.low && v <= claim.high) set.insert(words);
    }
  }
  return f;
}

std::string list(const std::set<std::string>& s) { return s.empty() ? "none" : fmt::format("{}", fmt::join(s, ", ")); }

// The scan's values of one read-out ("final", "kick1", ...) as e -> output.
std::map<double, double> scan_series(const std::map<std::string, double>& values, const std::string& readout) {
  std::map<double, double> out;
  for (const auto& [key, v] : values) {
    if (const auto scanned = scan_key(key); scanned && scanned->second == readout) out[scanned->first] = v;
  }
  return out;
}

// How the two read-outs of one figure's scan compare: the scanned runs, those whose two read-outs
// give the same output (the output sphere's energy already final at 2 arrivals), and those whose
// run had stopped at its blow's end before 2 arrivals.
struct ReadoutAgreement {
  int runs = 0, same = 0, after_stop = 0;
};
ReadoutAgreement readout_agreement(const ExperimentResult& r) {
  ReadoutAgreement a;
  for (const auto& [e, end] : scan_series(r.values, "end")) {
    const auto at = r.values.find(fmt::format("scan.e{:g}.arrivals2", e));
    if (at == r.values.end()) continue;
    ++a.runs;
    a.same += std::fabs(at->second - end) <= 1e-12 * std::fabs(end) ? 1 : 0;
    a.after_stop += r.values.count(fmt::format("readout_after_stop.e{:g}", e)) != 0 ? 1 : 0;
  }
  return a;
}

std::string agreement_text(const std::string& figure, const ReadoutAgreement& a) {
  if (a.after_stop == a.runs) {
    return fmt::format("{}'s runs all end their blow before 2 arrivals (its output there is the blow's-end value, "
                       "final after it)", figure);
  }
  return fmt::format("{}'s two read-outs give the same output in {} of its {} scanned runs", figure, a.same, a.runs);
}

// The scanned e where both figures fall within their bands, as an interval between the scanned
// values on either side where they do not.
std::string joint_window(const std::map<double, std::set<std::string>>& fig4, const std::map<double, std::set<std::string>>& sandwich) {
  std::vector<double> scanned, within;
  for (const auto& [e, readouts] : fig4) {
    const auto it = sandwich.find(e);
    if (it == sandwich.end()) continue;
    scanned.push_back(e);
    if (!readouts.empty() && !it->second.empty()) within.push_back(e);
  }
  if (within.empty()) return "no scanned e puts both within";
  const auto lo = std::find(scanned.begin(), scanned.end(), within.front());
  const auto hi = std::find(scanned.begin(), scanned.end(), within.back());
  if (hi - lo + 1 != static_cast<long>(within.size())) {
    return fmt::format("both within for e = {}, not one interval of the scan", fmt::join(within, ", "));
  }
  const auto edge = [](std::vector<double>::const_iterator at, std::vector<double>::const_iterator end, double inside, bool above) {
    if (at == end) return fmt::format("beyond the scan's {:g}", inside);
    return above ? fmt::format("between {:g} and {:g}", inside, *at) : fmt::format("between {:g} and {:g}", *at, inside);
  };
  const auto below = lo == scanned.begin() ? scanned.end() : lo - 1;
  return fmt::format("both within for e from {:g} to {:g} (every scanned value between), the window's lower edge {} and "
                     "its upper edge {}",
                     within.front(), within.back(), edge(below, scanned.end(), within.front(), false),
                     edge(hi + 1, scanned.end(), within.back(), true));
}

// The elastic alternative: every figure read per bottom-row sphere (the bottom row's final energy
// over its spheres) at e = 1, against each figure's band.
std::string elastic_alternative(const AnalysisInput& in, const ExperimentResult& sandwich) {
  const auto* fig3 = in.result("fig3");
  const auto* fig4 = in.result("fig4");
  const auto* fig3_claim = in.claim_on("fig3", "output.e1.nb3");
  const auto* fig4_claim = in.claim_on("fig4", "output.steel_on_teflon");
  const auto* own_claim = in.claim_on("sandwich", "output.sandwich");
  if (fig3 == nullptr || fig4 == nullptr || fig3_claim == nullptr) return {};
  const auto value = [](const ExperimentResult& r, const std::string& key) {
    const auto it = r.values.find(key);
    return it == r.values.end() ? std::optional<double>() : std::optional<double>(it->second);
  };
  const auto f4 = value(*fig4, "output_def.bottom_row_per_sphere"), sw = value(sandwich, "output_def.bottom_row_per_sphere");
  const auto f3 = value(*fig3, "output_per_sphere.e1.nb3"), f3_sphere = value(*fig3, "output.e1.nb3");
  if (!f4 || !sw || !f3 || !f3_sphere) return {};
  const auto where = [](double v, const Claim& c) {
    return fmt::format("{} [{:.3g}, {:.3g}]", v >= c.low && v <= c.high ? "within" : "outside", c.low, c.high);
  };
  return fmt::format(
      " The elastic alternative: with no damping, read per bottom-row sphere (the bottom row's final energy over its "
      "spheres), Fig. 4 gives {} ({}) and the sandwich {} ({}); but that reading of Fig. 3's three steel blocks gives {} "
      "({}), where the output sphere gives {} ({}): one reading for every figure rules it out.",
      pct(*f4), where(*f4, *fig4_claim), pct(*sw), where(*sw, *own_claim), pct(*f3), where(*f3, *fig3_claim), pct(*f3_sphere),
      where(*f3_sphere, *fig3_claim));
}

// The hypotheses (a Teflon restitution and a read-out) that put both Fig. 4's and the sandwich's
// output within their bands.
std::string hypotheses(const AnalysisInput& in, const ExperimentResult& sandwich) {
  const auto* fig4_claim = in.claim_on("fig4", "output.steel_on_teflon");
  const auto* own_claim = in.claim_on("sandwich", "output.sandwich");
  const auto* fig4 = in.result("fig4");
  if (fig4_claim == nullptr || own_claim == nullptr || fig4 == nullptr) return {};
  const auto a = fits_of(*fig4, *fig4_claim), b = fits_of(sandwich, *own_claim);
  std::vector<std::string> both, same_readout, fig4_only, sandwich_only, neither;
  for (const auto& [e, readouts] : a.by_e) {
    const auto it = b.by_e.find(e);
    if (it == b.by_e.end()) continue;
    for (const auto& r : readouts) {
      if (it->second.count(r) != 0) same_readout.push_back(fmt::format("e = {:g} {}", e, r));
    }
    if (!readouts.empty() && !it->second.empty()) {
      both.push_back(fmt::format("e = {:g} (Fig. 4: {}; sandwich: {})", e, list(readouts), list(it->second)));
    } else if (!readouts.empty()) {
      fig4_only.push_back(fmt::format("{:g}", e));
    } else if (!it->second.empty()) {
      sandwich_only.push_back(fmt::format("{:g}", e));
    } else {
      neither.push_back(fmt::format("{:g}", e));
    }
  }
  auto join = [](const std::vector<std::string>& v) { return v.empty() ? std::string("no scanned e") : fmt::format("{}", fmt::join(v, ", ")); };
  auto for_e = [&](const std::vector<std::string>& v) { return v.empty() ? std::string("no scanned e") : "e = " + join(v); };
  const auto fig4_readouts = readout_agreement(*fig4), sandwich_readouts = readout_agreement(sandwich);
  // The read-out is no hypothesis where it changes no fit: every scanned e is within with both
  // read-outs or with neither, in both figures.
  bool one_readout = true;
  for (const auto* fits : {&a, &b}) {
    for (const auto& [e, readouts] : fits->by_e) one_readout = one_readout && (readouts.empty() || readouts.size() == std::size(kReadouts));
  }
  // Where the read-out changes no fit, the hypotheses are the restitutions alone.
  std::vector<std::string> both_e;
  for (const auto& [e, readouts] : a.by_e) {
    if (const auto it = b.by_e.find(e); it != b.by_e.end() && !readouts.empty() && !it->second.empty()) both_e.push_back(fmt::format("{:g}", e));
  }
  const auto fits = one_readout
                        ? fmt::format("A Teflon restitution puts both outputs within their bands at once for {}", for_e(both_e))
                        : fmt::format("A Teflon restitution puts both outputs within their bands at once for {}; with one "
                                      "read-out for both figures, for {}",
                                      join(both), same_readout.empty() ? std::string("no scanned e")
                                                                       : fmt::format("{}", fmt::join(same_readout, ", ")));
  return fmt::format(
      "Hypotheses, from the restitution scan of both figures (the restitution of the contacts involving Teflon), both read "
      "at the blow's end and at 2 estimated arrivals of the pulse. {}, and {}{}. {}: {}. The result is consistent with "
      "mild damping of the Teflon contacts, one parameter fitted to two numbers; the damping model's restitution does not "
      "depend on the impact speed, and the paper states none for Fig. 4.{} Fig. 4's output alone falls within its band "
      "for {}; the sandwich's alone for {}; neither for {}.{}",
      agreement_text("Fig. 4", fig4_readouts), agreement_text("the sandwich", sandwich_readouts),
      one_readout ? ": the read-out changes no fit here (every scanned e is within its band with both or with neither), so "
                    "at this height it is no hypothesis"
                  : "",
      fits, joint_window(a.by_e, b.by_e), elastic_alternative(in, sandwich), for_e(fig4_only), for_e(sandwich_only), for_e(neither),
      both.empty() ? " No single Teflon restitution with either read-out explains both figures: damping of the Teflon "
                     "contacts alone does not account for the paper's two values together."
                   : "");
}

void scan_plot(const AnalysisInput& in, ExperimentResult& out) {
  const auto* fig4_claim = in.claim_on("fig4", "output.steel_on_teflon");
  const auto* own_claim = in.claim_on("sandwich", "output.sandwich");
  std::vector<ScanSeries> series;
  std::vector<ScanBand> bands;
  const auto* fig4 = in.result("fig4");
  if (fig4 != nullptr && fig4_claim != nullptr && fig4_claim->paper) {
    bands.push_back({"Fig. 4: the paper's value, its band shaded", fig4_claim->low, fig4_claim->high, *fig4_claim->paper});
    for (const auto& [name, words] : kReadouts) series.push_back({fmt::format("Fig. 4, {}", words), scan_series(fig4->values, name), 0});
  }
  if (own_claim == nullptr || !own_claim->paper) return;
  const int band = static_cast<int>(bands.size());
  bands.push_back({"sandwich: the paper's value, its band shaded", own_claim->low, own_claim->high, *own_claim->paper});
  for (const auto& [name, words] : kReadouts) {
    auto s = scan_series(out.values, name);
    if (!s.empty()) series.push_back({fmt::format("sandwich, {}", words), std::move(s), band});
  }
  out.figures.push_back(scan_figure(series, bands, in.figures_dir, in.gnuplot,
                                    "The restitution scan: each figure's output against the restitution of the contacts "
                                    "involving Teflon, read at the blow's end and at 2 estimated arrivals of the pulse; "
                                    "shaded, each figure's acceptance band around the paper's value (dotted)"));
}

}  // namespace

namespace {

// The lowest steel block's leading pulse against the Teflon block's and against Nesterenko's
// speed, as values speed{PREFIX}.b3_over_b2 and speed_over_nesterenko{PREFIX}.b3.
void sandwich_speeds(const postproc::CaseReduction& r, const std::string& prefix, ExperimentResult& out) {
  const auto& teflon = r.waves.at(1);
  const auto& lowest = r.waves.at(2);
  if (teflon.maximum_speed && lowest.maximum_speed) {
    out.values["speed" + prefix + ".b3_over_b2"] = *lowest.maximum_speed / *teflon.maximum_speed;
  }
  if (lowest.maximum_speed && lowest.nesterenko_speed) {
    out.values["speed_over_nesterenko" + prefix + ".b3"] = *lowest.maximum_speed / *lowest.nesterenko_speed;
  }
}

}  // namespace

void sandwich(const AnalysisInput& in, ExperimentResult& out) {
  const auto* r = in.own("sandwich");
  if (r == nullptr) return;
  teflon_outputs(in, out, "sandwich");
  const auto* steel3 = in.own("steel3");
  if (const auto end = end_reading(*r); end && steel3 != nullptr) out.values["output.sandwich_over_steel3.rows24"] = *end / steel3->output_fraction;
  const auto* r8 = in.own("rows8");
  const auto steel3_rows8 = in.earlier("fig3", "output.e1.nb3");
  if (r8 != nullptr && steel3_rows8) {
    if (const auto end = end_reading(*r8)) out.values["output.sandwich_over_steel3.rows8"] = *end / *steel3_rows8;
  }
  sandwich_speeds(*r, "", out);
  if (r8 != nullptr) sandwich_speeds(*r8, ".rows8", out);
  Table w{"The leading pulse in each block of the sandwich, timed below the block's entrance (its rows reached out of "
          "depth order)",
          {"block", "material", "speed (m/s)", "Nesterenko (m/s)", "ratio", "rows timed", "entrance rows", "pulses", "note"},
          {}};
  for (const auto& b : r->waves) {
    std::optional<double> ratio;
    if (b.maximum_speed && b.nesterenko_speed) ratio = *b.maximum_speed / *b.nesterenko_speed;
    w.rows.push_back({std::to_string(b.block), r->spec.block_material(b.block), num(b.maximum_speed), num(b.nesterenko_speed),
                      num(ratio), std::to_string(b.rows_used), b.rows_entrance > 0 ? fmt::format("1-{}", b.rows_entrance) : "none",
                      std::to_string(b.pulses), b.note});
  }
  out.tables.push_back(w);
  const auto note = hypotheses(in, out);
  if (!note.empty()) out.notes.push_back(note);
  scan_plot(in, out);
}

}  // namespace granstack::study::analyses
