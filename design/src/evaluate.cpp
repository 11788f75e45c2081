#include <granstack/design/convergence.hpp>
#include <granstack/design/search.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/workers.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <numeric>
#include <set>

namespace granstack::design {

namespace {
// Asked as a run goes (every refsim::kSettleEvery samples) with its outcome so far: why what it has
// measured already settles the design, or "".
using Settle = std::function<std::string(const Outcome& so_far)>;

// One in-situ run of `spec`, to the blow's end when `to_blow_end` (abandoned once it is certain
// not to end by the cap, with `shortcuts`; stopped where `settle` says).
Outcome run(const model::StackSpec& spec, bool to_blow_end, double cap_durations, const std::atomic<bool>* abandon,
            bool shortcuts, const Settle& settle = {}) {
  const auto stack = model::Stack::build(spec);
  // The particles exactly as a generated case's data file gives them to refsim.
  refsim::InSituOptions options;
  // A signal (or the search's end) abandons the design at once.
  options.stop = [abandon] { return os::interrupt_signal() != 0 || (abandon != nullptr && abandon->load()); };
  options.stop_at_blow_end = to_blow_end;
  options.cap_durations = cap_durations;
  options.abandon_when_censored = shortcuts;
  std::string settled;
  Outcome partial;  // the run so far, its series grown at each ask
  if (settle) {
    options.settle = [&](const refsim::InSituResult& so_far) {
      take_shared(partial, so_far);
      settled = settle(partial);
      return !settled.empty();
    };
  }
  auto r = refsim::run_in_situ(stack, refsim::particles_from(generator::data_file(stack, "design")), options);
  Outcome o;
  if (r.settled_at) o.settled = fmt::format("{}, stopped at t = {:.4g} s", settled, r.run_time);
  take_shared(o, r);
  o.bottom_row_fraction = r.bottom_row_fraction;
  o.output_settled = r.output_settled;
  o.run_time = r.run_time;
  o.seconds = r.seconds;
  o.steps = r.steps;
  return o;
}
}  // namespace

bool stops_at_blow_end(const model::StackSpec& design) { return design.gravity == 0.0; }

model::StackSpec running_for(const model::StackSpec& design, long steps) {
  auto spec = design;
  spec.stop = model::StopRule::duration;
  spec.cap_durations = model::kBlowEndCapDurations;
  spec.duration.reset();
  const auto res = model::resolve(model::Stack::build(spec));
  spec.dump_every = res.dump_every;
  spec.series_every = res.series_every;
  spec.duration = static_cast<double>(steps) * res.dt;
  // steps x dt / dt may round a hair above `steps` (resolve takes the next whole step): lowered
  // by an ulp at a time until the case runs exactly `steps`.
  for (int k = 0; k < 8 && model::resolve(model::Stack::build(spec)).steps > steps; ++k) {
    spec.duration = std::nextafter(*spec.duration, 0.0);
  }
  if (model::resolve(model::Stack::build(spec)).steps != steps) {
    throw std::logic_error(fmt::format("design {}: no duration runs exactly {} steps", describe(design), steps));
  }
  return spec;
}

model::StackSpec stopping_at_blow_end(const model::StackSpec& design, double cap_durations) {
  auto spec = design;
  spec.stop = model::StopRule::blow_end;
  spec.cap_durations = cap_durations;
  return spec;
}

model::StackSpec first_run(const Space& space, const model::StackSpec& design) {
  return stops_at_blow_end(design) ? stopping_at_blow_end(design, space.cap_durations) : design;
}

std::optional<model::StackSpec> extended(const model::StackSpec& design, const model::StackSpec& ran, const Outcome& o) {
  // A run that stops at its blow's end (first_run) has ended where it should, or at its cap.
  if (stops_at_blow_end(design)) return std::nullopt;
  // The output sphere was still being kicked late in the run: its energy is not final. Once, the
  // run is made long enough for that last change to sit at kExtendedChangeFraction of it (the
  // evaluated spec then names its duration: confirm and the front's spec files run it).
  if (o.output_settled || ran.duration) return std::nullopt;
  auto longer = ran;
  longer.duration = ran.bottom == model::Boundary::wall ? kWallExtension * o.run_time
                                                        : o.output_last_change_time / kExtendedChangeFraction;
  return longer;
}

std::vector<model::StackSpec> scenario_specs(const Space& space, const model::StackSpec& design) {
  if (space.scenarios.empty()) return {design};
  std::vector<model::StackSpec> out;
  for (const auto& sc : space.scenarios) out.push_back(sc.applied_to(design));
  return out;
}

std::string not_final(const Space& space, const model::StackSpec& ran, const Outcome& o) {
  if (!o.settled.empty()) return "";  // stopped under way by a shortcut: decided, not final (Evaluation::shortcut)
  if (stops_at_blow_end(ran)) {
    if (o.blow_end_time) return "";
    return fmt::format("censored: the blow had not ended at the cap ({:g} automatic durations, t = {:.4g} s): {}; its "
                       "measures are not final",
                       space.cap_durations, o.run_time, o.blow_not_ended);
  }
  if (o.output_settled) return "";
  return ran.bottom == model::Boundary::wall
             ? fmt::format("load not final: the wall's peak came at t = {:.4g} s of {:.4g} s, and the stack's momentum at "
                           "the end was {:.3g} m v (the blow not yet taken)",
                           o.peak_wall_force_time, o.run_time, o.final_momentum_ratio)
             : fmt::format("output not final: the output sphere's energy still changed at t = {:.4g} s, beyond {:g} of the "
                           "run", o.output_last_change_time, model::kLastChangeFraction);
}

std::map<std::string, double> aggregated(const Space& space, const std::vector<std::map<std::string, double>>& runs) {
  std::map<std::string, double> out;
  if (runs.empty()) return out;
  for (const auto& [name, first] : runs.front()) {
    double worst = first, sum = 0.0;
    bool everywhere = true;
    for (const auto& r : runs) {
      const auto it = r.find(name);
      if (it == r.end()) {
        everywhere = false;
        break;
      }
      worst = std::max(worst, it->second);
      sum += it->second;
    }
    if (everywhere) out[name] = space.aggregate_of(name) == Aggregate::mean ? sum / static_cast<double>(runs.size()) : worst;
  }
  return out;
}

namespace {
std::map<std::string, double> aggregated(const Space& space, const std::vector<ScenarioRun>& runs) {
  std::vector<std::map<std::string, double>> measures;
  for (const auto& r : runs) measures.push_back(r.measures);
  return aggregated(space, measures);
}

void add_violation(Evaluation& e, const std::string& why) {
  e.feasible = false;
  e.violations += (e.violations.empty() ? "" : "; ") + why;
}

// The run measures the space ranks on or bounds: a design lacking one has no place on the front.
std::vector<std::string> named_run_measures(const Space& space) {
  std::vector<std::string> names;
  for (const auto o : space.objectives) {
    if (o->from_run != nullptr) names.emplace_back(o->name);
  }
  for (const auto& [name, bound] : space.constraints.max_measures) names.push_back(name);
  return names;
}

// Why a measure the space names is missing from the runs: their series does not resolve what a
// shock measure reads, or it came out as no finite number; "" where the measure does not apply
// (a yield ratio of contacts that are not Hertz's).
std::string unmeasured_why(const Space& space, const std::string& name,
                           const std::vector<std::optional<ScenarioOutcome>>& runs) {
  const auto o = find_objective(name);
  const bool shock = name == "filtered_wall_force" || name == "protected_acceleration" || name == "srs_peak";
  for (const auto& r : runs) {
    if (!r) continue;
    if (const auto why = shock_measures_unresolved(space, r->second.wall_force_interval); shock && !why.empty()) {
      return fmt::format("{} not measured: {}; lower it in [measures], or sample the designs' series finer", name, why);
    }
    if (const auto v = o != nullptr && o->from_run != nullptr ? o->from_run(r->second, space) : std::nullopt;
        v && !std::isfinite(*v)) {
      return fmt::format("{} not measured: it came out as {}, no number", name, *v);
    }
  }
  return "";
}
}  // namespace

void record(const Space& space, Evaluation& e, const std::vector<std::optional<ScenarioOutcome>>& runs) {
  std::vector<ScenarioRun> done;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k]) continue;  // settled before it ran
    const auto& [ran, o] = *runs[k];
    done.push_back({space.scenarios.empty() ? "" : space.scenarios[k].label, ran, run_measures(space, o), not_final(space, ran, o),
                    o.seconds});
    if (!done.back().not_final.empty()) {
      add_violation(e, done.back().label.empty() ? done.back().not_final : fmt::format("at {}: {}", done.back().label, done.back().not_final));
    }
    if (ran.bottom == model::Boundary::free_surface) e.output_separated = e.output_separated && o.output_separated;
    e.seconds += o.seconds;
  }
  e.measures = aggregated(space, done);
  for (const auto& name : named_run_measures(space)) {
    if (e.measures.count(name) != 0) continue;  // taken in every run
    if (const auto why = unmeasured_why(space, name, runs); !why.empty()) add_violation(e, why);
  }
  for (const auto& [name, bound] : space.constraints.max_measures) {
    const auto it = e.measures.find(name);
    if (it != e.measures.end() && it->second > bound) add_violation(e, fmt::format("{} {:.4g} > {:.4g}", name, it->second, bound));
  }
  if (space.scenarios.empty()) e.spec = done.front().spec;  // as run: its length and cadences
  else e.scenarios = std::move(done);
}

void record(const Space& space, Evaluation& e, const std::vector<ScenarioOutcome>& runs) {
  record(space, e, std::vector<std::optional<ScenarioOutcome>>(runs.begin(), runs.end()));
}

std::vector<std::size_t> scenario_order(const Space& space) {
  std::vector<std::size_t> order(std::max<std::size_t>(1, space.scenarios.size()));
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (!space.search.shortcuts) return order;
  // The striker's energy, then the stiffer contacts (the higher yield pressure).
  const auto hardness = [&](std::size_t k) {
    const auto& sc = space.scenarios[k];
    return std::pair{std::pow(sc.striker_radius_ratio, 3) * sc.striker_speed * sc.striker_speed, sc.yield_pressure_factor.value_or(0.0)};
  };
  if (!space.scenarios.empty()) std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return hardness(a) > hardness(b); });
  return order;
}

namespace {
// One scenario's run: to its blow's end, or (gravity) as it is and once more where not final.
ScenarioOutcome run_scenario(const Space& space, const model::StackSpec& one, const std::atomic<bool>* abandon, bool shortcuts,
                             const Settle& settle) {
  if (stops_at_blow_end(one)) {
    auto o = run(one, true, space.cap_durations, abandon, shortcuts, settle);
    return {stopping_at_blow_end(one, space.cap_durations), std::move(o)};
  }
  auto ran = one;
  auto o = run(ran, false, space.cap_durations, abandon, shortcuts, settle);
  if (!o.settled.empty()) return {ran, std::move(o)};
  if (const auto longer = extended(one, ran, o)) {
    const double first = o.seconds;
    ran = *longer;
    o = run(ran, false, space.cap_durations, abandon, shortcuts, settle);
    o.seconds += first;  // the scenario's time is both runs'
  }
  return {ran, std::move(o)};
}

// Why what has run already decides the design, or "" (`kind` gets which rule): a measure
// aggregated as the worst over its bound (the rest can only raise a worst), or, every objective
// geometric or a worst, its objectives dominated by a design of the run's front (the rest can only
// raise them). Each measure is taken at its worst over the finished runs' measures (`finished`) and,
// when given, the run under way (`so_far`: only the measures that grow with a run, whose values so
// far are lower bounds of the run's).
std::string decided(const Space& space, const Evaluation& e, const std::vector<std::map<std::string, double>>& finished,
                    const Outcome* so_far, const Dominator& dominator, std::string& kind) {
  const auto worst = [&](Objective o) -> std::optional<double> {
    if (o == nullptr || space.aggregate_of(o->name) != Aggregate::worst) return std::nullopt;
    auto v = so_far != nullptr ? value_so_far(o, *so_far, space) : std::optional<double>();
    if (so_far != nullptr && !v) return std::nullopt;  // not a growing measure, or not yet
    for (const auto& m : finished) {
      if (const auto it = m.find(std::string(o->name)); it != m.end()) v = std::max(v.value_or(it->second), it->second);
    }
    return v;
  };
  for (const auto& [name, bound] : space.constraints.max_measures) {
    const auto v = worst(find_objective(name));
    if (!v || !(*v > bound)) continue;
    kind = "constraint";
    return fmt::format("{} {:.4g} > {:.4g}{}", name, *v, bound, so_far != nullptr ? " so far" : "");
  }
  if (!dominator) return "";
  std::vector<double> values;
  for (const auto o : space.objectives) {
    const auto v = o->from_run == nullptr ? std::optional<double>(o->geometric(e)) : worst(o);
    if (!v) return "";
    values.push_back(*v);
  }
  const auto by = dominator(values);
  if (!by) return "";
  kind = "dominated";
  return fmt::format("dominated {}by {}", so_far != nullptr ? "so far " : "", *by);
}

std::vector<std::map<std::string, double>> finished_measures(const Space& space, const std::vector<std::optional<ScenarioOutcome>>& runs) {
  std::vector<std::map<std::string, double>> out;
  for (const auto& r : runs) {
    if (r) out.push_back(run_measures(space, r->second));
  }
  return out;
}

// Why the scenarios run so far (`runs`, the rest not run) settle the design, or "": a run not final
// (infeasible whatever the rest give), else what decided() says of them.
std::string settled_by(const Space& space, const Evaluation& e, const std::vector<std::optional<ScenarioOutcome>>& runs,
                       const Dominator& dominator, std::string& kind) {
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k]) continue;
    const auto why = not_final(space, runs[k]->first, runs[k]->second);
    if (why.empty()) continue;
    kind = "censored";
    return space.scenarios.empty() ? why : fmt::format("at {}: {}", space.scenarios[k].label, why);
  }
  return decided(space, e, finished_measures(space, runs), nullptr, dominator, kind);
}
// What settles a design while a scenario runs: decided() with the run under way.
Settle settle_for(const Space& space, const Evaluation& e, const std::vector<std::optional<ScenarioOutcome>>& runs,
                  const Dominator& dominator, std::string& kind) {
  return [&space, &e, finished = finished_measures(space, runs), dominator, &kind](const Outcome& so_far) {
    return decided(space, e, finished, &so_far, dominator, kind);
  };
}
}  // namespace

Evaluation evaluate_design(const Space& space, const model::StackSpec& spec, bool run_anyway, const std::atomic<bool>* abandon,
                           const Dominator& dominator) {
  auto e = measured(space, spec);
  if (!e.feasible && !run_anyway) return e;
  // The probes (run_anyway) fix the objectives' box: every scenario of theirs runs.
  const bool shortcuts = space.search.shortcuts && !run_anyway;
  const auto specs = scenario_specs(space, spec);
  const auto order = scenario_order(space);
  std::vector<std::optional<ScenarioOutcome>> runs(specs.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto settle = shortcuts ? settle_for(space, e, runs, dominator, e.shortcut) : Settle{};
    runs[order[i]] = run_scenario(space, specs[order[i]], abandon, shortcuts, settle);
    const auto& under_way = runs[order[i]]->second.settled;
    const bool last = i + 1 == order.size();
    if (!shortcuts || (last && under_way.empty())) continue;
    auto why = under_way.empty() ? settled_by(space, e, runs, dominator, e.shortcut)
                                 : fmt::format("{}{}", space.scenarios.empty() ? "" : "at " + space.scenarios[order[i]].label + ": ", under_way);
    if (why.empty()) continue;
    std::vector<std::string> left;
    for (std::size_t j = i + 1; j < order.size(); ++j) left.push_back(space.scenarios[order[j]].label);
    e.shortcut_why = left.empty() ? why : fmt::format("{}; not run: {}", why, fmt::join(left, ", "));
    break;
  }
  record(space, e, runs);
  return e;
}

Evaluation BatchRunner::evaluate_one(const Space& space, const model::StackSpec& spec, bool run_anyway,
                                     const std::atomic<bool>* abandon, const Dominator& dominator) {
  return evaluate_design(space, spec, run_anyway, abandon, dominator);
}

Evaluation measured(const Space& space, const model::StackSpec& spec) {
  Evaluation e;
  e.spec = spec;
  e.digest = spec_digest(spec);
  e.description = describe(spec);
  const auto g = measure(space, spec);
  e.spheres = g.spheres;
  e.height = g.height;
  e.areal_mass = g.areal_mass;
  e.feasible = g.violations.empty();
  e.violations = fmt::format("{}", fmt::join(g.violations, "; "));
  return e;
}

namespace {
// Runs a batch on this machine, `jobs` designs at a time, each on one core.
class LocalRunner : public BatchRunner {
 public:
  explicit LocalRunner(int jobs) : jobs_(std::max(1, jobs)) {}
  void run(const Space& space, const std::vector<model::StackSpec>& specs, Store& store,
           const std::function<void(int, int)>& on_done, const Dominator& dominator) override {
    std::atomic<int> finished{0};
    std::atomic<bool> ended{false};  // a design failed or a signal came: no other starts
    std::mutex m;
    std::exception_ptr error;
    const auto end_with = [&](std::exception_ptr e) {
      const std::lock_guard<std::mutex> lock(m);
      if (!error) error = std::move(e);
      ended = true;
    };
    os::for_each(specs.size(), jobs_, [&](std::size_t k) {
      if (ended) return;
      if (os::interrupt_signal() != 0) {  // no design starts once a signal came; the batch ends
        end_with(std::make_exception_ptr(refsim::InSituStopped("stopped by a signal")));
        return;
      }
      try {
        store.put(evaluate_design(space, specs[k], false, nullptr, dominator));
      } catch (...) {
        end_with(std::current_exception());
      }
      const int done = ++finished;
      const std::lock_guard<std::mutex> lock(m);
      if (on_done) on_done(done, static_cast<int>(specs.size()));
    });
    if (error) std::rethrow_exception(error);
  }

 private:
  int jobs_;
};
}  // namespace

std::unique_ptr<BatchRunner> local_runner(int jobs) { return std::make_unique<LocalRunner>(jobs); }

Dominator dominator_over(const Space& space, const std::vector<Evaluation>& designs) {
  auto points = std::make_shared<std::vector<std::pair<std::vector<double>, std::string>>>();
  for (const auto& d : designs) {
    if (d.feasible && d.shortcut.empty()) points->emplace_back(objective_values(space, d), fmt::format("{} ({})", d.description, d.digest.substr(0, 12)));
  }
  return [points](const std::vector<double>& v) -> std::optional<std::string> {
    for (const auto& [p, name] : *points) {
      bool better = false, worse = false;
      for (std::size_t k = 0; k < v.size() && !worse; ++k) {
        worse = !(p[k] <= v[k]);  // a NaN in either is no domination
        better = better || p[k] < v[k];
      }
      if (better && !worse) return name;
    }
    return std::nullopt;
  };
}

bool stands_for(const Evaluation& e, const Space& space, const Dominator& dominator) {
  return e.shortcut != "dominated" || (dominator && dominator(objective_values(space, e)).has_value());
}

std::vector<Evaluation> Evaluator::evaluate(const std::vector<model::StackSpec>& specs,
                                            const std::function<void(int, int)>& on_done, const Dominator& dominator) {
  std::vector<model::StackSpec> to_run;
  std::set<std::string> asked;
  for (const auto& spec : specs) {
    const auto digest = spec_digest(spec);
    auto e = store_.find(digest);
    if (e && !stands_for(*e, space_, dominator)) {  // settled against another run's front: run in full for this one
      if (asked.insert(digest).second) to_run.push_back(spec);
    } else if (e) {
      if (!e->searched) {  // run before as one of the study's designs: the search has now asked for it too
        e->searched = true;
        store_.put(*e);
      }
    } else if (asked.insert(digest).second) {
      const auto m = measured(space_, spec);
      if (m.feasible) to_run.push_back(spec);
      else store_.put(m);  // outside the constraints: stored, never run
    }
  }
  if (!to_run.empty()) runner_.run(space_, to_run, store_, on_done, dominator);
  runs_ += static_cast<int>(to_run.size());
  std::vector<Evaluation> out;
  for (const auto& spec : specs) {
    auto e = store_.find(spec_digest(spec));
    if (!e) throw std::runtime_error(fmt::format("design {}: the batch ended without its result", describe(spec)));
    out.push_back(std::move(*e));
  }
  return out;
}

std::vector<double> fitness(const Space& space, const Evaluation& e, const Normalisation* normalisation) {
  if (!e.feasible) {
    // The further outside the constraints, the worse: the search is led back into them.
    const double penalty = kInfeasible * (1.0 + measure(space, e.spec).violation);
    return std::vector<double>(space.objectives.size(), penalty);
  }
  std::vector<double> f;
  for (const auto o : space.objectives) {
    const auto v = objective_value(e, o);
    if (!v || !std::isfinite(*v)) {
      throw std::runtime_error(fmt::format("design {} ({}): no finite {} was measured", e.digest.substr(0, 12),
                                           e.description, to_string(o)));
    }
    f.push_back(*v);
  }
  return normalisation != nullptr ? normalisation->point(f) : f;
}

}  // namespace granstack::design
