#include <granstack/design/convergence.hpp>
#include <granstack/design/report.hpp>
#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/spec_fields.hpp>
#include <granstack/model/version.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/postproc/document.hpp>
#include <granstack/postproc/plot.hpp>
#include <granstack/postproc/reduce.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/refsim/in_situ.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <iterator>
#include <ctime>
#include <regex>
#include <set>
#include <sstream>

namespace granstack::design {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// One seed's run of a search, against the front of every run together.
struct RunSummary {
  int run = 0;
  std::uint64_t seed = 0;
  std::size_t designs = 0;      // distinct designs it joined (ran, or took from another run)
  int last_generation = -1;
  double hypervolume = 0.0;     // its last generation's
  double igd_plus = 0.0;        // of its own front against the front of all runs, in the box
  std::size_t on_front = 0;     // of the front of all runs, the designs it found
};

// Each run's designs, from its joins (a store from before them: run 0 joined every design).
std::vector<RunSummary> summarise_runs(const Space& space, const Store& store, const std::vector<Evaluation>& all,
                                       const std::vector<Generation>& generations) {
  std::vector<RunSummary> out;
  const auto box = stored_normalisation(store);
  const auto front = pareto_front(space, all);
  std::map<std::string, const Evaluation*> by_digest;
  for (const auto& e : all) by_digest[e.digest] = &e;
  for (std::size_t r = 0; r < space.search.seeds.size(); ++r) {
    RunSummary s{static_cast<int>(r), space.search.seeds[r], 0, -1, 0.0, 0.0, 0};
    std::vector<Evaluation> mine;
    const auto joins = store.joins(s.run);
    for (const auto& d : joins) {
      if (const auto it = by_digest.find(d); it != by_digest.end()) mine.push_back(*it->second);
    }
    if (joins.empty() && r == 0) mine = all;
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

// What the report shows, read from the store once (each read parses every design's spec).
struct Snapshot {
  Snapshot(const Space& space, const Store& store)
      : all(store.evaluations()), studies(store.study_designs()), generations(store.generations()),
        confirmations(store.confirmations()), box(stored_normalisation(store)),
        runs(summarise_runs(space, store, all, generations)) {}
  std::vector<Evaluation> all;
  std::vector<std::pair<std::string, Evaluation>> studies;
  std::vector<Generation> generations;
  std::vector<Confirmation> confirmations;
  std::optional<Normalisation> box;
  std::vector<RunSummary> runs;
};

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

std::string value_text(std::optional<double> v) { return v ? fmt::format("{:.4g}", *v) : "-"; }

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
  return fmt::format("granstack {} ({}), {}. NSGA-II, {}, population {}, generations 0 to {}, seed{} {}; {} distinct designs "
                     "evaluated in situ on refsim ({:.1f} s of refsim in all). Space digest {}.",
                     granstack::version(), granstack::git_commit(), date, to_string(space.search.schedule), space.search.population,
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
  t.rows.push_back({"striker", fmt::format("{} m/s", space.fixed.striker_speed)});
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

postproc::Table front_table(const Space& space, const std::vector<Evaluation>& front) {
  postproc::Table t{"The Pareto front: no other evaluated design is better in every objective", {"#", "design", "spheres"}, {}};
  for (const auto& h : measure_headers(space)) t.header.push_back(h);
  t.header.push_back("spec file");
  for (std::size_t i = 0; i < front.size(); ++i) {
    std::vector<std::string> row{std::to_string(i + 1), front[i].description, std::to_string(front[i].spheres)};
    for (auto& c : measure_cells(space, front[i])) row.push_back(std::move(c));
    row.push_back(fmt::format("front/{:02}_{}.toml", i + 1, front[i].digest.substr(0, 8)));
    t.rows.push_back(std::move(row));
  }
  return t;
}

// Where the front's designs leave the elastic model (docs/physics.md section 7): the designs whose
// largest contact pressure passes first yield, and the share of all evaluated designs that do.
std::string yield_text(const std::vector<Evaluation>& front, const std::vector<Evaluation>& all) {
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

// Each front design's run objectives in each scenario: the spread its aggregate hides.
// The scenarios (indices into e.scenarios) that decided each of the space's run objectives: the
// worst's, or all of them for a mean. Without scenarios, none.
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
    row.push_back(versus_front(space, e, front));
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

// A case confirm writes: its dumps binary (the same doubles as text, reduce and validate give the
// same numbers, about a third of the bytes and LIGGGHTS's time writing them).
model::StackSpec binary_dumps(model::StackSpec spec) {
  spec.dump_format = model::DumpFormat::binary;
  return spec;
}

// The run of the physical variant of a design's run `ran`: the variant's own, to its own blow's end
// (a store written before runs stopped there holds the strip's length and cadences: not the nest's).
model::StackSpec variant_run(const Space& space, const model::StackSpec& ran) {
  auto v = space.confirm_variant.applied_to(ran);
  if (!stops_at_blow_end(v)) return v;
  v.duration.reset();
  v.dump_every.reset();
  v.series_every.reset();
  return stopping_at_blow_end(v, space.cap_durations);
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

postproc::Table confirmations_table(const Snapshot& s) {
  postproc::Table t{"The front's best re-run on LIGGGHTS (granstack design confirm)",
                    {"design", "layers", "case", "LIGGGHTS output fraction", "LIGGGHTS peak wall force (N)",
                     "objectives: LIGGGHTS against in situ", "whole runs: validate's largest difference", "verdict",
                     "objectives: LIGGGHTS twice as long against in situ", "final", "a body it stands for: measures (the strip's)"}, {}};
  for (const auto& c : s.confirmations) {
    const auto e = std::find_if(s.all.begin(), s.all.end(), [&](const auto& x) { return x.digest == c.digest; });
    t.rows.push_back({c.digest.substr(0, 12), e != s.all.end() ? e->description : "?", c.case_dir, fmt::format("{:.6g}", c.liggghts_output_fraction),
                      value_text(c.liggghts_peak_wall_force), fmt::format("{:.3g}", c.objective_difference),
                      fmt::format("{:.3g}", c.largest_difference), c.verdict, value_text(c.longer_difference),
                      !c.longer_difference ? "-" : *c.longer_difference <= kFinalTolerance ? "final" : "NOT FINAL",
                      variant_text(c, e != s.all.end() ? &*e : nullptr)});
  }
  return t;
}

// A value for a log axis or a linear one: the objectives that span decades are drawn on a log axis.
bool log_axis(Objective o) { return o->log_axis; }

std::string axis_label(Objective o) { return fmt::format("{} ({})", to_string(o), unit_of(o)); }

// The front's plot elements: one per top-block material on the front (its own symbol), each
// point coloured by its number of blocks (column 3); column 4 holds the material's index.
std::string front_elements(const Space& space, const std::vector<Evaluation>& front) {
  static constexpr int kSymbols[] = {7, 5, 9, 11, 13, 15};
  std::string out;
  for (std::size_t k = 0; k < space.materials.size(); ++k) {
    const bool present = std::any_of(front.begin(), front.end(), [&](const auto& e) { return e.spec.block_material(1) == space.materials[k]; });
    if (!present) continue;
    out += fmt::format("     '' index 1 using 1:($4 == {} ? $2 : 1/0):3 with points pt {} ps 1.5 lc palette title 'front, top block {}', \\\n",
                       k, kSymbols[k % std::size(kSymbols)], space.materials[k]);
  }
  return out;
}

std::string pair_data(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front, Objective x, Objective y) {
  std::string data = "# every feasible design: x y N_B\n";
  for (const auto& e : s.all) {
    if (e.feasible) data += fmt::format("{:.10g} {:.10g} {}\n", *objective_value(e, x), *objective_value(e, y), e.spec.blocks);
  }
  data += "\n\n# the front: x y N_B top-block-material-index\n";
  for (const auto& e : front) {
    const auto k = std::find(space.materials.begin(), space.materials.end(), e.spec.block_material(1)) - space.materials.begin();
    data += fmt::format("{:.10g} {:.10g} {} {}\n", *objective_value(e, x), *objective_value(e, y), e.spec.blocks, k);
  }
  data += "\n\n# the study's designs: x y name\n";
  for (const auto& [name, e] : s.studies) {
    if (objective_value(e, x) && objective_value(e, y)) {
      data += fmt::format("{:.10g} {:.10g} \"{}\"\n", *objective_value(e, x), *objective_value(e, y), name);
    }
  }
  return data;
}

// One pair of objectives: every feasible design (grey), the front coloured by N_B with a symbol
// per top-block material, the study's designs labelled.
postproc::Figure pair_figure(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front, Objective x,
                             Objective y, const fs::path& dir) {
  const auto name = fmt::format("{}_vs_{}", to_string(y), to_string(x));
  postproc::PlotOptions o;
  o.format = "svg";
  const auto script = fmt::format(
      "{}\nset output '{}.svg'\nset xlabel '{}' noenhanced\nset ylabel '{}' noenhanced\n{}{}set key outside right top\n"
      "set cblabel 'N_B'\nset cbtics 1\n"
      "set palette defined (1 '#1b9e77', 2 '#d95f02', 3 '#7570b3', 4 '#e7298a', 5 '#66a61e', 6 '#e6ab02')\n"
      "plot '{}.dat' index 0 using 1:2 with points pt 7 ps 0.5 lc rgb '#c0c0c0' title 'evaluated', \\\n{}"
      "     '' index 2 using 1:2 with points pt 6 ps 2 lw 2 lc rgb 'black' title \"the study's designs\", \\\n"
      "     '' index 2 using 1:2:3 with labels offset -1,1 right font 'Sans,18' noenhanced notitle\n",
      postproc::gnuplot_terminal(o), name, axis_label(x), axis_label(y), log_axis(x) ? "set logscale x\nset format x '10^{%L}'\n" : "",
      log_axis(y) ? "set logscale y\nset format y '10^{%L}'\n" : "", name, front_elements(space, front));
  postproc::render_gnuplot(dir.string(), name, pair_data(space, s, front, x, y), script, o);
  return {name + ".svg", fmt::format("{} against {}: every feasible design evaluated (grey), the front (of all the objectives, "
                                     "seen in these two) coloured by the number of blocks with a symbol per top-block material, "
                                     "the study's designs (circles)",
                                     to_string(y), to_string(x))};
}

// The run of a design the figure shows: its own (no scenarios), else its scenario with the
// largest peak wall force.
model::StackSpec worst_run(const Evaluation& e) {
  if (e.scenarios.empty()) return e.spec;
  const auto force = [](const ScenarioRun& r) {
    const auto it = r.measures.find("peak_wall_force");
    return it == r.measures.end() ? 0.0 : it->second;
  };
  return std::max_element(e.scenarios.begin(), e.scenarios.end(), [&](const auto& a, const auto& b) { return force(a) < force(b); })->spec;
}

// The front's designs and the study's, each rerun in situ as the store measured it (to its blow's
// end; with scenarios, the one with the largest peak force). The figure shows the front's first
// kFiguredFront (least first objective) beside the study's; the energy table all of them.
constexpr std::size_t kFiguredFront = 3;
struct Rerun {
  std::string name;
  refsim::InSituResult r;
  double striker_speed = 0.0;  // m/s, of the run
  bool figured = true;
};
std::vector<Rerun> rerun_shown(const Snapshot& s, const std::vector<Evaluation>& front) {
  std::vector<Rerun> out;
  const auto add = [&](const std::string& name, const model::StackSpec& spec, bool figured) {
    const auto stack = model::Stack::build(spec);
    out.push_back({name, refsim::run_in_situ(stack, refsim::particles_from(generator::data_file(stack, "report"))),
                   spec.striker_speed, figured});
  };
  for (std::size_t i = 0; i < front.size(); ++i) {
    add(fmt::format("front {}: {}", i + 1, front[i].description), worst_run(front[i]), i < kFiguredFront);
  }
  for (const auto& [name, e] : s.studies) add(name, worst_run(e), true);
  return out;
}

// The force on the protected object against time.
postproc::Figure force_figure(const std::vector<Rerun>& shown, const fs::path& dir) {
  std::string data, plots;
  double peak = 0.0;  // the y axis spans three decades below the largest force shown
  std::size_t index = 0;  // of the figure's data sets
  for (const auto& one : shown) {
    if (!one.figured) continue;
    const std::size_t k = index++;
    const auto& r = one.r;
    peak = std::max(peak, r.peak_wall_force.value_or(0.0));
    data += fmt::format("# {}: t (s) F (N)\n", one.name);
    for (std::size_t j = 0; j < r.wall_force.size(); ++j) {
      data += fmt::format("{:.9g} {:.9g}\n", static_cast<double>(j + 1) * r.wall_force_interval, r.wall_force[j]);
    }
    data += "\n\n";
    plots += fmt::format("{}'force.dat' index {} using ($1*1e3):2 with lines lw {} title '{}'", k == 0 ? "plot " : ", \\\n     ", k,
                         k < kFiguredFront ? 2 : 1, one.name);
  }
  postproc::PlotOptions o;
  o.format = "svg";
  const auto script = fmt::format("{}\nset output 'force.svg'\nset xlabel 't (ms)'\nset ylabel 'F on the wall (N)'\n"
                                  "set key below noenhanced\nset logscale y\nset yrange [1e-3 * {}:*]\nset format y '%g'\n{}\n",
                                  postproc::gnuplot_terminal(o), fmt::format("{:.6g}", peak), plots);
  postproc::render_gnuplot(dir.string(), "force", data, script, o);
  return {"force.svg", "The force on the protected object (the bottom wall) against time (log scale), each run to its blow's end (with "
                       "scenarios, the one with the largest peak): the front's first three designs (thick) and the study's "
                       "designs at the same footprint"};
}

// Where the energy is when each run ends, over E_in: the striker, each block, the part of the
// blocks' that moves sideways, and the rest (elastic energy in the contacts, less what damping and
// friction took); and the striker's and (free bottom) the output sphere's speed then, over the
// striker's speed at impact.
postproc::Table energy_table(const std::vector<Rerun>& shown, bool wall) {
  std::size_t blocks = 0;
  for (const auto& x : shown) blocks = std::max(blocks, x.r.end_block_ke.size());
  postproc::Table t{"Where the energy is when the blow has ended, over E_in; and how fast the striker comes back up "
                    "(and, with a free bottom, the output sphere leaves), over the striker's speed",
                    {"design", "ended at (s)", "striker"},
                    {}};
  for (std::size_t k = 0; k < blocks; ++k) t.header.push_back(fmt::format("block {}", k + 1));
  t.header.push_back("of the blocks', sideways");
  t.header.push_back("the rest (contacts, dissipated)");
  t.header.push_back("v_striker up / v_0");
  if (!wall) t.header.push_back("v_out / v_0");
  for (const auto& x : shown) {
    const auto& r = x.r;
    std::vector<std::string> row{x.name, r.blow_end_time ? fmt::format("{:.4g}", *r.blow_end_time) : "not ended",
                                 fmt::format("{:.3g}", r.end_striker_ke / r.e_in)};
    double sum = r.end_striker_ke;
    for (std::size_t k = 0; k < blocks; ++k) {
      row.push_back(k < r.end_block_ke.size() ? fmt::format("{:.3g}", r.end_block_ke[k] / r.e_in) : "");
      if (k < r.end_block_ke.size()) sum += r.end_block_ke[k];
    }
    row.push_back(fmt::format("{:.3g}", r.end_sideways_ke / r.e_in));
    row.push_back(fmt::format("{:.3g}", 1.0 - sum / r.e_in));
    row.push_back(fmt::format("{:.3g}", r.end_striker_vz / x.striker_speed));
    if (!wall) row.push_back(fmt::format("{:.3g}", r.end_output_speed / x.striker_speed));
    t.rows.push_back(std::move(row));
  }
  return t;
}

postproc::Figure hypervolume_figure(const Snapshot& s, const fs::path& dir) {
  std::string data = "# generation hypervolume (a block per seed's run)\n";
  std::string plots;
  for (const auto& r : s.runs) {
    data += fmt::format("# seed {}\n", r.seed);
    for (const auto& g : s.generations) {
      if (g.run == r.run) data += fmt::format("{} {:.10g}\n", g.index, g.hypervolume);
    }
    data += "\n\n";
    plots += fmt::format("{}'hypervolume.dat' index {} using 1:2 with linespoints pt 7 title 'seed {}'", plots.empty() ? "" : ", ", r.run, r.seed);
  }
  postproc::PlotOptions o;
  o.format = "svg";
  const auto script = fmt::format("{}\nset output 'hypervolume.svg'\nset xlabel 'generation'\nset ylabel 'hypervolume'\n"
                                  "set key bottom right\nplot {}\n",
                                  postproc::gnuplot_terminal(o), plots);
  postproc::render_gnuplot(dir.string(), "hypervolume", data, script, o);
  return {"hypervolume.svg", "The hypervolume of each generation's front: it grows while the search still finds better designs"};
}

json evaluation_json(const Space& space, const Evaluation& e) {
  json objectives = json::object();
  for (const auto o : space.objectives) {
    const auto v = objective_value(e, o);
    objectives[std::string(to_string(o))] = v ? json(*v) : json(nullptr);
  }
  return {{"digest", e.digest}, {"description", e.description}, {"spheres", e.spheres}, {"feasible", e.feasible},
          {"violations", e.violations}, {"objectives", objectives}, {"areal_mass", e.areal_mass}, {"height", e.height},
          {"measures", e.measures}, {"spec", model::spec_json(e.spec)}};
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
  j["runs"] = json::array();
  for (const auto& r : s.runs) {
    j["runs"].push_back({{"seed", r.seed}, {"designs", r.designs}, {"last_generation", r.last_generation},
                         {"hypervolume", r.hypervolume}, {"igd_plus", r.igd_plus}, {"front_designs_found", r.on_front}});
  }
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
                                  {"longer_difference", c.longer_difference ? json(*c.longer_difference) : json(nullptr)}});
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
                                                     what, path.filename().string(), spec_toml(run)));
  };
  for (std::size_t i = 0; i < front.size(); ++i) {
    const auto& e = front[i];
    const auto head = fmt::format("front design {} after generation {} ({})", i + 1, generation, e.description);
    if (e.scenarios.empty()) {
      write(dir / "front" / front_file_name(generation, i + 1, e.digest), head + ", the run it was measured by", e.spec);
      continue;
    }
    for (const auto& [k, decides] : deciding_scenarios(space, e)) {
      const auto& sc = e.scenarios[k];
      write(dir / "front" / front_file_name(generation, i + 1, e.digest, static_cast<int>(k) + 1),
            fmt::format("{}, its scenario {} ({}), which decided {}", head, k + 1, sc.label, fmt::join(decides, ", ")),
            sc.spec);
    }
  }
}

// A JSON value as a TOML node (the manifest's spec JSON has the spec file's shapes).
std::unique_ptr<toml::node> toml_of(const json& v) {
  if (v.is_boolean()) return std::make_unique<toml::value<bool>>(v.get<bool>());
  if (v.is_number_integer()) return std::make_unique<toml::value<std::int64_t>>(v.get<std::int64_t>());
  if (v.is_number()) return std::make_unique<toml::value<double>>(v.get<double>());
  if (v.is_string()) return std::make_unique<toml::value<std::string>>(v.get<std::string>());
  if (v.is_array()) {
    auto a = std::make_unique<toml::array>();
    for (const auto& e : v) {
      if (auto n = toml_of(e)) a->push_back(std::move(*n));
    }
    return a;
  }
  if (v.is_object()) {
    auto t = std::make_unique<toml::table>();
    for (const auto& [k, e] : v.items()) {
      if (auto n = toml_of(e)) t->insert(k, std::move(*n));
    }
    return t;
  }
  return nullptr;  // null: the field keeps its default
}

// The largest relative difference between the design's objectives from LIGGGHTS (reduce of
// its run) and the store's in-situ values.
double objective_difference(const Space& space, const model::StackSpec& ran, const std::map<std::string, double>& stored,
                            const postproc::CaseReduction& r) {
  const auto outcome = outcome_of(r, ran);
  double worst = 0.0;
  for (const auto o : space.objectives) {
    if (o->from_run == nullptr) continue;  // the geometric ones: the same stack
    const auto liggghts = o->from_run(outcome, space);
    const auto mine = stored.find(std::string(o->name));
    if (!liggghts || mine == stored.end()) continue;
    worst = std::max(worst, std::fabs(*liggghts - mine->second) / std::max(std::fabs(*liggghts), std::fabs(mine->second)));
  }
  return worst;
}

// A run of the design `ran` ran for `steps` steps, twice as long, with the same dt and output cadences.
model::StackSpec twice_as_long(const model::StackSpec& ran, long steps) { return running_for(ran, 2 * steps); }

// The steps the run of a case took: its run record's (a case that stops at its blow's end), or its spec's.
long steps_run(const std::string& case_dir) {
  const auto c = formats::Case::open(case_dir);
  return (formats::frames_written(c) - 1) * c.derived().dump_every;
}

// What confirm runs of a design: its run spec and stored measures, one per scenario.
std::vector<std::pair<model::StackSpec, std::map<std::string, double>>> confirm_runs(const Evaluation& e) {
  if (e.scenarios.empty()) return {{e.spec, e.measures}};
  std::vector<std::pair<model::StackSpec, std::map<std::string, double>>> out;
  for (const auto& r : e.scenarios) out.emplace_back(r.spec, r.measures);
  return out;
}

// What confirm will run and the most it can write (each run to its cap, binary dumps): LIGGGHTS
// and refsim of every scenario's case, LIGGGHTS again at up to twice that length, and the variant.
std::string confirm_plan(const Space& space, const std::vector<Evaluation>& front, std::size_t cases) {
  double bytes = 0.0;
  long runs = 0;
  const auto add = [&](const model::StackSpec& spec, double times) {
    const auto stack = model::Stack::build(binary_dumps(spec));
    const auto cost = model::estimate_cost(stack, model::resolve(stack));
    bytes += times * (cost.dump_bytes + cost.series_bytes);
  };
  for (const auto& e : front) {
    for (const auto& [spec, measures] : confirm_runs(e)) {
      add(spec, 4.0);  // two engines, and LIGGGHTS twice as long
      runs += 3;
    }
    if (!space.confirm_variant.empty()) {
      add(variant_run(space, worst_run(e)), 1.0);
      ++runs;
    }
  }
  return fmt::format("confirm: {} front design{}, {} case{}, {} runs; at most {:.0f} MB of dumps and series (binary, each "
                     "run to its cap at most)",
                     front.size(), front.size() == 1 ? "" : "s", cases, cases == 1 ? "" : "s", runs, bytes / 1e6);
}

}  // namespace

std::string spec_toml(const model::StackSpec& spec) {
  auto j = model::spec_json(spec);
  // The manifest keeps a field's default beside the one that replaces it (rows beside
  // block_rows); a spec file may give only one of them.
  for (const auto& f : model::spec_fields()) {
    if (!f.conflicts_with.empty() && j.contains(f.name)) j.erase(f.conflicts_with);
  }
  // The space fixes the wall's material (the study's steel) for every design; a design without a
  // wall leaves it out (generate refuses a wall's material where there is none).
  if (!spec.has_walls()) j.erase("wall_material");
  const auto t = toml_of(j);
  std::ostringstream os;
  os << *t->as_table() << "\n";
  return os.str();
}

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

fs::path write_report(const Space& space, const Store& store, const fs::path& dir) {
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
  d.push_back(front_table(space, front));
  d.push_back(postproc::Paragraph{yield_text(front, s.all)});
  if (!space.scenarios.empty()) d.push_back(scenario_table(space, front));
  d.push_back(postproc::Heading{2, "The study's designs", "study"});
  d.push_back(study_table(space, s, front));
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
    const auto shown = rerun_shown(s, front);
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
    d.push_back(generations_table(s));
    d.push_back(hypervolume_figure(s, dir));
  }
  if (!s.confirmations.empty()) {
    d.push_back(postproc::Heading{2, "Confirmed on LIGGGHTS", "confirmed"});
    d.push_back(confirmations_table(s));
  }
  int generation = 0;
  for (const auto& g : s.generations) generation = std::max(generation, g.index);
  write_front_specs(space, front, generation, dir);
  formats::write_file_atomically(dir / "design.md", postproc::markdown(d));
  formats::write_file_atomically(dir / "design.html", postproc::html(d, dir, "granstack design"));
  formats::write_file_atomically(dir / "design.json", report_json(space, s, front).dump(2) + "\n");
  return dir / "design.html";
}

std::vector<Confirmation> confirm_front(const Space& space, Store& store, const fs::path& dir, int top,
                                        const std::function<void(const std::string&)>& on_progress,
                                        const std::string& liggghts_exe,
                                        const std::function<void(const std::string&)>& on_plan) {
  auto front = pareto_front(space, store.evaluations());
  if (front.size() > static_cast<std::size_t>(top)) front.resize(static_cast<std::size_t>(top));
  // A case per design and scenario (DIGEST12, or DIGEST12_sK), each the run the store measured.
  struct Entry {
    std::size_t design;
    std::map<std::string, double> measures;
    model::StackSpec spec;
    std::string dir;
  };
  std::vector<Entry> entries;
  std::vector<std::string> dirs;
  for (std::size_t i = 0; i < front.size(); ++i) {
    const auto runs = confirm_runs(front[i]);
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const auto name = front[i].digest.substr(0, 12) + (runs.size() > 1 ? fmt::format("_s{}", k + 1) : "");
      generator::GenerateOptions o;
      o.output = dir / name;
      o.force = true;  // replaces only a case granstack made
      generator::generate({{name, binary_dumps(runs[k].first)}}, o);
      entries.push_back({i, runs[k].second, runs[k].first, o.output.string()});
      dirs.push_back(o.output.string());
    }
  }
  if (on_plan) on_plan(confirm_plan(space, front, entries.size()));
  runner::RunOptions ro;
  if (!liggghts_exe.empty()) ro.liggghts = liggghts_exe;
  const auto check = [](const std::vector<runner::RunOutcome>& outcomes) {
    for (const auto& r : outcomes) {
      if (r.status == runner::RunStatus::failed) throw ConfirmRunFailed(fmt::format("{}: {}", r.case_dir, r.message));
    }
  };
  for (const auto engine : {runner::Engine::liggghts, runner::Engine::refsim}) {
    ro.on_progress = [&](const runner::ProgressSnapshot& s) {
      if (on_progress) on_progress(fmt::format("confirm: {} runs {} of {}", runner::to_string(engine), s.finished, s.total));
    };
    check(runner::run_copies(dirs, engine, ro));
  }
  // The physical confirmation: each run again on LIGGGHTS, twice as long as LIGGGHTS ran it
  // (to the frame where it judged the blow ended), with the same cadences.
  std::vector<std::string> longer_dirs;
  std::vector<model::StackSpec> longer_specs;
  for (const auto& en : entries) {
    generator::GenerateOptions o;
    o.output = en.dir + "_x2";
    o.force = true;
    longer_specs.push_back(twice_as_long(en.spec, steps_run(runner::copy_dir(en.dir, runner::Engine::liggghts))));
    generator::generate({{o.output.filename().string(), binary_dumps(longer_specs.back())}}, o);
    longer_dirs.push_back(o.output.string());
  }
  ro.engine = runner::Engine::liggghts;
  ro.force = true;
  ro.on_progress = [&](const runner::ProgressSnapshot& s) {
    if (on_progress) on_progress(fmt::format("confirm: LIGGGHTS twice as long, {} of {}", s.finished, s.total));
  };
  check(runner::run_cases(longer_dirs, ro));
  // The physical variant the space asks for, of each design's worst scenario, on LIGGGHTS.
  const auto& variant = space.confirm_variant;
  std::vector<std::pair<std::string, model::StackSpec>> variant_runs(front.size());
  if (!variant.empty()) {
    std::vector<std::string> variant_dirs;
    for (std::size_t i = 0; i < front.size(); ++i) {
      generator::GenerateOptions o;
      o.output = dir / (front[i].digest.substr(0, 12) + variant.suffix());
      o.force = true;
      variant_runs[i] = {o.output.string(), variant_run(space, worst_run(front[i]))};
      generator::generate({{o.output.filename().string(), binary_dumps(variant_runs[i].second)}}, o);
      variant_dirs.push_back(o.output.string());
    }
    ro.on_progress = [&](const runner::ProgressSnapshot& s) {
      if (on_progress) on_progress(fmt::format("confirm: LIGGGHTS, {}, {} of {}", variant.label(), s.finished, s.total));
    };
    check(runner::run_cases(variant_dirs, ro));
  }
  // Per design: the worst of its scenarios' comparisons, and the largest LIGGGHTS values.
  std::vector<Confirmation> out;
  for (std::size_t i = 0; i < front.size(); ++i) {
    Confirmation c{front[i].digest, "", 0.0, std::nullopt, 0.0, 0.0, "", std::nullopt, "", {}, ""};
    std::vector<std::string> disagreements;
    for (std::size_t n = 0; n < entries.size(); ++n) {
      const auto& en = entries[n];
      if (en.design != i) continue;
      const auto liggghts = runner::copy_dir(en.dir, runner::Engine::liggghts), refsim = runner::copy_dir(en.dir, runner::Engine::refsim);
      const auto compared = postproc::compare_runs(liggghts, refsim);
      if (const auto why = compared.disagreement(postproc::kDefaultTolerance); !why.empty()) {
        disagreements.push_back(fs::path(en.dir).filename().string() + ": " + why);
      }
      postproc::ReduceOptions quiet;
      quiet.write_files = false;
      const auto r = postproc::reduce_case(liggghts, quiet);
      if (c.case_dir.empty()) c.case_dir = en.dir;
      c.liggghts_output_fraction = std::max(c.liggghts_output_fraction, r.output_fraction);
      if (r.peak_wall_force) c.liggghts_peak_wall_force = std::max(c.liggghts_peak_wall_force.value_or(0.0), *r.peak_wall_force);
      c.largest_difference = std::max(c.largest_difference, compared.worst());
      c.objective_difference = std::max(c.objective_difference, objective_difference(space, en.spec, en.measures, r));
      const auto longer = postproc::reduce_case(en.dir + "_x2", quiet);
      c.longer_difference = std::max(c.longer_difference.value_or(0.0),
                                     objective_difference(space, longer_specs[n], en.measures, longer));
    }
    // One tolerance, one verdict: the objectives and the whole runs, frame by frame, to the same
    // stopping frame (validate's), whatever the objectives say.
    if (c.objective_difference > postproc::kDefaultTolerance) {
      disagreements.push_back(fmt::format("objectives differ by {:.3g} (tolerance {:g})", c.objective_difference,
                                          postproc::kDefaultTolerance));
    }
    c.verdict = disagreements.empty() ? "agree" : fmt::format("DISAGREE: {}", fmt::join(disagreements, "; "));
    if (!variant.empty()) {
      postproc::ReduceOptions quiet;
      quiet.write_files = false;
      const auto& [vdir, vspec] = variant_runs[i];
      const auto outcome = outcome_of(postproc::reduce_case(vdir, quiet), vspec);
      c.variant = variant.label();
      c.variant_measures = run_measures(space, outcome);
      c.variant_not_final = not_final(space, vspec, outcome);
    }
    out.push_back(c);
    store.put_confirmation(c);
  }
  return out;
}

}  // namespace granstack::design
