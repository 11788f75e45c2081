// The Teflon experiments (Fig. 4's stack and the sandwich): the output read every way, the
// restitution scan of the Teflon contacts, and the hypotheses that fit both figures at once.
#include "analyses.hpp"
#include "analysis_text.hpp"
#include "curves.hpp"
#include "figures.hpp"

#include <granstack/model/contact.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace granstack::study::analyses {

namespace {

// The output sphere of a case: its energy curve and the kicks it receives (stretches of change
// separated by at least two contact times of the bottom block's spheres).
struct OutputReadings {
  Curve curve;
  std::vector<Kick> kicks;
};

OutputReadings output_readings(const postproc::CaseReduction& r) {
  OutputReadings o{series_energy(r, "output_sphere"), {}};
  const auto stack = model::Stack::build(r.spec);
  const auto lib = r.spec.material_library();
  const auto& bottom = stack.blocks().back();
  const auto& m = lib.at(bottom.material);
  const double tc = model::hertz_contact_time(model::sphere_sphere(m, bottom.radius, m, bottom.radius), r.spec.striker_speed);
  o.kicks = kicks(o.curve, 2.0 * tc, 1e-4 * o.curve.max());
  return o;
}

// The restitution of the Teflon contacts of a case (1 for the main case).
double teflon_restitution(const model::StackSpec& s) {
  for (int k = 1; k <= s.blocks; ++k) {
    if (s.block_material(k) == "teflon") return s.restitution.get("steel", "teflon");
  }
  return s.restitution.value;
}

// A value of the restitution scan, scan.e<E>.<final|kickN>: E and the read-out; none for another value.
std::optional<std::pair<double, std::string>> scan_key(const std::string& key) {
  if (key.rfind("scan.e", 0) != 0) return std::nullopt;
  const auto last = key.rfind('.');
  return std::pair{std::stod(key.substr(6, last - 6)), key.substr(last + 1)};
}

// Each scanned e's output after every kick, as values scan.eE.kickN (kick N's reading) and
// scan.eE.final (scan_key), with a table.
void restitution_scan(const AnalysisInput& in, ExperimentResult& out, const std::string& main_name) {
  std::map<double, std::pair<double, std::vector<double>>> scan;  // e -> final, after each kick
  for (const auto& c : in.experiment.cases) {
    if (c.name != main_name && c.name.rfind("teflon_e", 0) != 0) continue;
    const auto* r = in.own(c.name);
    if (r == nullptr) continue;
    const auto o = output_readings(*r);
    auto& row = scan[teflon_restitution(c.spec)];
    row.first = r->output_fraction;
    for (const auto& k : o.kicks) row.second.push_back(k.after / r->e_in);
  }
  std::size_t most = 0;
  for (const auto& [e, row] : scan) most = std::max(most, row.second.size());
  Table t{"Restitution of the contacts involving Teflon against the read-out: the output after each kick of the output "
          "sphere, and at the run's end",
          {"e (Teflon contacts)", "final"}, {}};
  for (std::size_t k = 1; k <= most; ++k) t.header.push_back(fmt::format("after kick {}", k));
  for (const auto& [e, row] : scan) {
    out.values[fmt::format("scan.e{:g}.final", e)] = row.first;
    std::vector<std::string> cells{fmt::format("{:g}", e), pct(row.first)};
    for (std::size_t k = 0; k < most; ++k) {
      if (k < row.second.size()) out.values[fmt::format("scan.e{:g}.kick{}", e, k + 1)] = row.second[k];
      cells.push_back(k < row.second.size() ? pct(row.second[k]) : "-");
    }
    t.rows.push_back(cells);
  }
  out.tables.push_back(t);
}

// The main case's output read other ways: the definitions, and after each kick.
void main_readings(ExperimentResult& out, const postproc::CaseReduction& main, const OutputReadings& o, double paper) {
  Table d{"The output of the main case read other ways", {"reading", "value", "over the paper's"}, {}};
  auto add = [&](const std::string& key, const std::string& label, double v) {
    out.values[key] = v;
    d.rows.push_back({label, pct(v), num(v / paper)});
  };
  add("output_def.final", "output sphere, after it left (granstack's output_fraction; primary)", main.output_fraction);
  add("output_def.peak", "output sphere, peak kinetic energy", main.output_peak_fraction);
  add("output_def.bottom_row_per_sphere", "bottom row's final energy per sphere", main.output_fraction_bottom_row_per_sphere);
  for (std::size_t i = 0; i < o.kicks.size(); ++i) {
    add(fmt::format("output_def.after_kick{}", i + 1),
        fmt::format("output sphere after kick {} of {} (ends at {:.0f} us)", i + 1, o.kicks.size(), o.kicks[i].end * 1e6),
        o.kicks[i].after / main.e_in);
  }
  out.values["kicks"] = static_cast<double>(o.kicks.size());
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
  out.values["output." + main_name] = main->output_fraction;
  if (const auto* r8 = in.own("rows8")) out.values["output.rows8"] = r8->output_fraction;
  const auto o = output_readings(*main);
  main_readings(out, *main, o, paper);
  material_sensitivity(in, out, *main, paper);
  restitution_scan(in, out, main_name);
  out.figures.push_back(output_figure(*main, o.curve, o.kicks, paper, in.figures_dir, main_name + "_output", in.gnuplot,
                                      "The output sphere's kinetic energy over E_in against time, its kicks marked; dashed, "
                                      "the paper's value and the estimated arrival of the pulse at the bottom face"));
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
    if (v >= claim.low && v <= claim.high) set.insert(readout == "final" ? "final" : "after kick " + readout.substr(4));
  }
  return f;
}

std::string list(const std::set<std::string>& s) { return s.empty() ? "none" : fmt::format("{}", fmt::join(s, ", ")); }

// The hypotheses (a Teflon restitution and a read-out) that put both Fig. 4's and the sandwich's
// output within their bands.
std::string hypotheses(const AnalysisInput& in, const ExperimentResult& sandwich) {
  const auto* fig4_claim = in.claim_on("fig4", "output.steel_on_teflon");
  const auto* own_claim = in.claim_on("sandwich", "output.sandwich");
  const auto* fig4 = in.result("fig4");
  if (fig4_claim == nullptr || own_claim == nullptr || fig4 == nullptr) return {};
  const auto a = fits_of(*fig4, *fig4_claim), b = fits_of(sandwich, *own_claim);
  std::vector<std::string> both, fig4_only, sandwich_only;
  for (const auto& [e, readouts] : a.by_e) {
    const auto it = b.by_e.find(e);
    if (it == b.by_e.end()) continue;
    if (!readouts.empty() && !it->second.empty()) {
      both.push_back(fmt::format("e = {:g} (Fig. 4: {}; sandwich: {})", e, list(readouts), list(it->second)));
    } else if (!readouts.empty()) {
      fig4_only.push_back(fmt::format("{:g}", e));
    } else if (!it->second.empty()) {
      sandwich_only.push_back(fmt::format("{:g}", e));
    }
  }
  auto join = [](const std::vector<std::string>& v) { return v.empty() ? std::string("no scanned e") : fmt::format("{}", fmt::join(v, ", ")); };
  auto for_e = [&](const std::vector<std::string>& v) { return v.empty() ? std::string("no scanned e") : "e = " + join(v); };
  return fmt::format(
      "Hypotheses, from the restitution scan of both figures (every scanned e, every read-out: the output after each "
      "kick and at the end): a Teflon restitution puts both outputs within their bands at once for {}. Only Fig. 4's "
      "output falls within its band for {}; only the sandwich's for {}.{}",
      join(both), for_e(fig4_only), for_e(sandwich_only),
      both.empty() ? " No single Teflon restitution with any read-out explains both figures: damping of the Teflon "
                     "contacts alone does not account for the paper's two values together."
                   : "");
}

// The scan's values of one read-out ("final", "kick1", ...) as e -> output.
std::map<double, double> scan_series(const std::map<std::string, double>& values, const std::string& readout) {
  std::map<double, double> out;
  for (const auto& [key, v] : values) {
    if (const auto scanned = scan_key(key); scanned && scanned->second == readout) out[scanned->first] = v;
  }
  return out;
}

void scan_plot(const AnalysisInput& in, ExperimentResult& out) {
  const auto* fig4_claim = in.claim_on("fig4", "output.steel_on_teflon");
  const auto* own_claim = in.claim_on("sandwich", "output.sandwich");
  std::vector<ScanSeries> series;
  std::vector<ScanBand> bands;
  const auto* fig4 = in.result("fig4");
  if (fig4 != nullptr && fig4_claim != nullptr && fig4_claim->paper) {
    bands.push_back({"Fig. 4: the paper's value, its band shaded", fig4_claim->low, fig4_claim->high, *fig4_claim->paper});
    series.push_back({"Fig. 4, final", scan_series(fig4->values, "final"), 0});
  }
  if (own_claim == nullptr || !own_claim->paper) return;
  const int band = static_cast<int>(bands.size());
  bands.push_back({"sandwich: the paper's value, its band shaded", own_claim->low, own_claim->high, *own_claim->paper});
  for (const auto* readout : {"kick1", "kick2", "final"}) {
    auto s = scan_series(out.values, readout);
    if (s.empty()) continue;
    series.push_back({std::string("sandwich, ") + (readout == std::string("final") ? "final" : fmt::format("after kick {}", readout + 4)),
                      std::move(s), band});
  }
  out.figures.push_back(scan_figure(series, bands, in.figures_dir, in.gnuplot,
                                    "The restitution scan: each figure's output against the restitution of the contacts "
                                    "involving Teflon, read at the end and after each kick of the output sphere; shaded, "
                                    "each figure's acceptance band around the paper's value (dotted)"));
}

}  // namespace

void sandwich(const AnalysisInput& in, ExperimentResult& out) {
  const auto* r = in.own("sandwich");
  if (r == nullptr) return;
  teflon_outputs(in, out, "sandwich");
  if (const auto steel3 = in.earlier("fig3", "output.e1.nb3")) out.values["output.sandwich_over_steel3"] = r->output_fraction / *steel3;
  const auto& teflon = r->waves.at(1);
  const auto& lowest = r->waves.at(2);
  if (teflon.maximum_speed && lowest.maximum_speed) out.values["speed.b3_over_b2"] = *lowest.maximum_speed / *teflon.maximum_speed;
  if (lowest.maximum_speed && lowest.nesterenko_speed) {
    out.values["speed_over_nesterenko.b3"] = *lowest.maximum_speed / *lowest.nesterenko_speed;
  }
  Table w{"The leading maximum in each block of the sandwich", {"block", "material", "speed (m/s)", "Nesterenko (m/s)", "ratio", "pulses", "note"}, {}};
  for (const auto& b : r->waves) {
    std::optional<double> ratio;
    if (b.maximum_speed && b.nesterenko_speed) ratio = *b.maximum_speed / *b.nesterenko_speed;
    w.rows.push_back({std::to_string(b.block), r->spec.block_material(b.block), num(b.maximum_speed), num(b.nesterenko_speed),
                      num(ratio), std::to_string(b.pulses), b.note});
  }
  out.tables.push_back(w);
  const auto note = hypotheses(in, out);
  if (!note.empty()) out.notes.push_back(note);
  scan_plot(in, out);
}

}  // namespace granstack::study::analyses
