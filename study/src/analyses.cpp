// The named analyses of the catalogue (study/data/catalogue.toml).
#include "analyses.hpp"

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

namespace {

std::string pct(double f) { return fmt::format("{:.3g} %", 100.0 * f); }
std::string num(double v) { return fmt::format("{:.4g}", v); }
std::string num(const std::optional<double>& v) { return v ? num(*v) : "-"; }

// fig2: the candidate readings of "10 and 3 %", and the wave speeds against Nesterenko.
void fig2(const AnalysisInput& in, ExperimentResult& out) {
  Table readings{"Peak kinetic energy of block k over the peak of block 1, four readings, free bottom and bottom wall",
                 {"reading", "bottom", "block 2", "block 3", "block 4"}, {}};
  const std::pair<const char*, const char*> names[] = {{"whole_block", "whole block, peak over the run (reduce's peak/top)"},
                                                       {"leading_peak", "whole block, its first peak"},
                                                       {"column", "impact column, peak over the run"},
                                                       {"column_leading", "impact column, its first peak"}};
  for (const auto* variant : {"free", "wall"}) {
    const auto* r = in.own(variant);
    if (r == nullptr) continue;
    const int nb = r->spec.blocks;
    std::map<std::string, std::vector<double>> v;
    const double top_block = r->blocks.front().peak_ke;
    const auto blocks = block_energies(*r);
    const auto columns = impact_column_energies(*r);
    const double top_column = columns.front().max();
    for (std::size_t k = 0; k < static_cast<std::size_t>(nb); ++k) {
      v["whole_block"].push_back(r->blocks[k].normalised);
      v["leading_peak"].push_back(blocks[k].first_peak() / top_block);
      v["column"].push_back(columns[k].max() / top_column);
      v["column_leading"].push_back(columns[k].first_peak() / top_column);
    }
    for (const auto& [key, label] : names) {
      std::vector<std::string> row{label, variant};
      for (int k = 2; k <= nb; ++k) {
        const double x = v[key][static_cast<std::size_t>(k - 1)];
        out.values[fmt::format("{}.{}.b{}", key, variant, k)] = x;
        row.push_back(pct(x));
      }
      readings.rows.push_back(row);
    }
  }
  out.tables.push_back(readings);

  if (const auto* r = in.own("free")) {
    Table waves{"The leading wave down the impact column of each block (free bottom) against Nesterenko's law",
                {"block", "peak force (N)", "speed (m/s)", "Nesterenko (m/s)", "ratio", "pulses"}, {}};
    double worst = 1.0;
    for (const auto& w : r->waves) {
      std::optional<double> ratio;
      if (w.speed && w.nesterenko_speed) ratio = *w.speed / *w.nesterenko_speed;
      if (ratio) {
        out.values[fmt::format("speed_ratio.free.b{}", w.block)] = *ratio;
        if (std::fabs(*ratio - 1.0) > std::fabs(worst - 1.0)) worst = *ratio;
      }
      waves.rows.push_back({std::to_string(w.block), num(w.peak_force), num(w.speed), num(w.nesterenko_speed), num(ratio),
                            std::to_string(w.pulses)});
    }
    out.values["speed_ratio.worst"] = worst;
    out.tables.push_back(waves);
    out.figures.push_back(energy_figure(*r, in.figures_dir, "fig2_energy", in.gnuplot,
                                        "Fig. 2 re-made: kinetic energy of each block of four steel blocks (free bottom), "
                                        "over the top block's peak; the inset magnifies the lower blocks"));
  }
  if (const auto* r = in.own("wall")) {
    out.figures.push_back(energy_figure(*r, in.figures_dir, "fig2_column_wall", in.gnuplot,
                                        "The reading that gives the paper's 10 and 3 %: the energy of each block's impact "
                                        "column over its peak in block 1, bottom wall",
                                        true));
  }
}

// fig3: output against N_B per e, and the decay fits both ways the study's form allows.
// Fig. 3's outputs: e -> (N_B, E_out/E_in), e from 1 down.
using OutputsByE = std::map<double, std::vector<std::pair<int, double>>, std::greater<>>;

std::string with_error(const ExperimentResult& out, const std::string& key) {
  const auto er = out.errors.find(key);
  const double v = out.values.at(key);
  return er == out.errors.end() ? num(v) : fmt::format("{:.4f} +- {:.4f}", v, er->second);
}

Table output_table(const OutputsByE& by_e) {
  Table t{"Output fraction E_out/E_in (the output sphere after it left the free bottom)", {"N_B"}, {}};
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
  if (origin.covariance) out.errors["alpha.all.origin"] = origin.error(0);
  if (free.covariance) out.errors["alpha.all.free"] = free.error(1);
  out.values["rms_ln_residual.all.origin"] = std::sqrt(origin.rss / static_cast<double>(n));
  out.values["rms_ln_residual.all.free"] = std::sqrt(free.rss / static_cast<double>(n));
  fits.rows.push_back({"all, one alpha", with_error(out, "alpha.all.origin"), with_error(out, "alpha.all.free"),
                       num(std::exp(free.coefficients(0))), std::to_string(xy.size())});
}

// The spread of alpha fitted per e, one way ("origin" or "free").
std::pair<double, double> alpha_range(const OutputsByE& by_e, const ExperimentResult& out, const std::string& way) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& [e, points] : by_e) {
    const auto it = out.values.find(fmt::format("alpha.e{}.{}", e, way));
    if (it == out.values.end()) continue;
    lo = std::min(lo, it->second);
    hi = std::max(hi, it->second);
  }
  return {lo, hi};
}

// fig3: output against N_B per e, and the decay fits both ways the study's form allows.
void fig3(const AnalysisInput& in, ExperimentResult& out) {
  OutputsByE by_e;
  for (const auto& c : in.experiment.cases) {
    const auto* r = in.own(c.name);
    if (r == nullptr) continue;
    const double e = c.spec.restitution.value;
    by_e[e].emplace_back(c.spec.blocks, r->output_fraction);
    out.values[fmt::format("output.e{}.nb{}", e, c.spec.blocks)] = r->output_fraction;
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
  const auto [lo0, hi0] = alpha_range(by_e, out, "origin");
  const auto [lo1, hi1] = alpha_range(by_e, out, "free");
  out.notes.push_back(fmt::format(
      "How well one alpha describes every e: fitted per e, alpha ranges from {:.3f} to {:.3f} through the origin (the "
      "form as written) but only from {:.3f} to {:.3f} with a free prefactor A, which falls with e (the table's A). "
      "One alpha for all e through the origin, {:.3f}, leaves logarithmic residuals of {:.3f} RMS (a factor {:.2f} on "
      "the output): exp(-(alpha/e) N_B) holds for the slope, while damping also takes a share at the first "
      "block that the form without a prefactor does not have.",
      lo0, hi0, lo1, hi1, out.values["alpha.all.origin"], out.values["rms_ln_residual.all.origin"],
      std::exp(out.values["rms_ln_residual.all.origin"])));
  out.figures.push_back(decay_figure(by_e, out.values["alpha.all.origin"], in.figures_dir, in.gnuplot));
}

// friction: how much of the top row's sideways energy friction removes, by width and walls.
void friction(const AnalysisInput& in, ExperimentResult& out) {
  Table t{"Top row of the top block: sideways energy cut and downward energy change against mu = 0",
          {"sides", "top columns", "mu", "sideways cut, first contact", "sideways cut, whole run", "downward change"}, {}};
  std::vector<BarGroup> bars;
  for (const auto* sides : {"free", "walls"}) {
    for (const int cols : {2, 4, 8}) {
      const auto* base = in.own(fmt::format("{}_cols{}_mu0", sides, cols));
      if (base == nullptr) continue;
      const auto stack = model::Stack::build(base->spec);
      // The impact's own pulse: 1.5 striker contact times.
      const double window = 1.5 * model::hertz_contact_time(model::striker_contact(stack), base->spec.striker_speed);
      const double side0 = reduce_column(*base, "energy_parts", "top_row_sideways_J").max_until(window);
      BarGroup g{fmt::format("{}\\n{} columns", std::string(sides) == "free" ? "free sides" : "side walls", cols), {}};
      for (const double mu : {0.1, 0.25}) {
        const auto* r = in.own(fmt::format("{}_cols{}_mu{}", sides, cols, mu));
        if (r == nullptr) continue;
        const auto key = fmt::format("{}.cols{}.mu{}", sides, cols, mu);
        const double first = 1.0 - reduce_column(*r, "energy_parts", "top_row_sideways_J").max_until(window) / side0;
        const double run = 1.0 - r->top_row_sideways_peak / base->top_row_sideways_peak;
        const double down = r->top_row_downward_peak / base->top_row_downward_peak - 1.0;
        out.values["sideways_cut_first." + key] = first;
        out.values["sideways_cut_run." + key] = run;
        out.values["downward_change." + key] = down;
        t.rows.push_back({sides, std::to_string(cols), fmt::format("{}", mu), pct(first), pct(run), fmt::format("{:+.3g} %", 100 * down)});
        g.values.push_back(first);
      }
      bars.push_back(g);
    }
  }
  out.tables.push_back(t);
  if (!bars.empty()) {
    const BarStyle style{"friction_sideways", "Top row of the top block: sideways energy cut by friction",
                         "sideways energy cut, first contact",
                         "Friction: the cut of the top row's sideways energy over the first striker contact, by top-block "
                         "width and side boundary; dashed, the paper's 44 and 75 %",
                         {{"paper, mu = 0.1: 44 %", 0.44}, {"paper, mu = 0.25: 75 %", 0.75}}};
    out.figures.push_back(bar_figure(bars, {"mu = 0.1", "mu = 0.25"}, style, in.figures_dir, in.gnuplot));
  }
}

// What a sensitivity case changes from the main case.
std::string what_changed(const model::StackSpec& main, const model::StackSpec& s) {
  std::vector<std::string> parts;
  for (const auto& [pair, v] : s.restitution.pairs) {
    if (main.restitution.get(pair.first, pair.second) != v) parts.push_back(fmt::format("e({}:{}) = {}", pair.first, pair.second, v));
  }
  for (const auto& m : s.custom_materials) {
    parts.push_back(fmt::format("{}: Y = {:g} GPa, nu = {}", m.name, m.youngs_modulus / 1e9, m.poisson_ratio));
  }
  if (s.duration != main.duration && s.duration) parts.push_back(fmt::format("duration {:g} ms", *s.duration * 1e3));
  return parts.empty() ? "(the model as given)" : fmt::format("{}", fmt::join(parts, "; "));
}

// What in the Teflon experiments brings the output within the paper's band: the claim on the
// main case's output gives the band; each finding is named with its value.
struct BandMatches {
  const Claim* claim = nullptr;
  std::vector<std::string> found;
  void check(double v, const std::string& what) {
    if (claim != nullptr && v >= claim->low && v <= claim->high) found.push_back(fmt::format("{} ({})", what, pct(v)));
  }
  std::string note() const {
    const auto band = fmt::format("[{}, {}]", pct(claim->low), pct(claim->high));
    return found.empty() ? fmt::format("No variation tried gives an output within the paper's band {}.", band)
                         : fmt::format("Within the paper's band {}: {}; nothing else tried.", band, fmt::join(found, "; "));
  }
};

// The sensitivity runs: every case of the experiment against the main one.
void sensitivity_table(const AnalysisInput& in, ExperimentResult& out, const postproc::CaseReduction& main, double paper,
                       BandMatches& matches) {
  Table s{fmt::format("Sensitivity: what moves the output (the paper: {})", pct(paper)),
          {"case", "changed", "output", "over the paper's", "block 2 peak/top"}, {}};
  for (const auto& c : in.experiment.cases) {
    const auto* r = in.own(c.name);
    if (r == nullptr) continue;
    out.values["output." + c.name] = r->output_fraction;
    out.values["block2_peak." + c.name] = r->blocks.at(1).normalised;
    const auto changed = what_changed(main.spec, c.spec);
    s.rows.push_back({c.name, changed, pct(r->output_fraction), num(r->output_fraction / paper), num(r->blocks.at(1).normalised)});
    matches.check(r->output_fraction, changed);
  }
  out.tables.push_back(s);
}

// The main case's output read other ways: definitions and the window after each kick.
std::vector<Kick> output_readings(ExperimentResult& out, const postproc::CaseReduction& main, const Curve& output, double paper,
                                  BandMatches& matches) {
  const auto stack = model::Stack::build(main.spec);
  const auto lib = main.spec.material_library();
  const auto& bottom = stack.blocks().back();
  const auto& m = lib.at(bottom.material);
  const double tc = model::hertz_contact_time(model::sphere_sphere(m, bottom.radius, m, bottom.radius), main.spec.striker_speed);
  const auto k = kicks(output, 2.0 * tc, 1e-4 * output.max());
  Table d{"The output read other ways (main case)", {"reading", "value", "over the paper's"}, {}};
  auto add = [&](const std::string& key, const std::string& label, double v) {
    out.values[key] = v;
    d.rows.push_back({label, pct(v), num(v / paper)});
  };
  add("output_def.final", "output sphere, after it left (granstack's output_fraction)", main.output_fraction);
  add("output_def.peak", "output sphere, peak kinetic energy", main.output_peak_fraction);
  add("output_def.bottom_row_per_sphere", "bottom row's final energy per sphere", main.output_fraction_bottom_row_per_sphere);
  matches.check(main.output_fraction_bottom_row_per_sphere, "the bottom row's energy per sphere");
  for (std::size_t i = 0; i < k.size(); ++i) {
    add(fmt::format("output_def.after_kick{}", i + 1),
        fmt::format("output sphere after kick {} of {} (ends at {:.0f} us)", i + 1, k.size(), k[i].end * 1e6),
        k[i].after / main.e_in);
    matches.check(k[i].after / main.e_in, fmt::format("reading the output after kick {}", i + 1));
  }
  out.values["kicks"] = static_cast<double>(k.size());
  out.tables.push_back(d);
  return k;
}

// The output of the main case of fig4 or the sandwich read several ways, and the sensitivity runs.
void sensitivity(const AnalysisInput& in, ExperimentResult& out, const std::string& main_name, double paper) {
  const auto* main = in.own(main_name);
  if (main == nullptr) return;
  out.values["output." + main_name] = main->output_fraction;
  BandMatches matches;
  for (const auto& c : in.experiment.claims) {
    if (c.quantities.front() == "output." + main_name) matches.claim = &c;
  }
  sensitivity_table(in, out, *main, paper, matches);
  const auto output = series_energy(*main, "output_sphere");
  const auto k = output_readings(out, *main, output, paper, matches);
  if (matches.claim != nullptr) out.notes.push_back(matches.note());
  out.figures.push_back(output_figure(*main, output, k, in.figures_dir, main_name + "_output",
                                      in.gnuplot,
                                      "The output sphere's kinetic energy over E_in against time, its kicks marked; the "
                                      "dashed line is the estimated arrival of the pulse at the bottom face (the automatic "
                                      "duration is 2 of them, 7 with a soft block between stiffer ones)"));
}

void fig4(const AnalysisInput& in, ExperimentResult& out) {
  const auto* r = in.own("steel_on_teflon");
  if (r == nullptr) return;
  sensitivity(in, out, "steel_on_teflon", 0.04);
  const auto& teflon = r->waves.at(1);
  out.values["pulses.teflon"] = teflon.pulses;
  if (const auto* f2 = in.reduction("fig2", "free")) {
    out.values["block2_peak_over_fig2"] = r->blocks.at(1).normalised / f2->blocks.at(1).normalised;
    auto column_leading = [](const postproc::CaseReduction& c) {
      const auto columns = impact_column_energies(c);
      return columns.at(1).first_peak() / columns.front().max();
    };
    out.values["column_leading_over_fig2"] = column_leading(*r) / column_leading(*f2);
    const auto& steel = f2->waves.at(1);
    if (teflon.speed && steel.speed) out.values["speed.teflon_over_steel"] = *teflon.speed / *steel.speed;
    Table w{"Block 2: steel (Fig. 2) against Teflon (Fig. 4)", {"", "peak/top", "pulses", "speed (m/s)", "Nesterenko (m/s)"}, {}};
    w.rows.push_back({"steel, Fig. 2", num(f2->blocks.at(1).normalised), std::to_string(steel.pulses), num(steel.speed),
                      num(steel.nesterenko_speed)});
    w.rows.push_back({"Teflon, Fig. 4", num(r->blocks.at(1).normalised), std::to_string(teflon.pulses), num(teflon.speed),
                      num(teflon.nesterenko_speed)});
    out.tables.push_back(w);
  }
  out.figures.push_back(energy_figure(*r, in.figures_dir, "fig4_energy", in.gnuplot,
                                      "Fig. 4 re-made: kinetic energy of a steel block over a Teflon block, over the top "
                                      "block's peak; the inset magnifies the Teflon block"));
}

void sandwich(const AnalysisInput& in, ExperimentResult& out) { sensitivity(in, out, "sandwich", 0.006); }

// eq3: the striker's speed after an isolated collision against the hard-sphere formula.
// A sphere resting on two smaller ones touching both (model::seat_height): the angle of the
// contact normals from the vertical and the mass ratio kappa = m_small / m_large of Eq. (3).
struct Seat {
  double cos_theta = 0.0, kappa = 0.0;
  double eq3() const {  // v_f / v_i of the large sphere
    const double k = 2.0 * kappa * cos_theta * cos_theta;
    return (1.0 - k) / (1.0 + k);
  }
  double eq5() const {  // transmitted amplitude per branch
    return 0.25 * std::pow(2.0 * cos_theta / (1.0 + 2.0 * kappa * cos_theta * cos_theta), 1.2);
  }
  double eq4() const {  // the symmetric Y-branch of granular chains at the same angle
    return std::pow(2.0 * cos_theta / (2.0 * cos_theta * cos_theta + 1.0), 1.2);
  }
};

Seat seat(double upper_radius, double upper_mass, double lower_radius, double lower_mass) {
  return {model::seat_height(lower_radius, upper_radius) / (upper_radius + lower_radius), lower_mass / upper_mass};
}

// eq3: the striker's speed after an isolated collision against the hard-sphere formula.
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

// eq45: the leading wave's peak force in block k+1 over block k, in the stack of Fig. 2.
void eq45(const AnalysisInput& in, ExperimentResult& out) {
  const auto* r = in.reduction("fig2", "free");
  if (r == nullptr) return;
  Table t{"Peak Hertz force between vertical neighbours of the impact column, block k+1 over block k (Fig. 2's stack)",
          {"interface", "F_m above (N)", "F_m below (N)", "ratio", "Eq. (5)", "Eq. (4)"}, {}};
  const auto stack = model::Stack::build(r->spec);
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k + 1 < r->waves.size(); ++k) {
    const auto& upper = stack.blocks()[k];
    const auto& lower = stack.blocks()[k + 1];
    const auto g = seat(upper.radius, upper.sphere_mass, lower.radius, lower.sphere_mass);
    const double ratio = r->waves[k + 1].peak_force / r->waves[k].peak_force;
    out.values[fmt::format("force_ratio.b{}_b{}", k + 1, k + 2)] = ratio;
    out.values["eq5"] = g.eq5();
    out.values["eq4"] = g.eq4();
    sum += ratio;
    ++n;
    t.rows.push_back({fmt::format("{} -> {}", k + 1, k + 2), num(r->waves[k].peak_force), num(r->waves[k + 1].peak_force),
                      fmt::format("{:.3f}", ratio), fmt::format("{:.3f}", g.eq5()), fmt::format("{:.3f}", g.eq4())});
  }
  if (n > 0) out.values["force_ratio.mean"] = sum / n;
  out.tables.push_back(t);
}

}  // namespace

Analysis find_analysis(const std::string& name) {
  static const std::map<std::string, Analysis> analyses{{"fig2", fig2},         {"fig3", fig3}, {"friction", friction},
                                                         {"fig4", fig4},         {"sandwich", sandwich},
                                                         {"eq3", eq3},           {"eq45", eq45}};
  const auto it = analyses.find(name);
  return it == analyses.end() ? nullptr : it->second;
}

}  // namespace granstack::study
