// Beyond the paper (#67 item 6): the study when the contacts yield. Thornton's law on refsim for an
// annealed and a hardened steel at three speeds, beside the elastic stacks: Fig. 3's decay with
// depth and each block's share of E_in dissipated by yield, the Teflon sandwich against three
// steel blocks, the friction study's stack; and one block under LIGGGHTS's thornton_ning.
#include "analyses.hpp"
#include "analysis_text.hpp"
#include "figures.hpp"

#include <granstack/postproc/fit.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace granstack::study::analyses {

namespace {

constexpr int kDeepest = 4;                         // the cases' blocks, 1 to 4
constexpr double kSpeeds[] = {0.1, 1.0, 2.0};       // m/s
struct Grade {
  const char* cases;  // the catalogue's case prefix
  const char* label;
  const char* figure;  // its name in a figure's key
};
constexpr Grade kGrades[] = {{"steel", "steel (AISI 304 annealed)", "AISI 304 annealed"},
                             {"steel_4340", "steel_4340 (AISI 4340 quenched and tempered)", "AISI 4340 quenched and tempered"}};

std::string case_name(const std::string& prefix, int blocks, std::optional<double> speed) {
  return speed ? fmt::format("{}_nb{}_v{:g}", prefix, blocks, *speed) : fmt::format("{}_nb{}", prefix, blocks);
}

// One series of Fig. 3: the outputs of 1 to 4 blocks (those that ran), fitted as Fig. 3's decay
// form (e = 1), into `key`'s values and one row of `t`; the ratios of successive outputs (the
// decimation per block) into `ratios`.
// The readings of runs whose blow had not ended at the cap: how many, and the latest time (over the
// run's length) at which such a run's output sphere last changed its energy by 1e-3 of it.
struct Unended {
  int runs = 0;
  double latest_change = 0.0;
  void add(const postproc::CaseReduction& r) {
    if (r.blow_end_time) return;
    ++runs;
    latest_change = std::max(latest_change, r.final_time > 0.0 ? r.output_last_change_time / r.final_time : 1.0);
  }
};

void decay_row(const AnalysisInput& in, const std::string& prefix, std::optional<double> speed, const std::string& label,
               const std::string& figure_label, const std::string& key, ExperimentResult& out, Table& t,
               std::vector<double>& ratios, Unended& unended, std::vector<DecaySeries>& figure) {
  std::vector<int> nbs;
  std::vector<double> fs;
  std::vector<std::string> row{label, speed ? fmt::format("{:g}", *speed) : "any"};
  for (int nb = 1; nb <= kDeepest; ++nb) {
    const auto* r = in.own(case_name(prefix, nb, speed));
    if (r == nullptr || !(r->output_fraction > 0.0)) {
      row.push_back("-");
      continue;
    }
    row.push_back(pct(r->output_fraction));
    unended.add(*r);
    out.values[fmt::format("output.{}.nb{}", key, nb)] = r->output_fraction;
    if (!fs.empty() && nbs.back() == nb - 1) ratios.push_back(r->output_fraction / fs.back());
    nbs.push_back(nb);
    fs.push_back(r->output_fraction);
  }
  if (nbs.size() < 2) {
    row.insert(row.end(), {"-", "-", "-"});
    t.rows.push_back(std::move(row));
    return;
  }
  const auto fit = postproc::fit_decay(nbs, fs);
  DecaySeries series{speed ? fmt::format("{}, {:g} m/s", figure_label, *speed) : figure_label, {}, fit.alpha, fit.prefactor};
  for (std::size_t i = 0; i < nbs.size(); ++i) series.points.emplace_back(nbs[i], fs[i]);
  figure.push_back(std::move(series));
  out.values["alpha." + key + ".origin"] = fit.alpha_origin;
  out.values["alpha." + key + ".free"] = fit.alpha;
  if (fit.alpha_origin_error) out.errors["alpha." + key + ".origin"] = *fit.alpha_origin_error;
  if (fit.alpha_error) out.errors["alpha." + key + ".free"] = *fit.alpha_error;
  row.push_back(with_error(out, "alpha." + key + ".origin"));
  row.push_back(with_error(out, "alpha." + key + ".free"));
  row.push_back(num(fit.prefactor));
  t.rows.push_back(std::move(row));
}

// Where E_in is when four blocks' blow has ended: each block's share dissipated by yield, the
// striker's, and the output.
void dissipation_row(const AnalysisInput& in, const Grade& g, double speed, ExperimentResult& out, Table& t) {
  const auto* r = in.own(case_name(g.cases, kDeepest, speed));
  std::vector<std::string> row{g.label, fmt::format("{:g}", speed)};
  if (r == nullptr || !r->plastic_work_fraction || r->block_plastic_work_fraction.size() != static_cast<std::size_t>(kDeepest)) {
    row.resize(t.header.size(), "-");
    t.rows.push_back(std::move(row));
    return;
  }
  for (int b = 0; b < kDeepest; ++b) {
    const double w = r->block_plastic_work_fraction[static_cast<std::size_t>(b)];
    out.values[fmt::format("dissipated.{}.v{:g}.b{}", g.cases, speed, b + 1)] = w;
    row.push_back(pct(w));
  }
  out.values[fmt::format("dissipated.{}.v{:g}", g.cases, speed)] = *r->plastic_work_fraction;
  row.push_back(pct(r->striker_plastic_work_fraction.value_or(0.0)));
  row.push_back(pct(*r->plastic_work_fraction));
  row.push_back(pct(r->output_fraction));
  t.rows.push_back(std::move(row));
}

// One block under thornton_ning on the reproduction's engine against Thornton's law on refsim.
void check_row(const AnalysisInput& in, const Grade& g, double speed, ExperimentResult& out, Table& t) {
  const auto* thornton = in.own(case_name(g.cases, 1, speed));
  const auto* ning = in.own(fmt::format("{}_v{:g}", g.cases == std::string("steel") ? "ning" : "ning_4340", speed));
  std::vector<std::string> row{g.label, fmt::format("{:g}", speed)};
  if (thornton == nullptr || ning == nullptr) {
    row.resize(t.header.size(), "-");
    t.rows.push_back(std::move(row));
    return;
  }
  const double d = ning->output_fraction / thornton->output_fraction - 1.0;
  out.values[fmt::format("ning_over_thornton.{}.v{:g}", g.cases, speed)] = d;
  row.insert(row.end(), {pct(thornton->output_fraction), pct(ning->output_fraction), fmt::format("{:+.1f} %", 100.0 * d)});
  t.rows.push_back(std::move(row));
}

// The sandwich (steel / Teflon / steel, at Fig. 3's 8 rows) against three steel blocks of the same
// height, elastic and yielding, and where E_in goes in the sandwich: the paper's "less than three
// steel blocks" asked again of stacks that yield.
Table sandwich_table(const AnalysisInput& in, ExperimentResult& out) {
  Table t{"The sandwich (steel / Teflon / steel, 8 rows) against three steel blocks of the same height: the output "
          "when the blow has ended, over E_in, and the share of E_in each of the sandwich's blocks dissipates by yield",
          {"stack", "v (m/s)", "sandwich", "three steel blocks", "sandwich / three steel", "yield: block 1 (steel)",
           "block 2 (Teflon)", "block 3 (steel)", "striker"},
          {}};
  const auto row = [&](const std::string& label, const std::string& key, const std::string& sandwich, const std::string& steel3,
                       std::optional<double> v) {
    const auto name = [&](const std::string& prefix) { return v ? fmt::format("{}_v{:g}", prefix, *v) : prefix; };
    const auto* a = in.own(name(sandwich));
    const auto* b = in.own(name(steel3));
    std::vector<std::string> cells{label, v ? fmt::format("{:g}", *v) : "any"};
    if (a == nullptr || b == nullptr || !(b->output_fraction > 0.0)) {
      cells.resize(t.header.size(), "-");
      t.rows.push_back(std::move(cells));
      return;
    }
    out.values["sandwich." + key] = a->output_fraction;
    out.values["steel3." + key] = b->output_fraction;
    out.values["sandwich_over_steel3." + key] = a->output_fraction / b->output_fraction;
    cells.insert(cells.end(), {pct(a->output_fraction), pct(b->output_fraction), num(a->output_fraction / b->output_fraction)});
    for (std::size_t k = 0; k < 3; ++k) {
      const bool has = k < a->block_plastic_work_fraction.size();
      if (has) out.values[fmt::format("dissipated.sandwich.{}.b{}", key, k + 1)] = a->block_plastic_work_fraction[k];
      cells.push_back(has ? pct(a->block_plastic_work_fraction[k]) : "-");
    }
    cells.push_back(a->striker_plastic_work_fraction ? pct(*a->striker_plastic_work_fraction) : "-");
    t.rows.push_back(std::move(cells));
  };
  row("elastic (Hertz, e = 1)", "elastic", "sandwich_elastic", "steel3_elastic", std::nullopt);
  for (const double v : kSpeeds) row(kGrades[0].label, fmt::format("steel.v{:g}", v), "sandwich", "steel3", v);
  for (const double v : kSpeeds) row(kGrades[1].label, fmt::format("steel_4340.v{:g}", v), "sandwich_4340", "steel3_4340", v);
  return t;
}

// Two steel blocks with Coulomb friction (the friction study's stack, 2 top columns) at 1 m/s:
// the output over E_in against mu, elastic and yielding.
Table friction_table(const AnalysisInput& in, ExperimentResult& out) {
  constexpr double kFrictions[] = {0.0, 0.1, 0.25};
  Table t{"Two blocks with Coulomb friction at 1 m/s (the friction study's stack, 2 top columns): the output when the "
          "blow has ended, over E_in, against mu",
          {"stack", "mu = 0", "mu = 0.1", "mu = 0.25"}, {}};
  const std::pair<const char*, const char*> series[] = {
      {"friction_elastic", "steel, elastic (Hertz, e = 1)"}, {"friction", kGrades[0].label}, {"friction_4340", kGrades[1].label}};
  for (const auto& [prefix, label] : series) {
    std::vector<std::string> cells{label};
    for (const double mu : kFrictions) {
      const auto* r = in.own(fmt::format("{}_mu{:g}", prefix, mu));
      if (r != nullptr) out.values[fmt::format("output.{}.mu{:g}", prefix, mu)] = r->output_fraction;
      cells.push_back(r == nullptr ? "-" : pct(r->output_fraction));
    }
    t.rows.push_back(std::move(cells));
  }
  return t;
}

std::string range_text(const std::vector<double>& v, double scale = 1.0) {
  if (v.empty()) return "-";
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return fmt::format("{:.3g} to {:.3g}", *lo * scale, *hi * scale);
}

// How alpha moves with the speed (for each grade) and with the grade (at each speed), as measured.
std::string trend_text(const ExperimentResult& out) {
  const auto alpha = [&](const char* grade, double v) -> std::optional<double> {
    const auto it = out.values.find(fmt::format("alpha.{}.v{:g}.origin", grade, v));
    return it == out.values.end() ? std::nullopt : std::optional<double>(it->second);
  };
  bool rises = true, harder_lower = true, all = true;
  for (const auto& g : kGrades) {
    for (std::size_t k = 1; k < std::size(kSpeeds); ++k) {
      const auto a = alpha(g.cases, kSpeeds[k - 1]), b = alpha(g.cases, kSpeeds[k]);
      all = all && a && b;
      if (a && b) rises = rises && *b > *a;
    }
  }
  for (const double v : kSpeeds) {
    const auto soft = alpha(kGrades[0].cases, v), hard = alpha(kGrades[1].cases, v);
    all = all && soft && hard;
    if (soft && hard) harder_lower = harder_lower && *hard < *soft;
  }
  if (!all) return "";
  return fmt::format("Alpha {} with the speed for both grades, and the hardened grade's is {} the annealed one's at every "
                     "speed.",
                     rises ? "rises" : "does not rise at every step", harder_lower ? "below" : "not always below");
}

}  // namespace

void plasticity(const AnalysisInput& in, ExperimentResult& out) {
  Table decay{"Output against depth: the output sphere's energy when the blow has ended, over E_in, and Fig. 3's decay "
              "form fitted (e = 1: ln f = -alpha N_B through the origin, and with a free prefactor A)",
              {"stack", "v (m/s)", "N_B = 1", "N_B = 2", "N_B = 3", "N_B = 4", "alpha (through the origin)", "alpha (free A)", "A"},
              {}};
  std::vector<double> elastic_ratios, yielding_ratios, alphas, free_alphas, prefactors;
  Unended unended;
  std::vector<DecaySeries> figure;
  decay_row(in, "elastic", std::nullopt, "steel, elastic (Hertz, e = 1)", "elastic (Hertz, e = 1), any speed", "elastic", out,
            decay, elastic_ratios, unended, figure);
  for (const auto& g : kGrades) {
    for (const double v : kSpeeds) {
      const auto key = fmt::format("{}.v{:g}", g.cases, v);
      decay_row(in, g.cases, v, g.label, g.figure, key, out, decay, yielding_ratios, unended, figure);
      if (const auto a = out.values.find("alpha." + key + ".origin"); a != out.values.end()) alphas.push_back(a->second);
      if (const auto a = out.values.find("alpha." + key + ".free"); a != out.values.end()) free_alphas.push_back(a->second);
      const auto* one = in.own(case_name(g.cases, 1, v));
      const auto* elastic_one = in.own(case_name("elastic", 1, std::nullopt));
      if (one != nullptr && elastic_one != nullptr && elastic_one->output_fraction > 0.0) {
        prefactors.push_back(one->output_fraction / elastic_one->output_fraction);
      }
    }
  }
  out.tables.push_back(std::move(decay));
  if (!figure.empty()) {
    out.figures.push_back(decay_series_figure(figure, "plasticity_decay",
                                              "Output against depth under Thornton's law (annealed AISI 304 and AISI 4340 at "
                                              "0.1, 1 and 2 m/s) beside the elastic stacks, each with A exp(-alpha N_B) "
                                              "fitted (dashed)",
                                              in.figures_dir, in.gnuplot));
  }

  Table where{"Where E_in goes in four blocks when the blow has ended: each block's share dissipated by yield (top "
              "first; half of a contact's work to each of its spheres), the striker's, all of it, and the output",
              {"stack", "v (m/s)", "block 1", "block 2", "block 3", "block 4", "striker", "yield in all", "output"}, {}};
  for (const auto& g : kGrades) {
    for (const double v : kSpeeds) dissipation_row(in, g, v, out, where);
  }
  out.tables.push_back(std::move(where));

  out.tables.push_back(sandwich_table(in, out));
  if (const auto elastic = out.values.find("sandwich_over_steel3.elastic"); elastic != out.values.end()) {
    std::vector<std::string> parts;
    for (const auto& g : kGrades) {
      std::vector<double> r;
      for (const double v : kSpeeds) {
        if (const auto it = out.values.find(fmt::format("sandwich_over_steel3.{}.v{:g}", g.cases, v)); it != out.values.end()) {
          r.push_back(it->second);
        }
      }
      if (!r.empty()) parts.push_back(fmt::format("{} {}", g.cases, range_text(r)));
    }
    out.notes.push_back(fmt::format("The sandwich passes on {:.3g} times what three steel blocks of its height do "
                                    "elastic; yielding, {} times (over the three speeds).",
                                    elastic->second, fmt::join(parts, ", ")));
  }
  out.tables.push_back(friction_table(in, out));

  Table check{"One block under LIGGGHTS's thornton_ning (the reproduction's engine) against Thornton's law (refsim): "
              "the same yield pressures, another unloading",
              {"stack", "v (m/s)", "output, thornton", "output, thornton_ning", "thornton_ning / thornton - 1"}, {}};
  for (const auto& g : kGrades) {
    for (const double v : kSpeeds) check_row(in, g, v, out, check);
  }
  out.tables.push_back(std::move(check));

  if (!yielding_ratios.empty() && !elastic_ratios.empty()) {
    const auto elastic = out.values.find("alpha.elastic.origin");
    out.notes.push_back(fmt::format(
        "Under yield each block still passes on a share of what reaches it: the output over the output of one block "
        "fewer is {} across both grades and speeds (elastic: {}), and Fig. 3's form through the origin gives alpha "
        "{} against {} elastic; with a free prefactor, alpha {}. The first block costs most: one yielding block "
        "passes on {} of what one elastic block does. {}",
        range_text(yielding_ratios), range_text(elastic_ratios), range_text(alphas),
        elastic != out.values.end() ? fmt::format("{:.3g}", elastic->second) : std::string("-"), range_text(free_alphas),
        range_text(prefactors), trend_text(out)));
  }
  if (unended.runs > 0) {
    out.notes.push_back(fmt::format(
        "{} of these runs had not ended their blow at the cap (the cases' table says why); their output sphere's "
        "energy last changed by 1e-3 of it at {:.2g} of the run at the latest, {}.",
        unended.runs, unended.latest_change,
        unended.latest_change < 0.5 ? "so their readings are final" : "so a reading may still change with a longer run"));
  }
}

}  // namespace granstack::study::analyses
