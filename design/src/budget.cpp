// What a search spent its refsim time on, and how far each seed's run has come (#50): per run,
// the share of its time on censored runs, on scenarios that decided no objective and on designs
// off its front, the designs its shortcuts settled early; and its hypervolume and IGD+ against
// the front of every run after each generation's worth of distinct designs, with whether it has
// stopped improving by the report's rule.
#include "report_parts.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <limits>
#include <set>

namespace granstack::design::report_parts {

std::vector<Evaluation> run_designs(const Store& store, int run, const std::vector<Evaluation>& all) {
  std::map<std::string, const Evaluation*> by_digest;
  for (const auto& e : all) by_digest[e.digest] = &e;
  std::vector<Evaluation> mine;
  const auto joins = store.joins(run);
  for (const auto& d : joins) {
    if (const auto it = by_digest.find(d); it != by_digest.end()) mine.push_back(*it->second);
  }
  if (joins.empty() && run == 0) mine = all;  // a store from before the joins: run 0 joined every design
  return mine;
}

std::map<std::size_t, std::vector<std::string>> deciding_scenarios(const Space& space, const Evaluation& e) {
  std::map<std::size_t, std::vector<std::string>> out;
  if (e.scenarios.empty()) return out;
  for (const auto o : space.objectives) {
    if (o->from_run == nullptr) continue;
    const std::string name(o->name);
    if (space.aggregate_of(name) == Aggregate::mean) {
      for (std::size_t k = 0; k < e.scenarios.size(); ++k) out[k].push_back(name + " (mean)");
      continue;
    }
    const auto value = [&](std::size_t k) {
      const auto it = e.scenarios[k].measures.find(name);
      return it == e.scenarios[k].measures.end() ? -std::numeric_limits<double>::infinity() : it->second;
    };
    std::size_t worst = 0;
    for (std::size_t k = 1; k < e.scenarios.size(); ++k) {
      if (value(k) > value(worst)) worst = k;
    }
    out[worst].push_back(name + " (worst)");
  }
  return out;
}

namespace {
// Adds a design's time to `b`: its runs censored, its runs (of a design run in full, within its
// constraints) that decided no objective, and the whole of it when it is off the run's front.
void spend(const Space& space, const Evaluation& e, bool on_front, RunBudget& b) {
  b.seconds += e.seconds;
  if (!on_front) b.off_front += e.seconds;
  if (!e.shortcut.empty()) {
    ++b.settled[e.shortcut];
    b.skipped_runs += space.scenarios.size() - e.scenarios.size();
  }
  b.scenario_runs += std::max<std::size_t>(1, e.scenarios.size()) * (e.spheres > 0 && !e.measures.empty());
  const auto deciding = deciding_scenarios(space, e);
  for (std::size_t k = 0; k < e.scenarios.size(); ++k) {
    const auto& r = e.scenarios[k];
    b.timed = b.timed && (r.seconds > 0.0);
    if (!r.not_final.empty()) b.censored += r.seconds;
    else if (e.feasible && e.shortcut.empty() && deciding.count(k) == 0) b.undecided += r.seconds;
  }
  if (e.scenarios.empty() && !e.feasible && e.violations.find("censored") != std::string::npos) b.censored += e.seconds;
}
}  // namespace

std::vector<RunBudget> run_budgets(const Space& space, const Store& store, const std::vector<Evaluation>& all) {
  std::vector<RunBudget> out;
  for (std::size_t r = 0; r < space.search.seeds.size(); ++r) {
    RunBudget b;
    b.seed = space.search.seeds[r];
    const auto mine = run_designs(store, static_cast<int>(r), all);
    std::set<std::string> front;
    for (const auto& e : pareto_front(space, mine)) front.insert(e.digest);
    for (const auto& e : mine) spend(space, e, front.count(e.digest) > 0, b);
    b.designs = mine.size();
    out.push_back(b);
  }
  return out;
}

postproc::Table budget_table(const std::vector<RunBudget>& budgets) {
  postproc::Table t{"What each seed's run spent refsim's time on, over the designs it joined (a design two runs joined "
                    "counts in both); settled: designs its shortcuts settled before all their scenarios ran",
                    {"seed", "designs", "refsim s", "censored runs", "scenarios deciding no objective", "designs off its front",
                     "settled (censored / constraint / dominated)", "scenario runs not run"}, {}};
  const auto share = [](const RunBudget& b, double x) {
    return b.seconds > 0.0 && b.timed ? fmt::format("{:.1f} %", 100.0 * x / b.seconds) : std::string("-");
  };
  for (const auto& b : budgets) {
    const auto n = [&](const char* k) { return b.settled.count(k) ? b.settled.at(k) : std::size_t{0}; };
    t.rows.push_back({std::to_string(b.seed), std::to_string(b.designs), fmt::format("{:.1f}", b.seconds), share(b, b.censored),
                      share(b, b.undecided), b.seconds > 0.0 ? fmt::format("{:.1f} %", 100.0 * b.off_front / b.seconds) : "-",
                      fmt::format("{} / {} / {}", n("censored"), n("constraint"), n("dominated")), std::to_string(b.skipped_runs)});
  }
  return t;
}

std::vector<Progress> run_progress(const Space& space, const Store& store, const std::vector<Evaluation>& all,
                                   const Normalisation& box) {
  const auto reference = pareto_front(space, all);
  const auto step = static_cast<std::size_t>(space.search.population);
  std::vector<Progress> out;
  for (std::size_t r = 0; r < space.search.seeds.size(); ++r) {
    Progress p;
    p.seed = space.search.seeds[r];
    const auto mine = run_designs(store, static_cast<int>(r), all);
    std::vector<Evaluation> front;  // the front of the designs so far: each point reads only it
    for (std::size_t n = 0; n < mine.size(); ++n) {
      join_front(space, front, mine[n]);
      if ((n + 1) % step != 0 && n + 1 != mine.size()) continue;
      p.points.push_back({n + 1, normalised_hypervolume(space, box, front), igd_plus(space, box, front, reference)});
    }
    out.push_back(std::move(p));
  }
  return out;
}

int convergence_window(const Space& space) { return space.search.stagnation > 0 ? space.search.stagnation : kConvergenceWindow; }

std::string stopped_improving(const Space& space, const Progress& p) {
  const auto k = static_cast<std::size_t>(convergence_window(space));
  if (p.points.size() <= k) return fmt::format("too few designs to tell ({} of the {} generations' worth the rule reads)", p.points.size(), k + 1);
  for (std::size_t i = k; i < p.points.size(); ++i) {
    const double now = p.points[i].hypervolume, then = p.points[i - k].hypervolume;
    if (now - then <= space.search.stagnation_tolerance * now) {
      return fmt::format("stopped improving at {} designs (hypervolume {:.6g})", p.points[i].designs, now);
    }
  }
  const auto& last = p.points.back();
  const double then = p.points[p.points.size() - 1 - k].hypervolume;
  return fmt::format("still improving: the hypervolume rose {:.3g} % over its last {} designs", 100.0 * (last.hypervolume - then) / last.hypervolume,
                     last.designs - p.points[p.points.size() - 1 - k].designs);
}

}  // namespace granstack::design::report_parts
