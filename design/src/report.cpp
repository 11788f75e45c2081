#include "report_parts.hpp"

#include <granstack/design/convergence.hpp>
#include <granstack/design/report.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/model/spec_fields.hpp>
#include <granstack/model/version.hpp>
#include <granstack/postproc/document.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <regex>
#include <set>

namespace granstack::design {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace report_parts;

namespace report_parts {

// Each run's designs, from its joins (a store from before them: run 0 joined every design).
std::vector<RunSummary> summarise_runs(const Space& space, const Store& store, const std::vector<Evaluation>& all,
                                       const std::vector<Generation>& generations) {
  std::vector<RunSummary> out;
  const auto box = stored_normalisation(store);
  const auto front = pareto_front(space, all);
  for (std::size_t r = 0; r < space.search.seeds.size(); ++r) {
    RunSummary s{static_cast<int>(r), space.search.seeds[r], 0, -1, 0.0, 0.0, 0};
    const auto mine = run_designs(store, s.run, all);
    for (const auto& g : generations) {
      if (g.run != s.run) continue;
      s.last_generation = g.index;
      s.hypervolume = g.hypervolume;
    }
    s.designs = mine.size();
    if (box && !mine.empty()) s.igd_plus = igd_plus(space, *box, mine, front);
    std::set<std::string> found;
    for (const auto& e : mine) found.insert(e.digest);
    s.on_front = static_cast<std::size_t>(std::count_if(front.begin(), front.end(), [&](const auto& e) { return found.count(e.digest) > 0; }));
    out.push_back(s);
  }
  return out;
}

}  // namespace report_parts

namespace {

// The hypervolume over the runs that finished a generation: "mean M, standard deviation S, from A to B".
std::string hypervolume_spread(const std::vector<RunSummary>& runs) {
  std::vector<double> v;
  for (const auto& r : runs) {
    if (r.last_generation >= 0) v.push_back(r.hypervolume);
  }
  if (v.empty()) return "no run has finished a generation";
  double mean = 0.0, var = 0.0;
  for (const double x : v) mean += x / static_cast<double>(v.size());
  for (const double x : v) var += (x - mean) * (x - mean) / static_cast<double>(std::max<std::size_t>(1, v.size() - 1));
  return fmt::format("mean {:.6g}, standard deviation {:.3g}, from {:.6g} to {:.6g} over {} seed(s)", mean, std::sqrt(var),
                     *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()), v.size());
}

std::vector<std::string> objective_cells(const Space& space, const Evaluation& e) {
  std::vector<std::string> cells;
  for (const auto o : space.objectives) cells.push_back(value_text(objective_value(e, o)));
  return cells;
}

std::vector<std::string> objective_headers(const Space& space) {
  std::vector<std::string> h;
  for (const auto o : space.objectives) h.push_back(fmt::format("{} ({})", to_string(o), unit_of(o)));
  return h;
}

// The measures a design table shows: the objectives, then every other run measure the space's
// bottom allows (what each run also measured: the crush beside a force objective, say).
std::vector<Objective> shown_measures(const Space& space) {
  auto shown = space.objectives;
  const bool wall = space.fixed.bottom == model::Boundary::wall;
  for (const auto& def : objective_table()) {
    const bool allowed = def.from_run != nullptr && !(def.needs == Needs::wall && !wall) && !(def.needs == Needs::free_bottom && wall);
    if (allowed && std::find(shown.begin(), shown.end(), &def) == shown.end()) shown.push_back(&def);
  }
  return shown;
}
// Each shown measure's header says whether it is searched (an objective), bounded (a constraint,
// with its bound) or only reported.
std::vector<std::string> measure_headers(const Space& space) {
  std::vector<std::string> h;
  for (const auto o : shown_measures(space)) {
    const bool objective = std::find(space.objectives.begin(), space.objectives.end(), o) != space.objectives.end();
    const auto bound = space.constraints.max_measures.find(std::string(o->name));
    std::string role = objective ? "" : ", reported";
    if (bound != space.constraints.max_measures.end()) role = fmt::format(", <= {:.4g}", bound->second);
    h.push_back(fmt::format("{} ({}{})", to_string(o), unit_of(o), role));
  }
  return h;
}
std::vector<std::string> measure_cells(const Space& space, const Evaluation& e) {
  std::vector<std::string> cells;
  for (const auto o : shown_measures(space)) cells.push_back(value_text(objective_value(e, o)));
  return cells;
}

// For each objective but the areal mass, the front's design at most as heavy as `e` that does
// best in it: how much better the search does at equal or lower mass.
std::string versus_front(const Space& space, const Evaluation& e, const std::vector<Evaluation>& front) {
  std::vector<std::string> parts;
  for (const auto o : space.objectives) {
    const auto mine = objective_value(e, o);
    if (!mine || o == find_objective("areal_mass")) continue;
    const Evaluation* best = nullptr;
    for (const auto& f : front) {
      if (f.areal_mass > e.areal_mass) continue;
      if (best == nullptr || *objective_value(f, o) < *objective_value(*best, o)) best = &f;
    }
    if (best == nullptr) return "no front design is as light";
    parts.push_back(fmt::format("{} {:.4g}, {:.3g} times less ({}, {:.4g} kg/m^2)", to_string(o), *objective_value(*best, o),
                                *mine / *objective_value(*best, o), best->description, best->areal_mass));
  }
  return parts.empty() ? "-" : fmt::format("{}", fmt::join(parts, "; "));
}

std::string run_line(const Space& space, const Snapshot& s) {
  const auto& gens = s.generations;
  double seconds = 0.0;
  for (const auto& e : s.all) seconds += e.seconds;
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  int last = -1;
  for (const auto& g : gens) last = std::max(last, g.index);
  return fmt::format("granstack {} ({}), {}. {} (pagmo2), {}, population {}, generations 0 to {}, seed{} {}; {} distinct "
                     "designs evaluated in situ on refsim ({:.1f} s of refsim in all). Space digest {}.",
                     granstack::version(), granstack::git_commit(), date, to_string(space.search.algorithm),
                     to_string(space.search.schedule), space.search.population,
                     last, space.search.seeds.size() > 1 ? "s" : "", fmt::join(space.search.seeds, ", "), s.all.size(), seconds,
                     space.digest().substr(0, 12));
}

postproc::Table space_table(const Space& space) {
  postproc::Table t{"The design space", {"what", "values"}, {}};
  t.rows.push_back({"blocks", fmt::format("{} to {}", space.min_blocks, space.max_blocks)});
  t.rows.push_back({"materials (per block)", fmt::format("{}", fmt::join(space.materials, ", "))});
  t.rows.push_back({"radius ratio (per interface)", fmt::format("{}", fmt::join(space.radius_ratios, ", "))});
  t.rows.push_back({"rows (per block)", fmt::format("{} to {}", space.min_rows, space.max_rows)});
  t.rows.push_back({"footprint", fmt::format("{} top columns of radius {:.4g} m", space.fixed.top_columns, space.top_radius)});
  if (space.scenarios.empty()) t.rows.push_back({"striker", fmt::format("{} m/s", space.fixed.striker_speed)});
  t.rows.push_back({"bottom", std::string(model::to_string(space.fixed.bottom))});
  t.rows.push_back({"sides", space.fixed.sides == model::Boundary::wall
                                 ? "rigid side walls beside the stack (confined: a design space's default)"
                                 : "free (sides = \"free\"): a strip that may splay sideways"});
  const auto& c = space.constraints;
  std::string measures;
  for (const auto& [name, bound] : c.max_measures) measures += fmt::format(", {} <= {:.4g} {}", name, bound, find_objective(name)->unit);
  t.rows.push_back({"constraints", fmt::format("spheres <= {}, height <= {} m, areal mass <= {} kg/m^2{}",
                                               c.max_spheres ? std::to_string(*c.max_spheres) : "any", c.max_height ? value_text(c.max_height) : "any",
                                               c.max_areal_mass ? value_text(c.max_areal_mass) : "any", measures)});
  if (!space.scenarios.empty()) {
    std::vector<std::string> labels, how;
    for (const auto& sc : space.scenarios) labels.push_back(sc.label);
    for (const auto o : space.objectives) {
      if (o->from_run != nullptr) how.push_back(fmt::format("{}: {}", o->name, to_string(space.aggregate_of(o->name))));
    }
    t.rows.push_back({"scenarios", fmt::format("{} (each run objective over them: {})", fmt::join(labels, "; "), fmt::join(how, ", "))});
  }
  return t;
}

// The spec files of the front's `rank`th design after `generation` (write_front_specs): the run the
// store measured, or with scenarios each one that decided an objective, with the scenario's place
// and the objectives it decided.
struct FrontFile {
  std::string name;
  std::optional<std::size_t> scenario;
  std::vector<std::string> decides;
};
std::vector<FrontFile> front_files(const Space& space, const Evaluation& e, int generation, std::size_t rank) {
  if (e.scenarios.empty()) return {{front_file_name(generation, rank, e.digest), std::nullopt, {}}};
  std::vector<FrontFile> files;
  for (auto& [k, decides] : deciding_scenarios(space, e)) {
    files.push_back({front_file_name(generation, rank, e.digest, static_cast<int>(k) + 1), k, std::move(decides)});
  }
  return files;
}

postproc::Table front_table(const Space& space, const std::vector<Evaluation>& front, int generation) {
  postproc::Table t{"The Pareto front: no other evaluated design is better in every objective", {"#", "design", "spheres"}, {}};
  for (const auto& h : measure_headers(space)) t.header.push_back(h);
  t.header.push_back("spec files");
  for (std::size_t i = 0; i < front.size(); ++i) {
    std::vector<std::string> row{std::to_string(i + 1), front[i].description, std::to_string(front[i].spheres)};
    for (auto& c : measure_cells(space, front[i])) row.push_back(std::move(c));
    std::vector<std::string> names;
    for (const auto& f : front_files(space, front[i], generation, i + 1)) names.push_back("front/" + f.name);
    row.push_back(fmt::format("{}", fmt::join(names, ", ")));
    t.rows.push_back(std::move(row));
  }
  return t;
}

// Where the front's designs leave the elastic model (docs/physics.md section 7): the designs whose
// largest contact pressure passes first yield, and the share of all evaluated designs that do.
std::string yield_text(const Space& space, const std::vector<Evaluation>& front, const std::vector<Evaluation>& all) {
  const auto yield = find_objective("yield_ratio");
  std::vector<std::string> beyond;
  double largest = 0.0;
  bool judged = false;
  for (std::size_t i = 0; i < front.size(); ++i) {
    const auto r = objective_value(front[i], yield);
    if (!r) continue;
    judged = true;
    largest = std::max(largest, *r);
    if (*r > 1.0) beyond.push_back(fmt::format("{} ({:.3g})", i + 1, *r));
  }
  if (!judged) {
    return "First yield: the front's designs were not judged (their contacts are not Hertz's, or they were measured "
           "before granstack judged it).";
  }
  long measured = 0, yielding = 0;
  for (const auto& e : all) {
    if (const auto r = objective_value(e, yield)) {
      ++measured;
      yielding += *r > 1.0 ? 1 : 0;
    }
  }
  const auto share = fmt::format("{} of the {} designs judged ({:.0f} %) press a contact beyond first yield.", yielding,
                                 measured, 100.0 * static_cast<double>(yielding) / static_cast<double>(measured));
  if (yields(space)) {  // the contacts yield in the model: the ratio says how far past first yield, not a model's limit
    return fmt::format("First yield: {} of the front's {} designs press a contact beyond it{}{}. Under {} the contacts "
                       "yield there, dissipate and keep a dent, as the material does (docs/physics.md section 7): the "
                       "ratio (the Hertz pressure of the largest overlap over first yield's) says how far into the "
                       "plastic range, not where the model stops holding. {}",
                       beyond.size(), front.size(), beyond.empty() ? "" : ": ", fmt::join(beyond, ", "),
                       model::to_string(space.fixed.normal_model), share);
  }
  if (beyond.empty()) {
    return fmt::format("First yield: every front design stays below it (largest yield_ratio {:.3g}): its contacts are "
                       "elastic, as the model has them. {}", largest, share);
  }
  return fmt::format("First yield: front design{} {} press{} a contact beyond first yield (yield_ratio, the largest "
                     "Hertz pressure over 1.6 times the softer yield strength, above 1): the contact yields there, and "
                     "the elastic result is a model, not the material (a real stack dissipates there and deforms for "
                     "good; docs/physics.md section 7). {}",
                     beyond.size() > 1 ? "s" : "", fmt::join(beyond, ", "), beyond.size() > 1 ? "" : "es", share);
}

// What the protected mass is (a division of the wall's force, the wall rigid) and how it compares
// with the front's stacks: M over each one's mass, a stack's mass being its areal mass over the
// space's one footprint.
std::string protected_mass_text(const Space& space, const std::vector<Evaluation>& front) {
  const bool plate = space.fixed.has_plate();
  const double mass = plate ? space.fixed.plate_mass : space.protected_mass;
  if (mass <= 0.0 || front.empty()) return "";
  const double footprint = model::Stack::build(front.front().spec).footprint_area();
  double lo = HUGE_VAL, hi = 0.0;
  for (const auto& e : front) {
    const double ratio = mass / (e.areal_mass * footprint);
    lo = std::min(lo, ratio);
    hi = std::max(hi, ratio);
  }
  if (plate) {
    return fmt::format("The protected object: a plate of M = {:g} kg that the stack strikes, in the run, on a mount of "
                       "stiffness {:g} N/m and damping {:g} N s/m; protected_acceleration and srs_peak read its own "
                       "acceleration. M is {:.3g} to {:.3g} times the mass of the front's stacks over the footprint.",
                       mass, space.fixed.mount_stiffness, space.fixed.mount_damping, lo, hi);
  }
  return fmt::format("The protected object: protected_acceleration and srs_peak divide the wall's force by M = {:g} kg, "
                     "the wall rigid: M is not moved by the blow. M is {:.3g} to {:.3g} times the mass of the front's "
                     "stacks over the footprint; where it is not many times a stack's, the object would move under the "
                     "blow, and the rigid wall overstates what it feels.",
                     space.protected_mass, lo, hi);
}

// Each front design's run objectives in each scenario: the spread its aggregate hides.
postproc::Table scenario_table(const Space& space, const std::vector<Evaluation>& front) {
  postproc::Table t{"The front's designs in each scenario", {"#", "scenario"}, {}};
  std::vector<Objective> run;
  for (const auto o : space.objectives) {
    if (o->from_run != nullptr) run.push_back(o);
  }
  for (const auto o : run) t.header.push_back(fmt::format("{} ({})", o->name, o->unit));
  t.header.push_back("decides");
  for (std::size_t i = 0; i < front.size(); ++i) {
    const auto deciding = deciding_scenarios(space, front[i]);
    for (std::size_t k = 0; k < front[i].scenarios.size(); ++k) {
      const auto& r = front[i].scenarios[k];
      std::vector<std::string> row{std::to_string(i + 1), r.label};
      for (const auto o : run) {
        const auto v = r.measures.find(std::string(o->name));
        row.push_back(v == r.measures.end() ? "-" : fmt::format("{:.4g}", v->second));
      }
      const auto d = deciding.find(k);
      row.push_back(d == deciding.end() ? "-" : fmt::format("{}", fmt::join(d->second, ", ")));
      t.rows.push_back(std::move(row));
    }
  }
  return t;
}

postproc::Table study_table(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front) {
  postproc::Table t{"The study's designs at the same footprint and settings, against the front", {"design", "layers", "within the constraints"}, {}};
  for (const auto& h : measure_headers(space)) t.header.push_back(h);
  t.header.push_back("the front's best at equal or lower areal mass");
  for (const auto& [name, e] : s.studies) {
    std::vector<std::string> row{name, e.description, e.feasible ? "yes" : "no: " + e.violations};
    for (auto& c : measure_cells(space, e)) row.push_back(std::move(c));
    // Against a baseline outside the constraints (a censored blow's measures are not final) the
    // factors are said to be so.
    const auto versus = versus_front(space, e, front);
    row.push_back(e.feasible || versus == "-" ? versus
                                              : fmt::format("{} (against a baseline outside the constraints: {})", versus,
                                                            e.violations.substr(0, e.violations.find(':'))));
    t.rows.push_back(std::move(row));
  }
  return t;
}

postproc::Table generations_table(const Snapshot& s) {
  postproc::Table t{s.box ? "Hypervolume of every design run up to each generation, in the normalised box"
                          : "Hypervolume of each generation's front (raw objectives, against a reference point fixed at "
                            "generation 0: a store from before the normalised box)",
                    {"seed", "generation", "hypervolume", "new designs run"}, {}};
  for (const auto& g : s.generations) {
    t.rows.push_back({std::to_string(s.runs.at(static_cast<std::size_t>(g.run)).seed), std::to_string(g.index),
                      fmt::format("{:.6g}", g.hypervolume), std::to_string(g.evaluations)});
  }
  return t;
}

// Each seed's run: its designs, its last hypervolume, IGD+ of its front against all runs' front.
postproc::Table runs_table(const Snapshot& s, std::size_t front_size) {
  postproc::Table t{fmt::format("Each seed's run against the front of all of them ({} designs); the hypervolume {}", front_size,
                                hypervolume_spread(s.runs)),
                    {"seed", "designs", "last generation", "hypervolume", "IGD+ to the front of all", "front designs it found"}, {}};
  for (const auto& r : s.runs) {
    t.rows.push_back({std::to_string(r.seed), std::to_string(r.designs), std::to_string(r.last_generation),
                      fmt::format("{:.6g}", r.hypervolume), fmt::format("{:.3g}", r.igd_plus), std::to_string(r.on_front)});
  }
  return t;
}

// The normalised box: each objective's axis and what fixed it.
postproc::Table box_table(const Normalisation& box) {
  postproc::Table t{"The hypervolume's box, fixed before the search (reference point 1.1 on every axis)",
                    {"objective", "axis", "ideal (0)", "nadir (1)", "from"}, {}};
  for (const auto& a : box.axes) {
    t.rows.push_back({a.objective, a.log ? "log10" : "linear", fmt::format("{:.4g}", a.ideal), fmt::format("{:.4g}", a.nadir), a.basis});
  }
  return t;
}

// The physical variant's run measures beside the design's (the worst over its scenarios), in the
// objective table's order.
std::string variant_text(const Confirmation& c, const Evaluation* e) {
  if (c.variant.empty()) return "-";
  std::string out = c.variant + ":";
  for (const auto& def : objective_table()) {
    const std::string name(def.name);
    const auto it = c.variant_measures.find(name);
    if (it == c.variant_measures.end()) continue;
    const double value = it->second;
    out += fmt::format(" {} {:.4g}", name, value);
    if (e == nullptr) continue;
    if (const auto mine = e->measures.find(name); mine != e->measures.end()) out += fmt::format(" ({:.4g})", mine->second);
  }
  return out + (c.variant_not_final.empty() ? "" : "; " + c.variant_not_final);
}

// With free sides, what confining changes: each run measure of the front's confirmed designs run
// between side walls (confirm's variant) against the free strip's, as a range of relative changes.
std::string confining_text(const Space& space, const Snapshot& s) {
  if (space.fixed.sides == model::Boundary::wall) return "";
  ConfirmVariant walls;
  walls.sides = model::Boundary::wall;
  std::map<std::string, std::pair<double, double>> change;  // measure: the least and largest
  int designs = 0, not_final = 0;
  for (const auto& c : s.confirmations) {
    const auto e = std::find_if(s.all.begin(), s.all.end(), [&](const auto& x) { return x.digest == c.digest; });
    if (c.variant != walls.label() || e == s.all.end()) continue;
    ++designs;
    if (!c.variant_not_final.empty()) ++not_final;
    for (const auto& [name, confined] : c.variant_measures) {
      const auto free = e->measures.find(name);
      if (free == e->measures.end() || !(free->second != 0.0)) continue;
      const double r = confined / free->second - 1.0;
      const auto it = change.try_emplace(name, r, r).first;
      it->second = {std::min(it->second.first, r), std::max(it->second.second, r)};
    }
  }
  const std::string lead = "**This space's designs have free sides** (`sides = \"free\"`): a strip that may splay sideways, "
                           "not a protector's confined body.";
  if (designs == 0) {
    return lead + " Nothing here says yet what confining changes: `granstack design confirm` runs the front's best "
                  "between side walls as well.";
  }
  std::vector<std::string> parts;
  for (const auto& [name, range] : change) {
    parts.push_back(fmt::format("{} {:+.1f} % to {:+.1f} %", name, 100.0 * range.first, 100.0 * range.second));
  }
  return fmt::format("{} Between side walls (confirm's runs of {} front design{}, on LIGGGHTS{}): {}.", lead, designs,
                     designs == 1 ? "" : "s", not_final > 0 ? fmt::format("; {} not final", not_final) : "",
                     parts.empty() ? "no run measure to compare" : fmt::format("{}", fmt::join(parts, "; ")));
}

// Each objective's spread between LIGGGHTS's law and the search's (Confirmation::law_spread), or "-".
std::string law_text(const Confirmation& c) {
  if (c.law.empty()) return "-";
  return fmt::format("{}: {}{}", c.law, spread_text(c),
                     c.law_yield ? fmt::format("; its contacts yield at {:.2g} to {:.2g} times their materials' pressure",
                                               c.law_yield->first, c.law_yield->second)
                                 : "");
}

postproc::Table confirmations_table(const Snapshot& s) {
  postproc::Table t{"The front's best re-run on LIGGGHTS (granstack design confirm)",
                    {"design", "layers", "case", "LIGGGHTS output fraction", "LIGGGHTS peak wall force (N)",
                     "objectives: LIGGGHTS against in situ (another law: against refsim under it)",
                     "whole runs: validate's largest difference", "verdict",
                     "objectives: LIGGGHTS twice as long against in situ", "final",
                     "LIGGGHTS's law where the search's has no counterpart there: each objective against the search's",
                     "a body it stands for: measures (the strip's)"}, {}};
  for (const auto& c : s.confirmations) {
    const auto e = std::find_if(s.all.begin(), s.all.end(), [&](const auto& x) { return x.digest == c.digest; });
    const auto layers = e != s.all.end() ? e->description : "?";
    if (!c.not_run.empty()) {
      t.rows.push_back({c.digest.substr(0, 12), layers, "-", "-", "-", "-", "-", c.verdict, "-", "-", "-", "-"});
      continue;
    }
    t.rows.push_back({c.digest.substr(0, 12), layers, c.case_dir, fmt::format("{:.6g}", c.liggghts_output_fraction),
                      value_text(c.liggghts_peak_wall_force), fmt::format("{:.3g}", c.objective_difference),
                      fmt::format("{:.3g}", c.largest_difference), c.verdict, value_text(c.longer_difference),
                      !c.longer_difference ? "-" : *c.longer_difference <= kFinalTolerance ? "final" : "NOT FINAL",
                      law_text(c), variant_text(c, e != s.all.end() ? &*e : nullptr)});
  }
  return t;
}

// Where LIGGGHTS ran another law than the search's: each objective's spread between the two laws
// over the confirmed designs, as a model-form uncertainty; and the designs LIGGGHTS could not take.
std::string law_spread_text(const Space& space, const Snapshot& s) {
  std::map<std::string, std::pair<double, double>> range;  // objective: the least and largest spread
  std::optional<std::pair<double, double>> yield;  // the contacts' yield pressures over their materials'
  std::string law;
  int designs = 0, not_run = 0;
  for (const auto& c : s.confirmations) {
    not_run += c.not_run.empty() ? 0 : 1;
    if (c.law.empty()) continue;
    law = c.law;
    ++designs;
    if (c.law_yield) {
      yield = yield ? std::pair{std::min(yield->first, c.law_yield->first), std::max(yield->second, c.law_yield->second)}
                    : *c.law_yield;
    }
    for (const auto& [name, spread] : c.law_spread) {
      const auto it = range.try_emplace(name, spread, spread).first;
      it->second = {std::min(it->second.first, spread), std::max(it->second.second, spread)};
    }
  }
  if (designs == 0 && not_run == 0) return "";
  std::vector<std::string> parts;
  for (const auto& [name, r] : range) parts.push_back(fmt::format("{} {:+.1f} % to {:+.1f} %", name, 100.0 * r.first, 100.0 * r.second));
  const auto searched = model::to_string(space.fixed.normal_model);
  std::string out =
      designs == 0 ? ""
                   : fmt::format("LIGGGHTS 3.8 has no {0} law: its runs of the front's {1} confirmed design{2} are under {3}, "
                                 "its nearest (docs/physics.md section 7), against refsim under {3} for the verdict; "
                                 "the two laws' spread on the objectives, {3} over {0}: {4}. It is a model-form "
                                 "uncertainty, what two elastic-plastic laws say, not a disagreement of the engines{5}.",
                                 searched, designs, designs == 1 ? "" : "s", law, fmt::join(parts, "; "),
                                 yield ? fmt::format(", and it holds more than the laws' unloading: under {} these "
                                                     "designs' contacts yield at {:.2g} to {:.2g} times their "
                                                     "materials' pressure (one yield radius for every contact; "
                                                     "`granstack generate` prints each kind's)",
                                                     law, yield->first, yield->second)
                                       : "");
  if (not_run > 0) {
    out += fmt::format("{}{} design{} could not run on LIGGGHTS (the table says why).", out.empty() ? "" : " ", not_run,
                       not_run == 1 ? "" : "s");
  }
  return out;
}

// Whether each seed's run has stopped improving, by the rule stated.
std::string convergence_text(const Space& space, const std::vector<Progress>& progress) {
  std::vector<std::string> runs;
  for (const auto& p : progress) runs.push_back(fmt::format("seed {}: {}", p.seed, stopped_improving(space, p)));
  return fmt::format("Has the search stopped improving? The rule: a run has when its hypervolume gained at most {:g} of itself "
                     "over {} generations' worth of distinct designs ({} each; [search] stagnation and stagnation_tolerance "
                     "set them, and end a search by the same rule). {}.",
                     space.search.stagnation_tolerance, convergence_window(space), space.search.population, fmt::join(runs, "; "));
}

json evaluation_json(const Space& space, const Evaluation& e) {
  json objectives = json::object();
  for (const auto o : space.objectives) {
    const auto v = objective_value(e, o);
    objectives[std::string(to_string(o))] = v ? json(*v) : json(nullptr);
  }
  return {{"digest", e.digest}, {"description", e.description}, {"spheres", e.spheres}, {"feasible", e.feasible},
          {"violations", e.violations}, {"objectives", objectives}, {"areal_mass", e.areal_mass}, {"height", e.height},
          {"measures", e.measures}, {"spec", model::spec_json(e.spec)}, {"shortcut", e.shortcut}};
}

// Each run's spending and progress, for the benchmark's record (bench/design_budget.sh).
json runs_json(const Space& space, const Snapshot& s) {
  json runs = json::array();
  const auto& budgets = s.budgets;
  const auto& progress = s.progress;
  for (std::size_t k = 0; k < s.runs.size(); ++k) {
    const auto& r = s.runs[k];
    const auto& b = budgets.at(k);
    json j = {{"seed", r.seed}, {"designs", r.designs}, {"last_generation", r.last_generation}, {"hypervolume", r.hypervolume},
              {"igd_plus", r.igd_plus}, {"front_designs_found", r.on_front}, {"refsim_seconds", b.seconds},
              {"censored_seconds", b.censored}, {"undecided_seconds", b.undecided}, {"off_front_seconds", b.off_front},
              {"settled", b.settled}, {"scenario_runs", b.scenario_runs}, {"scenario_runs_not_run", b.skipped_runs},
              {"timed", b.timed}};
    if (k < progress.size()) {
      j["stopped_improving"] = stopped_improving(space, progress[k]);
      for (const auto& p : progress[k].points) j["progress"].push_back({p.designs, p.hypervolume, p.igd_plus});
    }
    runs.push_back(j);
  }
  return runs;
}

json report_json(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front) {
  json j = json::object();
  j["granstack_version"] = std::string(granstack::version());
  j["space_digest"] = space.digest();
  j["sides"] = std::string(model::to_string(space.fixed.sides));  // "wall": confined
  for (const char* key : {"front", "study_designs", "generations", "confirmations"}) j[key] = json::array();
  for (const auto& e : front) j["front"].push_back(evaluation_json(space, e));
  for (const auto& [name, e] : s.studies) {
    auto study = evaluation_json(space, e);
    study["name"] = name;
    j["study_designs"].push_back(study);
  }
  for (const auto& g : s.generations) {
    j["generations"].push_back({{"seed", s.runs.at(static_cast<std::size_t>(g.run)).seed}, {"generation", g.index},
                                {"hypervolume", g.hypervolume}, {"new_designs", g.evaluations}});
  }
  j["schedule"] = std::string(to_string(space.search.schedule));
  j["runs"] = runs_json(space, s);
  if (s.box) {
    for (const auto& a : s.box->axes) {
      j["normalisation"].push_back({{"objective", a.objective}, {"log", a.log}, {"ideal", a.ideal}, {"nadir", a.nadir}, {"basis", a.basis}});
    }
  }
  for (const auto& c : s.confirmations) {
    j["confirmations"].push_back({{"digest", c.digest}, {"case", c.case_dir}, {"liggghts_output_fraction", c.liggghts_output_fraction},
                                  {"liggghts_peak_wall_force", c.liggghts_peak_wall_force ? json(*c.liggghts_peak_wall_force) : json(nullptr)},
                                  {"largest_difference", c.largest_difference}, {"objective_difference", c.objective_difference},
                                  {"verdict", c.verdict},
                                  {"longer_difference", c.longer_difference ? json(*c.longer_difference) : json(nullptr)},
                                  {"law", c.law.empty() ? json(nullptr) : json(c.law)}, {"law_spread", c.law_spread},
                                  {"not_run", c.not_run.empty() ? json(nullptr) : json(c.not_run)}});
  }
  if (!s.twins.empty()) {  // beside the elastic model: each design's elastic twin, by the design's digest
    j["elastic_twins"] = json::object();
    const auto elastic = elastic_reference(space);
    for (const auto& [digest, twin] : s.twins) j["elastic_twins"][digest] = evaluation_json(elastic, twin);
  }
  j["evaluations"] = s.all.size();
  return j;
}


// front/gGGG_NN_DIGEST.toml: the front after generation GGG (the last any run has finished).
void write_front_specs(const Space& space, const std::vector<Evaluation>& front, int generation, const fs::path& dir) {
  fs::create_directories(dir / "front");
  // The front of an earlier report goes first (after a resume the front changes: old and new
  // files numbered 01 stood side by side); only files named as this writes them, never others.
  static const std::regex ours(R"((g\d+_)?\d{2,}_[0-9a-f]{8}(_s\d+)?\.toml)");
  std::vector<fs::path> earlier;
  for (const auto& e : fs::directory_iterator(dir / "front")) {
    if (e.is_regular_file() && std::regex_match(e.path().filename().string(), ours)) earlier.push_back(e.path());
  }
  for (const auto& f : earlier) fs::remove(f);
  const auto write = [&](const fs::path& path, const std::string& what, const model::StackSpec& run) {
    formats::write_file_atomically(path, fmt::format("# granstack design: {}; run it with\n#   granstack generate --config {} "
                                                     "-o CASE && granstack run CASE && granstack reduce CASE\n{}",
                                                     what, path.filename().string(), model::spec_toml(run)));
  };
  for (std::size_t i = 0; i < front.size(); ++i) {
    const auto& e = front[i];
    const auto head = fmt::format("front design {} after generation {} ({})", i + 1, generation, e.description);
    for (const auto& f : front_files(space, e, generation, i + 1)) {
      if (!f.scenario) {
        write(dir / "front" / f.name, head + ", the run it was measured by", e.spec);
        continue;
      }
      const auto& sc = e.scenarios[*f.scenario];
      write(dir / "front" / f.name,
            fmt::format("{}, its scenario {} ({}), which decided {}", head, *f.scenario + 1, sc.label,
                        fmt::join(f.decides, ", ")),
            sc.spec);
    }
  }
}

}  // namespace

std::string status_text(const Space& space, const Store& store) {
  const auto all = store.evaluations();
  const auto gens = store.generations();
  const auto front = pareto_front(space, all);
  const auto feasible = std::count_if(all.begin(), all.end(), [](const auto& e) { return e.feasible; });
  const auto first_run = store.generations(0);
  const auto done = first_run.empty() ? std::string("no generation finished yet (the initial population was stopped)")
                                      : fmt::format("generations 0 to {} done", first_run.back().index);
  std::string out;
  for (const auto& w : space.warnings) out += fmt::format("warning: this search's measures cannot be trusted: {}\n", w);
  out += fmt::format("{} (the space asks for {}; {}); {} distinct designs evaluated ({} within the constraints); the front "
                     "holds {}\n", done, space.search.generations, to_string(space.search.schedule), all.size(), feasible, front.size());
  if (!first_run.empty()) {
    out += fmt::format("hypervolume: {:.6g} at generation 0, {:.6g} at generation {}\n", first_run.front().hypervolume,
                       first_run.back().hypervolume, first_run.back().index);
  }
  if (space.search.seeds.size() > 1) {
    const auto runs = summarise_runs(space, store, all, gens);
    for (const auto& r : runs) {
      out += fmt::format("seed {}: {} designs, generation {}, hypervolume {:.6g}, IGD+ to the front of all {:.3g}\n", r.seed,
                         r.designs, r.last_generation, r.hypervolume, r.igd_plus);
    }
    out += fmt::format("hypervolume {}\n", hypervolume_spread(runs));
  }
  const auto headers = objective_headers(space);
  for (std::size_t i = 0; i < std::min<std::size_t>(front.size(), 10); ++i) {
    std::vector<std::string> values;
    const auto cells = objective_cells(space, front[i]);
    for (std::size_t k = 0; k < cells.size(); ++k) values.push_back(fmt::format("{} {}", to_string(space.objectives[k]), cells[k]));
    out += fmt::format("  {:>2}. {}  ({})\n", i + 1, front[i].description, fmt::join(values, ", "));
  }
  return out;
}

std::string front_file_name(int generation, std::size_t rank, const std::string& digest, int scenario) {
  return fmt::format("g{:03}_{:02}_{}{}.toml", generation, rank, digest.substr(0, 8),
                     scenario > 0 ? fmt::format("_s{}", scenario) : "");
}

std::string spread_text(const Confirmation& c) {
  std::vector<std::string> parts;
  for (const auto& [name, spread] : c.law_spread) parts.push_back(fmt::format("{} {:+.1f} %", name, 100.0 * spread));
  return fmt::format("{}", fmt::join(parts, ", "));
}

fs::path write_report(const Space& space, const Store& store, const fs::path& dir, int jobs) {
  fs::create_directories(dir);
  const Snapshot s(space, store);
  const auto front = pareto_front(space, s.all);
  std::vector<postproc::Block> d;
  d.push_back(postproc::Heading{1, "granstack design: the search's front", "top"});
  d.push_back(postproc::Paragraph{run_line(space, s)});
  for (const auto& w : space.warnings) {
    d.push_back(postproc::Paragraph{fmt::format("**Warning: this search's measures cannot be trusted.** {}", w)});
  }
  if (store.measure_rules() != kMeasureRules) {
    d.push_back(postproc::Paragraph{fmt::format("**Warning: these designs were measured by granstack's measure rules {}, "
                                                "not this granstack's {}** ({}): their numbers are not what a search "
                                                "today would give. Search the space again into a new folder.",
                                                store.measure_rules(), kMeasureRules, measure_rules_changes())});
  }
  d.push_back(space_table(space));
  d.push_back(postproc::Heading{2, "The front", "front"});
  if (const auto confining = confining_text(space, s); !confining.empty()) d.push_back(postproc::Paragraph{confining});
  int generation = 0;
  for (const auto& g : s.generations) generation = std::max(generation, g.index);
  d.push_back(front_table(space, front, generation));
  d.push_back(postproc::Paragraph{yield_text(space, front, s.all)});
  if (const auto m = protected_mass_text(space, front); !m.empty()) d.push_back(postproc::Paragraph{m});
  if (!space.scenarios.empty()) d.push_back(scenario_table(space, front));
  d.push_back(postproc::Heading{2, "The study's designs", "study"});
  d.push_back(study_table(space, s, front));
  for (auto& b : elastic_blocks(space, s, front)) d.push_back(std::move(b));
  d.push_back(postproc::Heading{2, "Figures", "figures"});
  const bool any_feasible = std::any_of(s.all.begin(), s.all.end(), [](const auto& e) { return e.feasible; });
  if (!any_feasible) {  // nothing to draw (a search stopped before its first design finished)
    d.push_back(postproc::Paragraph{"No design within the constraints has been evaluated yet: no figure to draw."});
  }
  for (std::size_t i = 0; any_feasible && i < space.objectives.size(); ++i) {
    for (std::size_t k = i + 1; k < space.objectives.size(); ++k) {
      d.push_back(pair_figure(space, s, front, space.objectives[k], space.objectives[i], dir));
    }
  }
  if (any_feasible) {
    const bool wall = space.fixed.bottom == model::Boundary::wall;
    const auto shown = rerun_shown(s, front, jobs);
    if (wall) d.push_back(force_figure(shown, dir));
    d.push_back(energy_table(shown, wall));
  }
  d.push_back(postproc::Heading{2, "Convergence", "convergence"});
  if (s.generations.empty()) {  // stopped in its initial population: nothing to draw yet
    d.push_back(postproc::Paragraph{"No generation has finished yet (the search was stopped in its initial population); "
                                    "`granstack design run` resumes it."});
  } else {
    if (s.box) d.push_back(box_table(*s.box));
    if (s.runs.size() > 1) d.push_back(runs_table(s, front.size()));
    if (s.box) {
      d.push_back(postproc::Paragraph{convergence_text(space, s.progress)});
      for (auto& f : convergence_figures(s.progress, dir)) d.push_back(std::move(f));
    } else {
      d.push_back(hypervolume_figure(s, dir));
    }
    d.push_back(generations_table(s));
    d.push_back(budget_table(s.budgets));
  }
  if (!s.confirmations.empty()) {
    d.push_back(postproc::Heading{2, "Confirmed on LIGGGHTS", "confirmed"});
    if (const auto text = law_spread_text(space, s); !text.empty()) d.push_back(postproc::Paragraph{text});
    d.push_back(confirmations_table(s));
  }
  write_front_specs(space, front, generation, dir);
  formats::write_file_atomically(dir / "design.md", postproc::markdown(d));
  formats::write_file_atomically(dir / "design.html", postproc::html(d, dir, "granstack design"));
  formats::write_file_atomically(dir / "design.json", report_json(space, s, front).dump(2) + "\n");
  return dir / "design.html";
}

}  // namespace granstack::design
