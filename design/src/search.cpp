#include <granstack/design/convergence.hpp>
#include <granstack/design/search.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/workers.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <pagmo/algorithms/nsga2.hpp>
#include <pagmo/batch_evaluators/member_bfe.hpp>
#include <pagmo/bfe.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <pagmo/utils/hypervolume.hpp>
#include <pagmo/utils/multi_objective.hpp>

#include <algorithm>
#include <chrono>
#include <memory>
#include <set>

namespace granstack::design {

namespace {

// What the pagmo problem evaluates with: the space, the evaluator and the batch's progress.
struct Context {
  const Space* space = nullptr;
  Evaluator* evaluator = nullptr;
  int generation = 0;
  const SearchOptions* options = nullptr;
  Store* store = nullptr;
  int run = 0;
  std::optional<Normalisation> box;           // the hypervolume's (none: a store from before it, raw)
  std::vector<Evaluation> archive;            // the designs the run has evaluated, each once, in order
  std::set<std::string> joined;

  void join(const std::vector<Evaluation>& evaluations) {
    for (const auto& e : evaluations) {
      if (!joined.insert(e.digest).second) continue;
      store->put_join(run, static_cast<long>(archive.size()), e.digest);
      archive.push_back(e);
    }
  }

  std::vector<model::StackSpec> decode(const pagmo::vector_double& dvs) const {
    const std::size_t n = space->genes();
    std::vector<model::StackSpec> specs;
    for (std::size_t at = 0; at + n <= dvs.size(); at += n) {
      specs.push_back(space->decode(std::vector<double>(dvs.begin() + static_cast<long>(at), dvs.begin() + static_cast<long>(at + n))));
    }
    return specs;
  }
  pagmo::vector_double fitnesses(const pagmo::vector_double& dvs) {
    const auto evaluations = evaluator->evaluate(decode(dvs), [&](int done, int total) {
      if (options->on_progress) options->on_progress(generation, done, total);
    }, dominator_over(*space, archive));
    join(evaluations);
    pagmo::vector_double out;
    for (const auto& e : evaluations) {
      // Ranked by the raw objectives, as before the box (the same search, design for design, as
      // the stores and figures made before it; NSGA-II's crowding takes each objective's range).
      const auto f = design::fitness(*space, e);
      out.insert(out.end(), f.begin(), f.end());
    }
    return out;
  }
};

// The pagmo problem: whole-number genes (Space::decode), the space's objectives, evaluated a
// batch at a time (member_bfe calls batch_fitness with a generation's new individuals).
struct DesignProblem {
  std::shared_ptr<Context> context;
  pagmo::vector_double fitness(const pagmo::vector_double& x) const { return context->fitnesses(x); }
  pagmo::vector_double batch_fitness(const pagmo::vector_double& dvs) const { return context->fitnesses(dvs); }
  bool has_batch_fitness() const { return true; }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const { return context->space->bounds(); }
  pagmo::vector_double::size_type get_nobj() const { return context->space->objectives.size(); }
  pagmo::vector_double::size_type get_nix() const { return context->space->genes(); }
  std::string get_name() const { return "granstack design"; }
};

// Each generation's own seed, from the search's: a resumed search draws what an uninterrupted one would.
unsigned generation_seed(std::uint64_t seed, int generation) {
  return static_cast<unsigned>((seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(generation) * 0xBF58476D1CE4E5B9ULL) >> 32);
}

// The raw hypervolume's reference point of a store from before the normalised box: 1.1 times the
// worst feasible value of its first generation in each objective.
std::vector<double> reference_point(const Space& space, Store& store, const std::vector<Evaluation>& first) {
  if (const auto saved = store.meta("reference_point")) return nlohmann::json::parse(*saved).get<std::vector<double>>();
  std::vector<double> ref(space.objectives.size(), 0.0);
  bool any = false;
  for (const auto& e : first) {
    if (!e.feasible) continue;
    any = true;
    for (std::size_t k = 0; k < ref.size(); ++k) ref[k] = std::max(ref[k], *objective_value(e, space.objectives[k]));
  }
  for (auto& r : ref) r = any ? 1.1 * r : kInfeasible;
  store.set_meta("reference_point", nlohmann::json(ref).dump());
  return ref;
}

// A generation of the generational search, stored: its population, and the hypervolume of every
// design run so far (in the normalised box; a store from before it keeps its raw one of the
// generation's own designs).
Generation record(const Space& space, Store& store, const Context& c, const pagmo::population& pop, int index, int runs) {
  Generation g;
  g.run = c.run;
  g.index = index;
  g.evaluations = runs;
  std::vector<Evaluation> members;
  for (const auto& x : pop.get_x()) {
    g.population.push_back(x);
    const auto spec = space.decode(x);
    g.digests.push_back(spec_digest(spec));
    if (auto e = store.find(g.digests.back())) members.push_back(std::move(*e));
  }
  g.hypervolume = c.box ? normalised_hypervolume(space, *c.box, c.archive)
                        : hypervolume(space, members, reference_point(space, store, members));
  store.put_generation(g);
  return g;
}

// Why a generational search ends before its next generation ("" when it goes on).
std::string generational_end(const Space& space, const Store& store, const Context& c, const SearchOptions& options,
                             std::chrono::steady_clock::time_point start) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.time_limit > 0.0 && elapsed >= options.time_limit) return "time limit";
  if (space.search.max_designs && static_cast<long>(c.archive.size()) >= *space.search.max_designs) return "max_designs";
  const int k = space.search.stagnation;
  const auto gens = store.generations(c.run);
  if (k > 0 && static_cast<int>(gens.size()) > k) {
    const double now = gens.back().hypervolume, then = gens[gens.size() - 1 - static_cast<std::size_t>(k)].hypervolume;
    if (now - then <= space.search.stagnation_tolerance * now) return "stagnation";
  }
  return "";
}

SearchResult run_generational(const Space& space, Store& store, const SearchOptions& options, int run) {
  const auto local = options.runner ? nullptr : local_runner(options.jobs);
  Evaluator evaluator(space, store, options.runner ? *options.runner : *local);
  auto context = std::make_shared<Context>(Context{&space, &evaluator, 0, &options, &store, run, stored_normalisation(store), {}, {}});
  for (const auto& digest : store.joins(run)) {  // the designs evaluated before a resume
    if (auto e = store.find(digest); e && context->joined.insert(digest).second) context->archive.push_back(std::move(*e));
  }
  const auto seed = space.search.seeds.at(static_cast<std::size_t>(run));
  pagmo::problem problem{DesignProblem{context}};
  const pagmo::bfe batch{pagmo::member_bfe{}};
  SearchResult result;
  pagmo::population pop;
  const auto last = store.last_generation(run);
  if (last) {
    // Resume: the last finished generation's population, its fitness from the store.
    pop = pagmo::population(problem, 0u, generation_seed(seed, last->index));
    for (const auto& x : last->population) pop.push_back(x, problem.fitness(x));
    result.first_generation = last->index + 1;
  } else {
    // The designs [search] start names take the first places; the rest are drawn.
    const auto& start = space.search.start;
    const auto named = std::min(start.size(), static_cast<std::size_t>(space.search.population));
    const auto size = static_cast<pagmo::population::size_type>(space.search.population) - named;
    pop = pagmo::population(problem, batch, size, generation_seed(seed, 0));
    if (named > 0) {
      pagmo::vector_double all;  // evaluated as one batch
      for (std::size_t k = 0; k < named; ++k) all.insert(all.end(), start[k].begin(), start[k].end());
      const auto f = context->fitnesses(all);
      const auto m = space.objectives.size();
      for (std::size_t k = 0; k < named; ++k) {
        pop.push_back(start[k], pagmo::vector_double(f.begin() + static_cast<long>(k * m), f.begin() + static_cast<long>((k + 1) * m)));
      }
    }
    const auto g = record(space, store, *context, pop, 0, evaluator.runs());
    if (options.on_generation) options.on_generation(g);
    result.first_generation = 1;
  }
  const auto start = std::chrono::steady_clock::now();
  for (int gen = result.first_generation; gen <= space.search.generations; ++gen) {
    if (os::interrupt_signal() != 0) throw refsim::InSituStopped("stopped by a signal between generations");
    // Its other ends, between generations: the time limit, the budget, a still hypervolume.
    result.ended = generational_end(space, store, *context, options, start);
    if (!result.ended.empty()) break;
    context->generation = gen;
    const int before = evaluator.runs();
    const auto& o = space.search;
    pagmo::nsga2 algorithm(1u, o.crossover_probability, o.crossover_eta,
                           o.mutation_probability.value_or(1.0 / static_cast<double>(space.genes())), o.mutation_eta,
                           generation_seed(seed, gen));
    algorithm.set_bfe(batch);
    pop = algorithm.evolve(pop);
    const auto g = record(space, store, *context, pop, gen, evaluator.runs() - before);
    if (options.on_generation) options.on_generation(g);
    result.last_generation = gen;
  }
  result.runs = evaluator.runs();
  if (result.ended.empty()) result.ended = "generations";
  return result;
}

// Before the first design of a generational search: the probes run `jobs` at a time and the
// normalised box fixed (a store from before the box keeps its raw hypervolume). Returns the
// designs run. (The asynchronous search runs its probes in its own pool.)
int prepare(const Space& space, Store& store, int jobs) {
  if (stored_normalisation(store) || store.last_generation()) return 0;
  const int ran = evaluate_probes(space, store, jobs);
  fix_box(space, store);
  return ran;
}

}  // namespace

std::vector<Evaluation> pareto_front(const Space& space, const std::vector<Evaluation>& all) {
  std::vector<Evaluation> feasible;
  std::vector<pagmo::vector_double> points;
  for (const auto& e : all) {
    if (!e.feasible) continue;
    pagmo::vector_double p;
    for (const auto o : space.objectives) p.push_back(*objective_value(e, o));
    feasible.push_back(e);
    points.push_back(p);
  }
  std::vector<Evaluation> front;
  if (points.size() < 2) return feasible;  // none, or one: it dominates nothing and nothing it
  const auto fronts = std::get<0>(pagmo::fast_non_dominated_sorting(points));
  for (const auto i : fronts.front()) front.push_back(feasible[i]);
  const auto first = space.objectives.front();
  std::sort(front.begin(), front.end(), [&](const auto& a, const auto& b) { return *objective_value(a, first) < *objective_value(b, first); });
  return front;
}

bool join_front(const Space& space, std::vector<Evaluation>& front, const Evaluation& e) {
  if (!e.feasible) return false;
  const auto dominates = [](const std::vector<double>& a, const std::vector<double>& b) {
    bool better = false;
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (a[k] > b[k]) return false;
      better = better || a[k] < b[k];
    }
    return better;
  };
  const auto v = objective_values(space, e);
  if (std::any_of(front.begin(), front.end(), [&](const Evaluation& f) { return dominates(objective_values(space, f), v); })) {
    return false;
  }
  std::erase_if(front, [&](const Evaluation& f) { return dominates(v, objective_values(space, f)); });
  front.push_back(e);
  return true;
}

double hypervolume(const Space& space, const std::vector<Evaluation>& all, const std::vector<double>& reference) {
  std::vector<pagmo::vector_double> points;
  for (const auto& e : pareto_front(space, all)) {
    pagmo::vector_double p;
    for (const auto o : space.objectives) p.push_back(*objective_value(e, o));
    bool inside = true;
    for (std::size_t k = 0; k < p.size(); ++k) inside = inside && p[k] < reference[k];
    if (inside) points.push_back(p);
  }
  if (points.empty()) return 0.0;
  return pagmo::hypervolume(points, false).compute(reference);
}

std::vector<std::pair<std::string, model::StackSpec>> study_designs(const Space& space) {
  const auto design = [&](std::vector<std::string> materials) {
    model::StackSpec s = space.fixed;
    s.blocks = static_cast<int>(materials.size());
    s.materials = std::move(materials);
    s.block_rows.assign(static_cast<std::size_t>(s.blocks), 8);
    s.radius_ratios.assign(static_cast<std::size_t>(s.blocks - 1), 2);
    s.bottom_radius = space.top_radius / std::pow(2.0, s.blocks - 1);
    return canonical(std::move(s));
  };
  return {{"four steel blocks", design({"steel", "steel", "steel", "steel"})},
          {"steel over Teflon", design({"steel", "teflon"})},
          {"the sandwich (steel / Teflon / steel)", design({"steel", "teflon", "steel"})}};
}

namespace {
// The designs the store lacks, `jobs` at a time (each in situ on one core), stored as not
// searched; their evaluations, in their order.
std::pair<std::vector<Evaluation>, int> evaluate_at_once(const Space& space, Store& store,
                                                         const std::vector<model::StackSpec>& designs, int jobs) {
  std::vector<std::optional<Evaluation>> done(designs.size());
  std::vector<std::size_t> missing;
  for (std::size_t k = 0; k < designs.size(); ++k) {
    if (!store.find(spec_digest(designs[k]))) missing.push_back(k);
  }
  os::for_each(missing.size(), jobs, [&](std::size_t i) { done[missing[i]] = evaluate_design(space, designs[missing[i]], true); });
  std::vector<Evaluation> out;
  for (std::size_t k = 0; k < designs.size(); ++k) {
    if (done[k]) {
      done[k]->searched = false;
      store.put(*done[k]);
    }
    out.push_back(*store.find(spec_digest(designs[k])));
  }
  return {out, static_cast<int>(missing.size())};
}
}  // namespace

std::vector<Probe> probe_designs(const Space& space) {
  std::vector<Probe> out;
  for (auto& [name, spec] : study_designs(space)) out.push_back({name, std::move(spec)});
  const auto [light, heavy] = space.extreme_designs();
  for (const auto& d : {light, heavy}) {
    if (measure(space, d).violations.empty() && spec_digest(d) != spec_digest(out.back().spec)) out.push_back({"", d});
  }
  return out;
}

void store_probe(Store& store, const Probe& probe, Evaluation e) {
  e.searched = false;
  store.put(e);
  if (!probe.study_name.empty()) store.put_study_design(probe.study_name, spec_digest(probe.spec));
}

int evaluate_probes(const Space& space, Store& store, int jobs) {
  const auto probes = probe_designs(space);
  std::vector<model::StackSpec> designs;
  for (const auto& p : probes) designs.push_back(p.spec);
  const int ran = evaluate_at_once(space, store, designs, jobs).second;
  for (std::size_t k = 0; k < probes.size(); ++k) {
    if (!probes[k].study_name.empty()) store.put_study_design(probes[k].study_name, spec_digest(probes[k].spec));
  }
  return ran;
}

namespace {
// The probes' evaluations, each design once, in probe order.
std::vector<Evaluation> stored_probes(const Space& space, const Store& store) {
  std::vector<Evaluation> out;
  std::set<std::string> seen;
  for (const auto& p : probe_designs(space)) {
    auto e = store.find(spec_digest(p.spec));
    if (!e) throw std::logic_error(fmt::format("probe {} has not run", describe(p.spec)));
    if (seen.insert(e->digest).second) out.push_back(std::move(*e));
  }
  return out;
}
}  // namespace

void fix_box(const Space& space, Store& store) { store_normalisation(store, fix_normalisation(space, stored_probes(space, store))); }

std::vector<Evaluation> warm_designs(const Space& space, Store& store) {
  std::vector<Evaluation> warm;
  for (auto& e : stored_probes(space, store)) {
    if (!e.feasible || !space.encode(e.spec)) continue;
    if (!e.searched) {
      e.searched = true;
      store.put(e);
    }
    warm.push_back(std::move(e));
  }
  return warm;
}

void evaluate_study_designs(const Space& space, Store& store, int jobs) {
  const auto study = study_designs(space);
  std::vector<model::StackSpec> designs;
  for (const auto& d : study) designs.push_back(d.second);
  evaluate_at_once(space, store, designs, jobs);
  for (std::size_t k = 0; k < study.size(); ++k) store.put_study_design(study[k].first, spec_digest(study[k].second));
}

namespace {

// The breeding a store's search began with: a file that names none adopts it, one that names
// other values is refused (the search would change its rules halfway). A store whose search
// began before the breeding was kept bred with neither; one whose search has not begun, with
// the file's.
void adopt_breeding(Space& space, const Store& store) {
  auto& s = space.search;
  const auto kept = store.meta("breeding");
  if (!kept && !store.meta("schedule")) return;
  double front = 0.0, step = 0.0;
  if (kept) {
    const auto j = nlohmann::json::parse(*kept);
    front = j.at("front_parents").get<double>();
    step = j.at("step_mutation").get<double>();
  }
  if (!s.breeding_given) {
    s.front_parents = front;
    s.step_mutation = step;
  } else if (s.front_parents != front || s.step_mutation != step) {
    throw StoreError(fmt::format("the store's search breeds with front_parents = {} and step_mutation = {}, the space "
                                 "names {} and {}: name the store's (or neither) to resume it, or give another directory",
                                 front, step, s.front_parents, s.step_mutation));
  }
}

}  // namespace

void adopt_schedule(Space& space, const Store& store) {
  if (!store.meta("space_digest")) return;
  adopt_breeding(space, store);
  if (space.search.schedule_given) return;
  const auto named = store.meta("schedule");
  space.search.schedule = named && *named == to_string(Schedule::asynchronous) ? Schedule::asynchronous : Schedule::generational;
}

Space stored_space(const Store& store, const std::string& source) {
  const auto text = *store.meta("space");
  auto space = parse_space(text, source, true);
  // A search stored before spaces were confined by default ran its designs with free sides where
  // its file named none: it is read as it ran.
  if (const auto digest = store.meta("space_digest"); digest && *digest != space.digest()) {
    if (auto as_run = parse_space(text, source, true, true); as_run.digest() == *digest) {
      space = std::move(as_run);
      space.warnings.push_back("this search was stored before design spaces stood between side walls by default: its "
                               "designs have free sides (a strip that splays sideways), as they were run");
    }
  }
  adopt_schedule(space, store);
  return space;
}

SearchResult run_search(const Space& space, Store& store, const SearchOptions& options) {
  if (!store.meta("schedule")) {
    store.set_meta("schedule", std::string(to_string(space.search.schedule)));
    store.set_meta("breeding", nlohmann::json{{"front_parents", space.search.front_parents},
                                              {"step_mutation", space.search.step_mutation}}.dump());
  }
  const bool asynchronous = space.search.schedule == Schedule::asynchronous;
  const auto start = std::chrono::steady_clock::now();
  SearchResult total;
  total.runs = total.probes = asynchronous ? 0 : prepare(space, store, options.jobs);  // asynchronous: probes in its pool
  for (int run = 0; run < static_cast<int>(space.search.seeds.size()); ++run) {
    auto o = options;  // one time limit for every seed's run
    if (options.time_limit > 0.0) {
      o.time_limit = options.time_limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (o.time_limit <= 0.0) {
        total.ended = "time limit";
        break;
      }
    }
    const auto r = asynchronous ? run_asynchronous(space, store, o, run) : run_generational(space, store, o, run);
    if (run == 0) total.first_generation = r.first_generation;
    total.last_generation = r.last_generation;
    total.runs += r.runs;
    total.probes += r.probes;
    total.ended = r.ended;
    total.exhausted_because = r.exhausted_because;
    if (r.ended == "time limit") break;
  }
  return total;
}

}  // namespace granstack::design
