// The elastic model beside a space whose contacts yield (#67): each front design and study design
// run again under Hertz's law with e = 1 (its elastic twin), and the report's section that sets the
// two laws' answers side by side.
#include "report_parts.hpp"

#include <granstack/model/contact.hpp>
#include <granstack/os/workers.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace granstack::design {

bool yields(const Space& space) { return model::normal_law(space.fixed.normal_model).needs_yield; }

model::StackSpec elastic_twin(model::StackSpec spec) {
  const model::StackSpec defaults;
  spec.normal_model = model::NormalModel::hertz;
  spec.restitution = defaults.restitution;  // e = 1 between every pair
  spec.yield_pressure_factor = defaults.yield_pressure_factor;
  spec.order_dependent_yield = defaults.order_dependent_yield;
  return canonical(std::move(spec));
}

Space elastic_reference(const Space& space) {
  auto out = space;
  out.fixed = elastic_twin(space.fixed);
  out.scenarios.clear();
  for (auto sc : space.scenarios) {
    sc.yield_pressure_factor.reset();
    sc.label = sc.label.substr(0, sc.label.find(", p_y "));
    const bool seen = std::any_of(out.scenarios.begin(), out.scenarios.end(), [&](const Scenario& o) { return o.label == sc.label; });
    if (!seen) out.scenarios.push_back(std::move(sc));
  }
  return out;
}

int evaluate_elastic_twins(const Space& space, Store& store, int jobs) {
  if (!yields(space)) return 0;
  const auto elastic = elastic_reference(space);
  const auto have = store.elastic_twins();
  auto designs = pareto_front(space, store.evaluations());
  for (auto& [name, e] : store.study_designs()) designs.push_back(std::move(e));
  std::vector<const Evaluation*> missing;
  for (const auto& e : designs) {
    const bool listed = std::any_of(missing.begin(), missing.end(), [&](const Evaluation* m) { return m->digest == e.digest; });
    if (have.count(e.digest) == 0 && !listed) missing.push_back(&e);
  }
  std::vector<Evaluation> twins(missing.size());
  os::for_each(missing.size(), jobs, [&](std::size_t i) { twins[i] = evaluate_design(elastic, elastic_twin(missing[i]->spec), true); });
  for (std::size_t i = 0; i < missing.size(); ++i) store.put_elastic_twin(missing[i]->digest, twins[i]);
  return static_cast<int>(missing.size());
}

namespace report_parts {
namespace {

// Each value's rank from 1, ties given the mean of the ranks they share.
std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return v[a] < v[b]; });
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) out[order[k]] = 0.5 * static_cast<double>(i + j) + 1.0;
    i = j + 1;
  }
  return out;
}

// Spearman's rank correlation of two lists (Pearson's of their ranks); none where either list
// has every value equal or fewer than three.
std::optional<double> spearman(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 3) return std::nullopt;
  const auto ra = ranks(a), rb = ranks(b);
  const double mean = 0.5 * static_cast<double>(a.size() + 1);
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ab += (ra[i] - mean) * (rb[i] - mean);
    aa += (ra[i] - mean) * (ra[i] - mean);
    bb += (rb[i] - mean) * (rb[i] - mean);
  }
  if (aa == 0.0 || bb == 0.0) return std::nullopt;
  return ab / std::sqrt(aa * bb);
}

// A twin's value of a run objective, or why it has none to rank by (a blow not ended by the cap).
std::string twin_cell(const Evaluation& twin, Objective o) {
  const auto v = objective_value(twin, o);
  if (!v) return "-";
  return twin.violations.find("censored") != std::string::npos ? fmt::format("{:.4g} (censored)", *v) : fmt::format("{:.4g}", *v);
}

std::vector<Objective> run_objectives(const Space& space) {
  std::vector<Objective> out;
  for (const auto o : space.objectives) {
    if (o->from_run != nullptr) out.push_back(o);
  }
  return out;
}

postproc::Table twins_table(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front) {
  const auto law = model::to_string(space.fixed.normal_model);
  postproc::Table t{fmt::format("The front's designs and the study's, under {} and elastic (Hertz, e = 1), in the same "
                                "scenarios",
                                law),
                    {"design", "layers"}, {}};
  for (const auto o : run_objectives(space)) {
    t.header.push_back(fmt::format("{} ({}), {}", to_string(o), unit_of(o), law));
    t.header.push_back("elastic");
    t.header.push_back("elastic / " + std::string(law));
  }
  const auto row = [&](const std::string& name, const Evaluation& e) {
    const auto twin = s.twins.find(e.digest);
    if (twin == s.twins.end()) return;
    std::vector<std::string> cells{name, e.description};
    for (const auto o : run_objectives(space)) {
      const auto mine = objective_value(e, o), theirs = objective_value(twin->second, o);
      cells.push_back(value_text(mine));
      cells.push_back(twin_cell(twin->second, o));
      cells.push_back(mine && theirs && *mine > 0.0 ? fmt::format("{:.3g}", *theirs / *mine) : "-");
    }
    t.rows.push_back(std::move(cells));
  };
  for (std::size_t i = 0; i < front.size(); ++i) row(std::to_string(i + 1), front[i]);
  for (const auto& [name, e] : s.studies) row(name, e);
  return t;
}

// Which front design leads on the first run objective under each law, how the two laws order the
// front (Spearman's rho per run objective), and how many of the front's designs no other twin
// dominates elastic.
std::string orders_text(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front) {
  const auto law = model::to_string(space.fixed.normal_model);
  const auto objectives = run_objectives(space);
  std::vector<const Evaluation*> mine;
  std::vector<Evaluation> twins;
  for (const auto& e : front) {
    if (const auto t = s.twins.find(e.digest); t != s.twins.end()) {
      mine.push_back(&e);
      twins.push_back(t->second);
    }
  }
  if (mine.empty() || objectives.empty()) return "";
  const auto first = objectives.front();
  const auto lead = [&](const auto& value) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < mine.size(); ++i) best = value(i) < value(best) ? i : best;
    const auto at = std::find_if(front.begin(), front.end(), [&](const auto& e) { return e.digest == mine[best]->digest; });
    return fmt::format("#{} ({})", at - front.begin() + 1, mine[best]->description);
  };
  const auto lead_law = lead([&](std::size_t i) { return objective_value(*mine[i], first).value_or(HUGE_VAL); });
  const auto lead_elastic = lead([&](std::size_t i) { return objective_value(twins[i], first).value_or(HUGE_VAL); });
  std::vector<std::string> rhos;
  for (const auto o : objectives) {
    std::vector<double> a, b;
    for (std::size_t i = 0; i < mine.size(); ++i) {
      const auto x = objective_value(*mine[i], o), y = objective_value(twins[i], o);
      if (x && y) {
        a.push_back(*x);
        b.push_back(*y);
      }
    }
    const auto rho = spearman(a, b);
    rhos.push_back(rho ? fmt::format("{} {:.2f}", to_string(o), *rho) : fmt::format("{} - (too few or tied)", to_string(o)));
  }
  const auto elastic_front = pareto_front(elastic_reference(space), twins);
  const auto censored = std::count_if(twins.begin(), twins.end(), [](const auto& t) { return t.violations.find("censored") != std::string::npos; });
  return fmt::format("Least {}: front design {} under {}, {} elastic. The two laws' orders of the front's {} designs "
                     "(Spearman's rank correlation; 1: the same order): {}. Elastic, {} of the {} stay on the front their "
                     "twins make{}.",
                     to_string(first), lead_law, law, lead_elastic, mine.size(), fmt::join(rhos, ", "),
                     elastic_front.size(), mine.size(),
                     censored > 0 ? fmt::format(" ({} elastic twin{} censored: a lossless blow that has not ended by the "
                                                "cap, outside the front)", censored, censored == 1 ? "" : "s")
                                  : "");
}

// Against each study design: the front's best at equal or lower areal mass (under the space's law)
// and how many times less it takes of the first run objective, under each law.
std::string factors_text(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front) {
  const auto objectives = run_objectives(space);
  if (objectives.empty()) return "";
  const auto o = objectives.front();
  const auto law = model::to_string(space.fixed.normal_model);
  std::vector<std::string> parts;
  for (const auto& [name, study] : s.studies) {
    const Evaluation* best = nullptr;
    for (const auto& f : front) {
      if (f.areal_mass > study.areal_mass || !objective_value(f, o)) continue;
      if (best == nullptr || *objective_value(f, o) < *objective_value(*best, o)) best = &f;
    }
    const auto st = s.twins.find(study.digest);
    if (best == nullptr || st == s.twins.end() || s.twins.count(best->digest) == 0) continue;
    const auto& bt = s.twins.at(best->digest);
    const auto a = objective_value(study, o), b = objective_value(*best, o), c = objective_value(st->second, o),
               d = objective_value(bt, o);
    if (!a || !b || !c || !d || *b <= 0.0 || *d <= 0.0) continue;
    const bool censored = (study.violations + st->second.violations).find("censored") != std::string::npos;
    parts.push_back(fmt::format("{} takes {:.3g} times the {} of {} under {}, {:.3g} times elastic{}", name, *a / *b,
                                to_string(o), best->description, law, *c / *d, censored ? " (a censored baseline)" : ""));
  }
  if (parts.empty()) return "";
  return fmt::format("Against the study's designs, each beside the front's best at its areal mass or lighter under {} "
                     "(above 1: the front's design takes less): {}.",
                     law, fmt::join(parts, "; "));
}

}  // namespace

std::vector<postproc::Block> elastic_blocks(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front) {
  if (!yields(space) || s.twins.empty()) return {};
  const auto law = model::to_string(space.fixed.normal_model);
  std::vector<postproc::Block> d;
  d.push_back(postproc::Heading{2, "Beside the elastic model", "elastic"});
  d.push_back(postproc::Paragraph{fmt::format(
      "This search's contacts yield ({}: docs/physics.md section 7). The study's model and an elastic search take "
      "them elastic (Hertz, e = 1): each front design and study design run again so, in the same scenarios (those "
      "that differ only in the yield pressure are one blow elastic), shows what the elastic model would have "
      "answered. {}",
      law, orders_text(space, s, front))});
  if (const auto f = factors_text(space, s, front); !f.empty()) d.push_back(postproc::Paragraph{f});
  d.push_back(twins_table(space, s, front));
  return d;
}

}  // namespace report_parts
}  // namespace granstack::design
