// The named analyses of the catalogue (study/data/catalogue.toml): the registry, and the
// analyses of outputs, scale, friction, the container and the isolated collision.
#include "analyses.hpp"
#include "analysis_text.hpp"
#include "curves.hpp"
#include "figures.hpp"

#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/fit.hpp>
#include <granstack/postproc/least_squares.hpp>

#include <fmt/format.h>

#include <cmath>

namespace granstack::study {

const postproc::CaseReduction* AnalysisInput::reduction(const std::string& exp, const std::string& case_name) const {
  const auto it = cases.find(exp + "/" + case_name);
  if (it == cases.end() || !it->second->reduction) return nullptr;
  return &*it->second->reduction;
}

const ExperimentResult* AnalysisInput::result(const std::string& exp) const {
  for (const auto& r : results) {
    if (r.experiment->name == exp) return &r;
  }
  return nullptr;
}

std::optional<double> AnalysisInput::earlier(const std::string& exp, const std::string& value) const {
  const auto* r = result(exp);
  if (r == nullptr) return std::nullopt;
  const auto it = r->values.find(value);
  return it != r->values.end() && std::isfinite(it->second) ? std::optional<double>(it->second) : std::nullopt;
}

double AnalysisInput::paper(const std::string& quantity) const {
  for (const auto& c : experiment.claims) {
    if (c.quantity == quantity && c.paper) return *c.paper;
  }
  return std::nan("");
}

const Claim* AnalysisInput::claim_on(const std::string& exp, const std::string& quantity) const {
  const auto* r = result(exp);
  if (r == nullptr) return nullptr;
  for (const auto& c : r->experiment->claims) {
    if (c.quantity == quantity) return &c;
  }
  return nullptr;
}

namespace analyses {

double Seat::eq3() const {
  const double k = 2.0 * kappa * cos_theta * cos_theta;
  return (1.0 - k) / (1.0 + k);
}
double Seat::eq5() const { return 0.25 * std::pow(2.0 * cos_theta / (1.0 + 2.0 * kappa * cos_theta * cos_theta), 1.2); }
double Seat::eq4() const { return std::pow(2.0 * cos_theta / (2.0 * cos_theta * cos_theta + 1.0), 1.2); }

Seat seat(double upper_radius, double upper_mass, double lower_radius, double lower_mass) {
  return {model::seat_height(lower_radius, upper_radius) / (upper_radius + lower_radius), lower_mass / upper_mass};
}

namespace {

// Fig. 3's outputs: e -> (N_B, E_out/E_in), e from 1 down.
using OutputsByE = std::map<double, std::vector<std::pair<int, double>>, std::greater<>>;

Table output_table(const OutputsByE& by_e) {
  Table t{"Output fraction E_out/E_in (the output sphere after it left the free bottom), 8 rows", {"N_B"}, {}};
  std::map<int, std::vector<std::string>> rows;
  std::size_t column = 0;
  for (const auto& [e, points] : by_e) {
    t.header.push_back(fmt::format("e = {}", e));
    for (const auto& [nb, f] : points) {
      auto& row = rows[nb];
      row.resize(by_e.size(), "-");
      row[column] = pct(f);
    }
    ++column;
  }
  for (auto& [nb, row] : rows) {
    row.insert(row.begin(), std::to_string(nb));
    t.rows.push_back(row);
  }
  return t;
}

// Per e: ln f = ln A - (alpha/e) N_B with a free A and with A = 1; the values are the study's
// alpha, the slope times e.
void fit_per_e(const OutputsByE& by_e, ExperimentResult& out, Table& fits) {
  for (const auto& [e, points] : by_e) {
    if (points.size() < 2) continue;
    std::vector<int> nbs;
    std::vector<double> fs;
    for (const auto& [nb, f] : points) {
      nbs.push_back(nb);
      fs.push_back(f);
    }
    const auto fit = postproc::fit_decay(nbs, fs);
    const auto key = fmt::format("alpha.e{}", e);
    out.values[key + ".origin"] = fit.alpha_origin * e;
    out.values[key + ".free"] = fit.alpha * e;
    out.values[key + ".prefactor"] = fit.prefactor;
    if (fit.alpha_origin_error) out.errors[key + ".origin"] = *fit.alpha_origin_error * e;
    if (fit.alpha_error) out.errors[key + ".free"] = *fit.alpha_error * e;
    fits.rows.push_back({fmt::format("{}", e), with_error(out, key + ".origin"), with_error(out, key + ".free"),
                         num(fit.prefactor), std::to_string(nbs.size())});
  }
}

// One alpha for every e: ln f = -alpha N/e (origin) and ln f = ln A - alpha N/e (free A).
void fit_all(const OutputsByE& by_e, ExperimentResult& out, Table& fits) {
  std::vector<std::pair<double, double>> xy;  // N/e, ln f
  for (const auto& [e, points] : by_e) {
    for (const auto& [nb, f] : points) xy.emplace_back(nb / e, std::log(f));
  }
  const auto n = static_cast<Eigen::Index>(xy.size());
  Eigen::MatrixXd x0(n, 1), x1(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    x0(i, 0) = x1(i, 1) = -xy[static_cast<std::size_t>(i)].first;
    x1(i, 0) = 1.0;
    y(i) = xy[static_cast<std::size_t>(i)].second;
  }
  const auto origin = postproc::least_squares(x0, y);
  const auto free = postproc::least_squares(x1, y);
  out.values["alpha.all.origin"] = origin.coefficients(0);
  out.values["alpha.all.free"] = free.coefficients(1);
  out.values["prefactor.all.free"] = std::exp(free.coefficients(0));
  if (origin.covariance) out.errors["alpha.all.origin"] = origin.error(0);
  if (free.covariance) out.errors["alpha.all.free"] = free.error(1);
  out.values["rms_ln_residual.all.origin"] = std::sqrt(origin.rss / static_cast<double>(n));
  out.values["output_factor.all.origin"] = std::exp(out.values["rms_ln_residual.all.origin"]);
  fits.rows.push_back({"all, one alpha", with_error(out, "alpha.all.origin"), with_error(out, "alpha.all.free"),
                       num(std::exp(free.coefficients(0))), std::to_string(xy.size())});
}

// The spread of alpha fitted per e, one way ("origin" or "free"), as values ALPHA_WAY.low/high.
void alpha_range(const OutputsByE& by_e, ExperimentResult& out, const std::string& way) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& [e, points] : by_e) {
    const auto it = out.values.find(fmt::format("alpha.e{}.{}", e, way));
    if (it == out.values.end()) continue;
    lo = std::min(lo, it->second);
    hi = std::max(hi, it->second);
  }
  out.values[fmt::format("alpha.{}.lowest", way)] = lo;
  out.values[fmt::format("alpha.{}.highest", way)] = hi;
}

// What the one-alpha claim's summary says: whether the 1/e slope holds once each e has its own
// prefactor (the per-e alphas, the slope times e, span no more than the claim's band is wide), and
// whether that prefactor stays 1 (the form as written fixes it there) to 5 %.
void slope_note(const AnalysisInput& in, ExperimentResult& out) {
  const auto* claim = in.claim_on(in.experiment.name, "alpha.all.origin");
  if (claim == nullptr) return;
  double a_lo = INFINITY, a_hi = -INFINITY;
  for (const auto& [key, v] : out.values) {
    if (key.rfind("alpha.e", 0) == 0 && key.size() > 10 && key.compare(key.size() - 10, 10, ".prefactor") == 0) {
      a_lo = std::min(a_lo, v);
      a_hi = std::max(a_hi, v);
    }
  }
  const double lo = out.values["alpha.free.lowest"], hi = out.values["alpha.free.highest"];
  const bool slope = hi - lo <= claim->high - claim->low, one = a_lo >= 0.95 && a_hi <= 1.05;
  out.claim_notes["alpha.all.origin"] = fmt::format(
      "the 1/e slope {}: fitted per e with a free prefactor, alpha spans {:.3f} to {:.3f}, {} the band's width; the "
      "prefactor {}: A = {:.3f} to {:.3f}",
      slope ? "holds" : "does not hold", lo, hi, slope ? "within" : "more than", one ? "stays 1 to 5 %" : "does not stay 1", a_lo,
      a_hi);
}

}  // namespace

void fig3(const AnalysisInput& in, ExperimentResult& out) {
  OutputsByE by_e;
  for (const auto& c : in.experiment.cases) {
    const auto* r = in.own(c.name);
    if (r == nullptr || c.name.rfind("rows", 0) == 0) continue;
    const double e = c.spec.restitution.value;
    by_e[e].emplace_back(c.spec.blocks, r->output_fraction);
    out.values[fmt::format("output.e{}.nb{}", e, c.spec.blocks)] = r->output_fraction;
    // The bottom row's final energy per sphere: the Teflon note's elastic alternative, read here too.
    out.values[fmt::format("output_per_sphere.e{}.nb{}", e, c.spec.blocks)] = r->output_fraction_bottom_row_per_sphere;
  }
  const auto eight = out.values.find("output.e1.nb3");
  for (const auto* rows : {"rows4", "rows16"}) {
    const auto* r = in.own(rows);
    if (r != nullptr && eight != out.values.end()) out.values[fmt::format("output.{}_over_rows8.nb3", rows)] = r->output_fraction / eight->second;
  }
  // Fig. 3's 8 rows against Fig. 2's tall blocks, four steel blocks each (e = 1).
  const auto four = out.values.find("output.e1.nb4");
  if (const auto* tall = in.reduction("fig2", "free"); tall != nullptr && four != out.values.end()) {
    out.values["output.rows8_over_rows24.nb4"] = four->second / tall->output_fraction;
  }
  Table fits{"Fits of ln(E_out/E_in) = ln A - (alpha/e) N_B per e: alpha (the study's, i.e. the slope times e) with its "
             "standard error",
             {"e", "alpha through the origin", "alpha, free A", "A", "points"}, {}};
  fit_per_e(by_e, out, fits);
  out.tables.push_back(output_table(by_e));
  std::size_t points = 0;
  for (const auto& [e, p] : by_e) points += p.size();
  if (points < 3) {
    out.tables.push_back(fits);
    return;
  }
  fit_all(by_e, out, fits);
  out.tables.push_back(fits);
  alpha_range(by_e, out, "origin");
  alpha_range(by_e, out, "free");
  slope_note(in, out);
  out.notes.push_back(fmt::format(
      "How well one alpha describes every e: fitted per e, alpha ranges from {:.3f} to {:.3f} through the origin (the "
      "form as written) and from {:.3f} to {:.3f} with a free prefactor A (the table's A). One alpha for all e through "
      "the origin, {:.3f}, leaves logarithmic residuals of {:.3f} RMS (a factor {:.3f} on the output).",
      out.values["alpha.origin.lowest"], out.values["alpha.origin.highest"], out.values["alpha.free.lowest"],
      out.values["alpha.free.highest"], out.values["alpha.all.origin"], out.values["rms_ln_residual.all.origin"],
      out.values["output_factor.all.origin"]));
  std::vector<std::pair<int, double>> paper;
  for (int nb = 1; nb <= 4; ++nb) {
    const double p = in.paper(fmt::format("output.e1.nb{}", nb));
    if (std::isfinite(p)) paper.emplace_back(nb, p);
  }
  out.figures.push_back(decay_figure(by_e, out.values["alpha.all.origin"], paper, in.paper("alpha.e1.origin"), in.figures_dir, in.gnuplot));
}

void scale(const AnalysisInput& in, ExperimentResult& out) {
  const auto* base = in.own("r1mm");
  Table t{"Three steel blocks, 8 rows, e = 1: the output against size and speed (against the 1 mm, 1 m/s case)",
          {"case", "bottom radius (m)", "striker speed (m/s)", "dt (s)", "duration (s)", "output", "over 1 mm, 1 m/s"}, {}};
  for (const auto& c : in.experiment.cases) {
    const auto* r = in.own(c.name);
    if (r == nullptr) continue;
    const auto res = model::resolve(model::Stack::build(c.spec));
    std::string ratio = "-";
    if (base != nullptr && c.name != "r1mm") {
      const bool dt = c.name.rfind("dt", 0) == 0;
      const auto key = c.name[0] == 'v' ? fmt::format("output.{}_over_v1", c.name)
                       : dt            ? fmt::format("output.r1mm_over_{}", c.name)
                                       : fmt::format("output.{}_over_r1mm", c.name);
      out.values[key] = dt ? base->output_fraction / r->output_fraction : r->output_fraction / base->output_fraction;
      ratio = fmt::format("{:.6f}", out.values[key]);
    }
    t.rows.push_back({c.name, fmt::format("{:g}", c.spec.bottom_radius), fmt::format("{:g}", c.spec.striker_speed),
                      fmt::format("{:.3g}", res.dt), fmt::format("{:.3g}", res.duration), pct(r->output_fraction), ratio});
  }
  out.tables.push_back(t);
}

// What friction's dissipation predicts for the energy transmitted down (the study's 4 top columns,
// free sides): were the output to lose the share of E_in friction dissipates, it would fall by
// that share; it falls by less.
void friction_note(ExperimentResult& out) {
  const auto value = [&](const std::string& k) {
    const auto it = out.values.find(k);
    return it == out.values.end() ? NAN : it->second;
  };
  const double d1 = value("dissipated.free.cols4.mu0.1"), d25 = value("dissipated.free.cols4.mu0.25");
  const double s1 = value("transmitted_change.free.cols4.mu0.1"), s25 = value("transmitted_change.free.cols4.mu0.25");
  if (!std::isfinite(d1) || !std::isfinite(d25) || !std::isfinite(s1) || !std::isfinite(s25)) return;
  out.notes.push_back(fmt::format(
      "Friction's dissipation (4 top columns, free sides, e = 1): by the run's end friction has dissipated {} of E_in "
      "at mu = 0.1 and {} at mu = 0.25. Were the energy transmitted down to lose that share, the output would change "
      "by -{} and -{}; it changes by {} and {} (friction.4): friction takes less from what goes down than from the "
      "whole (it cuts the top row's sideways motion most: friction.1 and friction.2).",
      pct(d1), pct(d25), pct(d1), pct(d25), fmt::format("{:+.3g} %", 100 * s1), fmt::format("{:+.3g} %", 100 * s25)));
}

void friction(const AnalysisInput& in, ExperimentResult& out) {
  Table t{"Top row of the top block: sideways energy cut, downward energy change, and the change of the energy "
          "transmitted down (the output sphere's), against mu = 0",
          {"sides", "top columns", "mu", "sideways cut, whole run", "sideways cut, first contact", "downward change",
           "transmitted change", "dissipated (of E_in)"},
          {}};
  std::vector<BarGroup> bars;
  for (const auto* sides : {"free", "walls"}) {
    for (const int cols : {2, 4, 8}) {
      const auto* base = in.own(fmt::format("{}_cols{}_mu0", sides, cols));
      if (base == nullptr) continue;
      const auto stack = model::Stack::build(base->spec);
      // The impact's own pulse: 1.5 striker contact times.
      const double window = 1.5 * model::hertz_contact_time(model::striker_contact(stack), base->spec.striker_speed);
      const double side0 = reduce_column(*base, "energy_parts", "top_row_sideways_J").max_until(window);
      // The claims' primary readings are the free strip of 4 columns, over the whole run.
      const bool primary = std::string(sides) == "free" && cols == 4;
      BarGroup g{fmt::format("{}\\n{} columns{}", std::string(sides) == "free" ? "free sides" : "side walls", cols,
                             primary ? "\\n(primary)" : ""),
                 {}};
      std::vector<double> firsts;
      for (const double mu : {0.1, 0.25}) {
        const auto* r = in.own(fmt::format("{}_cols{}_mu{}", sides, cols, mu));
        if (r == nullptr) continue;
        const auto key = fmt::format("{}.cols{}.mu{}", sides, cols, mu);
        const double first = 1.0 - reduce_column(*r, "energy_parts", "top_row_sideways_J").max_until(window) / side0;
        const double run = 1.0 - r->top_row_sideways_peak / base->top_row_sideways_peak;
        const double down = r->top_row_downward_peak / base->top_row_downward_peak - 1.0;
        const double sent = r->output_fraction / base->output_fraction - 1.0;
        out.values["sideways_cut_first." + key] = first;
        out.values["sideways_cut_run." + key] = run;
        out.values["downward_change." + key] = down;
        out.values["transmitted_change." + key] = sent;
        if (r->dissipated_fraction) out.values["dissipated." + key] = *r->dissipated_fraction;
        t.rows.push_back({sides, std::to_string(cols), fmt::format("{}", mu), pct(run), pct(first),
                          fmt::format("{:+.3g} %", 100 * down), fmt::format("{:+.3g} %", 100 * sent),
                          r->dissipated_fraction ? pct(*r->dissipated_fraction) : "-"});
        g.values.push_back(run);
        firsts.push_back(first);
      }
      g.values.insert(g.values.end(), firsts.begin(), firsts.end());
      bars.push_back(g);
    }
  }
  out.tables.push_back(t);
  friction_note(out);
  if (!bars.empty()) {
    BarStyle style{"friction_sideways", "Top row of the top block: sideways energy cut by friction",
                         "sideways energy cut",
                         "Friction: the cut of the top row's sideways energy over the whole run (the first two bars of "
                         "each group) and over the first striker contact (sensitivity: the last two), by top-block width "
                         "and side boundary; the claims read the whole run of the free strip of 4 columns (primary); "
                         "dashed, the paper's values, shaded, each claim's acceptance band",
                         {}, {}};
    for (const double mu : {0.1, 0.25}) {
      const auto quantity = fmt::format("sideways_cut_run.free.cols4.mu{}", mu);
      const double p = in.paper(quantity);
      if (std::isfinite(p)) style.references.emplace_back(fmt::format("paper, mu = {}: {:g} %", mu, 100 * p), p);
      if (const auto* claim = in.claim_on("friction", quantity)) style.bands.emplace_back(claim->low, claim->high);
    }
    out.figures.push_back(bar_figure(bars, {"mu = 0.1, whole run", "mu = 0.25, whole run", "mu = 0.1, first contact",
                                            "mu = 0.25, first contact"},
                                     style, in.figures_dir, in.gnuplot));
  }
}

void container(const AnalysisInput& in, ExperimentResult& out) {
  const auto lone = in.earlier("fig3", "output.e1.nb3");
  Table t{"The container: three panels of three steel blocks, the centre one hit; energies at the last frame over E_in",
          {"separator", "output of the panel hit", "over the lone stack", "neighbouring panels", "matrix", "leaked"}, {}};
  for (const auto* name : {"matrix", "walls"}) {
    const auto* r = in.own(name);
    if (r == nullptr) continue;
    double neighbours = 0.0;
    for (std::size_t p = 0; p < r->panel_final_fraction.size(); ++p) {
      if (static_cast<int>(p) + 1 != r->spec.measured_panel()) neighbours += r->panel_final_fraction[p];
    }
    out.values[fmt::format("neighbours.{}", name)] = neighbours;
    out.values[fmt::format("leaked.{}", name)] = r->leaked_final_fraction;
    std::string over = "-";
    if (lone) {
      out.values[fmt::format("output.{}_over_lone", name)] = r->output_fraction / *lone;
      over = num(r->output_fraction / *lone);
    }
    t.rows.push_back({name, pct(r->output_fraction), over, fmt::format("{:.3g}", neighbours),
                      fmt::format("{:.3g}", r->matrix_final_fraction), fmt::format("{:.3g}", r->leaked_final_fraction)});
  }
  out.tables.push_back(t);
  if (const auto* r = in.own("matrix")) {
    const auto stack = model::Stack::build(r->spec);
    out.figures.push_back(stack_drawing(stack, in.figures_dir, "fig1b_container", in.gnuplot,
                                        "Fig. 1b re-made: the simulated container to scale. Left, the panel hit (x-z plane); "
                                        "right, every sphere seen along x: three panels side by side, the matrix of Teflon "
                                        "spheres (orange) in the gaps that grow block by block, the striker (red) on the "
                                        "centre panel, the output sphere (the panel hit's) in green",
                                        {{stack.output_sphere_id(), 6}}));
  }
}

void eq3(const AnalysisInput& in, ExperimentResult& out) {
  Table t{"v_f/v_i of the striker: Eq. (3) against the run (the engine that ran the cases)",
          {"case", "kappa", "theta (deg)", "Eq. (3)", "measured", "difference"}, {}};
  for (const auto& c : in.experiment.cases) {
    const auto* r = in.own(c.name);
    if (r == nullptr) continue;
    const auto stack = model::Stack::build(c.spec);
    const auto& top = stack.block(1);
    const auto g = seat(stack.striker_radius(), stack.striker_mass(), top.radius, top.sphere_mass);
    const double theory = g.eq3();
    out.values["v_ratio." + c.name] = r->striker_velocity_ratio;
    out.values["v_ratio_eq3." + c.name] = theory;
    t.rows.push_back({c.name, num(g.kappa), fmt::format("{:.2f}", std::acos(g.cos_theta) * 180.0 / M_PI),
                      fmt::format("{:.6f}", theory), fmt::format("{:.6f}", r->striker_velocity_ratio),
                      fmt::format("{:+.2e}", r->striker_velocity_ratio / theory - 1.0)});
  }
  out.tables.push_back(t);
}

}  // namespace analyses

Analysis find_analysis(const std::string& name) {
  using namespace analyses;
  static const std::map<std::string, Analysis> all{{"fig2", fig2},         {"fig3", fig3},       {"scale", scale},
                                                    {"friction", friction}, {"fig4", fig4},       {"sandwich", sandwich},
                                                    {"container", container}, {"eq3", eq3},   {"eq45", eq45},
                                                    {"rows", rows},         {"mechanisms", mechanisms},
                                                    {"plasticity", plasticity}};
  const auto it = all.find(name);
  return it == all.end() ? nullptr : it->second;
}

}  // namespace granstack::study
