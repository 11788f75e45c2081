#pragma once
// `granstack design`: evaluating designs in situ on refsim (each once, kept in the store) and
// the multi-objective search over a space with pagmo2's NSGA-II, one generation at a time, its
// population evaluated as a batch on `jobs` threads.
#include <granstack/design/objectives.hpp>
#include <granstack/design/space.hpp>
#include <granstack/design/store.hpp>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace granstack::design {

struct Normalisation;

// The search's shortcuts (#50), asked after each scenario a design has run: the design of the
// run's front that dominates `values` (the design's objectives in the space's order, each taken at
// its worst over the scenarios run so far, which the rest can only raise), described, or nullopt.
// Empty: no front to ask (every scenario that can decide runs).
using Dominator = std::function<std::optional<std::string>(const std::vector<double>& values)>;
using ScenarioOutcome = std::pair<model::StackSpec, Outcome>;

// Where a batch of designs runs: on this machine (local_runner) or as SLURM job arrays
// (slurm_runner, batch.hpp). run() evaluates every design of `specs` (feasible, none in the
// store) and stores each as it finishes, so a killed batch keeps what it finished; on_done(finished,
// total) after each.
class BatchRunner {
 public:
  virtual ~BatchRunner() = default;
  // `dominator`: the run's front for the shortcuts (a runner that cannot stop a design between its
  // scenarios runs them all).
  virtual void run(const Space& space, const std::vector<model::StackSpec>& specs, Store& store,
                   const std::function<void(int, int)>& on_done, const Dominator& dominator) = 0;
  // One design for the asynchronous search, as evaluate_design gives it (measured; run unless
  // infeasible or run_anyway): here in situ, or where the runner runs its cases. Called from
  // several threads at once; once *abandon is set, its runs stop and it throws.
  virtual Evaluation evaluate_one(const Space& space, const model::StackSpec& spec, bool run_anyway,
                                  const std::atomic<bool>* abandon, const Dominator& dominator);
};
// `jobs` designs at a time on this machine, each in situ on one core.
std::unique_ptr<BatchRunner> local_runner(int jobs);

class Evaluator {
 public:
  Evaluator(const Space& space, Store& store, BatchRunner& runner) : space_(space), store_(store), runner_(runner) {}
  // The designs' evaluations, from the store where there, else measured (outside the
  // constraints: stored, not run) or run by the batch runner. `dominator`: the run's front, for
  // the shortcuts; a stored design settled as dominated that it does not dominate runs again.
  std::vector<Evaluation> evaluate(const std::vector<model::StackSpec>& specs,
                                   const std::function<void(int, int)>& on_done = {}, const Dominator& dominator = {});
  int runs() const { return runs_; }  // refsim runs so far

 private:
  const Space& space_;
  Store& store_;
  BatchRunner& runner_;
  int runs_ = 0;
};

inline constexpr double kInfeasible = 1e12;

// A design runs until its blow has ended (model::BlowEnd: the wall has taken the whole blow, or
// the output sphere flies free, held for an estimated arrival of the pulse), at most
// the space's cap_durations automatic durations; its evaluated spec then says so (stop =
// blow_end, the space's cap), so a case of it (confirm, the front's spec files) stops at the same
// frame on either engine. A blow not ended at the cap is censored: stored, infeasible, with why.
// With gravity the blow has no such end: a design whose output sphere was still being kicked late
// in its run (past model::kLastChangeFraction) is run once more, long enough for that last change
// to come at kExtendedChangeFraction of the run; still unsettled, it is infeasible.
inline constexpr double kExtendedChangeFraction = 0.3;
inline constexpr double kWallExtension = 3.0;
bool stops_at_blow_end(const model::StackSpec& design);
// The design's spec run for exactly `steps` steps with its automatic dt and output cadences.
model::StackSpec running_for(const model::StackSpec& design, long steps);
// The design's spec stopping at its blow's end, at most `cap_durations` automatic durations.
model::StackSpec stopping_at_blow_end(const model::StackSpec& design, double cap_durations);
// The first spec a case of the design runs (a SLURM batch): to its blow's end, or (gravity) as it is.
model::StackSpec first_run(const Space& space, const model::StackSpec& design);

// A design's measures known without running it (geometry and constraints), as an evaluation.
Evaluation measured(const Space& space, const model::StackSpec& spec);

// The spec to run again after `ran` of `design` gave `o`, or nullopt (always, for a run that stops
// at its blow's end): with gravity, longer when not settled (free bottom: the last change at
// kExtendedChangeFraction of the run; wall: kWallExtension times as long).
std::optional<model::StackSpec> extended(const model::StackSpec& design, const model::StackSpec& ran, const Outcome& o);
// The specs a design runs: one per scenario (the design itself when the space has none).
std::vector<model::StackSpec> scenario_specs(const Space& space, const model::StackSpec& design);
// Each run measure over a design's scenarios (`runs`, each run's measures), as the space aggregates
// it (the worst, or the mean); a measure some run lacks is left out.
std::map<std::string, double> aggregated(const Space& space, const std::vector<std::map<std::string, double>>& runs);
// Why the outcome `o` of the run `ran` is not final ("" when it is).
std::string not_final(const Space& space, const model::StackSpec& ran, const Outcome& o);
// The evaluation of `e` (measured) from the runs of its scenario_specs (each its spec as run, or
// its extension, and its outcome), in their order: its measures (aggregated over scenarios), and
// infeasible where a run was not final or a measure breaks its bound. A scenario without a run
// (settled by a shortcut) is left out.
void record(const Space& space, Evaluation& e, const std::vector<ScenarioOutcome>& runs);
void record(const Space& space, Evaluation& e, const std::vector<std::optional<ScenarioOutcome>>& runs);
// The order a design's scenarios run in: with the space's shortcuts, the hardest blow first (the
// striker's kinetic energy, m v^2 with m ~ R^3; between equal energies the higher yield pressure,
// whose stiffer contacts pass on more force; the order of the space between equals), the one most
// likely to decide the worst case (Hertz: the force grows as v^(6/5)); without, the space's.
std::vector<std::size_t> scenario_order(const Space& space);
// A design stored as settled by dominance (Evaluation::shortcut) stands for a run only where that
// run's front dominates it too; elsewhere it runs again, in full.
bool stands_for(const Evaluation& e, const Space& space, const Dominator& dominator);
// The Dominator of `designs`' feasible ones that were run in full: the first that dominates.
Dominator dominator_over(const Space& space, const std::vector<Evaluation>& designs);
// One design's evaluation, run now without a store (what `evaluate` runs for a missing one); a
// design outside the constraints is not run unless `run_anyway`.
// `abandon`: set, the run stops (refsim::InSituStopped), as at a signal.
// With the space's shortcuts ([search] shortcuts, on unless `run_anyway`), its scenarios run in
// scenario_order and the design is settled (Evaluation::shortcut) as soon as what has run decides
// it: a run censored (infeasible whatever the rest give; a run is abandoned once it is certain not
// to end by the cap), a measure taken at its worst over its bound, or its objectives, each taken
// at its worst (the rest can only raise them), dominated by a design of `dominator`'s front.
Evaluation evaluate_design(const Space& space, const model::StackSpec& spec, bool run_anyway = false,
                           const std::atomic<bool>* abandon = nullptr, const Dominator& dominator = {});

struct SearchOptions {
  int jobs = 1;                  // with no runner: designs at once on this machine
  // Where designs run (none: this machine, local_runner(jobs)). The asynchronous search keeps
  // `jobs` designs in flight on it; the generational one hands it each generation.
  BatchRunner* runner = nullptr;
  double time_limit = 0.0;       // s of wall time after which no design starts (0: none)
  // Called after each design run (generation, finished, to run) and after each generation.
  std::function<void(int, int, int)> on_progress;
  std::function<void(const Generation&)> on_generation;
};

struct SearchResult {
  int first_generation = 0;  // the first this call ran (above 0: resumed)
  int last_generation = 0;
  int runs = 0;              // refsim runs this call needed (distinct designs, the study's included)
  int probes = 0;            // of them, the study's designs and the probes that fix the objectives' box
  std::string ended;         // why it ended: "generations", "max_designs", "time limit", "stagnation", "exhausted"
  std::string exhausted_because;  // exhausted: the constraint that refused the most draws, and how many
};

// Runs the search up to space.search.generations (or its other ends), resuming where the store
// stopped. Before the first design, the study's designs are run and the normalised box of the
// hypervolume fixed (convergence.hpp). An asynchronous search starts a design whenever one of its
// `jobs` ends; a generational one (pagmo2's NSGA-II) runs each generation as a batch.
SearchResult run_search(const Space& space, Store& store, const SearchOptions& options);

// MOEA/D's update in the asynchronous search (Li and Zhang 2009's limit on replacements): the
// members among `neighbours` (indices into `members`, nearest weight first) that a design of
// objectives `f` replaces, those it beats or equals in their Tchebycheff distance from the box's
// ideal (the origin) weighted by their own weights, at most kMoeadReplacements of them, so that one
// good design cannot fill a whole neighbourhood with copies of itself.
inline constexpr int kMoeadReplacements = 2;
std::vector<std::size_t> moead_replaced(const std::vector<std::vector<double>>& members, const std::vector<std::size_t>& neighbours,
                                        const std::vector<std::vector<double>>& weights, const std::vector<double>& f);

// The asynchronous search (search.cpp calls it): a steady-state NSGA-II. Each new design is bred
// from the population as it stands (binary tournaments on rank and crowding in the normalised
// objectives, SBX and polynomial mutation, pagmo2's operators, its genes made canonical); one equal
// to a design the store holds or one running is drawn again, and one outside the known constraints
// (spheres, height, areal mass, validity) is rejected before it runs. When a design ends it joins
// the population, which drops its worst (rank, then crowding). Every `population` designs make a
// generation. With one job the search is the same wherever it is stopped and resumed.
SearchResult run_asynchronous(const Space& space, Store& store, const SearchOptions& options, int run = 0);
// Draws before the space is called exhausted (no new design within its constraints).
inline constexpr int kDrawsPerDesign = 2000;
inline constexpr int kBredDraws = 200;  // of them bred; the rest drawn uniformly from the space

// The fitness the search ranks by: the objectives in the space's order, each in the normalised box
// (`normalisation`) when given, else raw; an infeasible design gets kInfeasible * (1 + its relative
// violation) in each, behind every feasible one.
std::vector<double> fitness(const Space& space, const Evaluation& e, const Normalisation* normalisation = nullptr);

// The study's own designs at the space's footprint and fixed settings: 4 steel blocks, steel over
// Teflon, and the sandwich (steel / Teflon / steel), each with 8 rows and the ratio 2.
std::vector<std::pair<std::string, model::StackSpec>> study_designs(const Space& space);

// A store's search keeps the schedule it was run with: a space file that does not name one takes
// the store's ([search] evaluation; a store from before the key is generational); and so its
// breeding ([search] front_parents and step_mutation; a file naming others is refused).
void adopt_schedule(Space& space, const Store& store);
// The space a store was written for, as status, report and confirm read it (parse_space's stored).
Space stored_space(const Store& store, const std::string& source);

// The study's designs (study_designs) evaluated at the space's footprint and stored by name,
// `jobs` at a time; run even where they break the space's constraints (they are marked so).
void evaluate_study_designs(const Space& space, Store& store, int jobs = 1);

// The elastic model beside a space whose contacts yield (thornton, thornton_ning): what the study
// and an elastic search take, Hertz's law with e = 1. yields: the space's law yields.
// elastic_twin: a design's stack under it (the rest of its spec as it is). elastic_reference: the
// space under it, its yield-pressure scenarios one blow each (they are the same blow elastic).
bool yields(const Space& space);
model::StackSpec elastic_twin(model::StackSpec spec);
Space elastic_reference(const Space& space);
// Where the space yields: the elastic twins of the front's designs and of the study's that the
// store lacks, each run in every scenario of the elastic reference, `jobs` at a time, and stored
// (Store::elastic_twins); returns how many ran. 0 where the space does not yield.
int evaluate_elastic_twins(const Space& space, Store& store, int jobs = 1);
// The probes that fix the normalised box before a search: the study's designs (by name) and the
// space's lightest and heaviest designs (Space::extreme_designs; no name) that lie within its
// known constraints.
struct Probe {
  std::string study_name;
  model::StackSpec spec;
};
std::vector<Probe> probe_designs(const Space& space);
// A probe's evaluation stored (not searched), and a study design's name with it.
void store_probe(Store& store, const Probe& probe, Evaluation e);
// The probes the store lacks run `jobs` at a time and stored; returns how many ran.
int evaluate_probes(const Space& space, Store& store, int jobs);
// Once every probe is stored: the normalised box fixed from them and stored.
void fix_box(const Space& space, Store& store);
// The probes that are feasible designs of the space, marked searched, in order: each run of an
// asynchronous search begins with them (warm start).
std::vector<Evaluation> warm_designs(const Space& space, Store& store);

// The feasible evaluations no other dominates in the space's objectives, best first objective first.
std::vector<Evaluation> pareto_front(const Space& space, const std::vector<Evaluation>& all);
// Designs joining a front one at a time: `e` joins `front` (designs none of which dominates
// another, in the order they joined) when it is feasible and no member dominates it, and the
// members it dominates leave; true when it joined. The front of a list so built holds the same
// designs as pareto_front of the list, in the list's order, at a cost per design of the front's size.
bool join_front(const Space& space, std::vector<Evaluation>& front, const Evaluation& e);

// The hypervolume of the feasible points among `all` against `reference` (per objective).
double hypervolume(const Space& space, const std::vector<Evaluation>& all, const std::vector<double>& reference);

}  // namespace granstack::design
