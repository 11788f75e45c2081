#pragma once
// `granstack design`: evaluating designs in situ on refsim (each once, kept in the store) and
// the multi-objective search over a space with pagmo2's NSGA-II, one generation at a time, its
// population evaluated as a batch on `jobs` threads.
#include <granstack/design/objectives.hpp>
#include <granstack/design/space.hpp>
#include <granstack/design/store.hpp>

#include <functional>
#include <memory>
#include <vector>

namespace granstack::design {

// Where a batch of designs runs: on this machine (local_runner) or as SLURM job arrays
// (slurm_runner, batch.hpp). run() evaluates every design of `specs` (feasible, none in the
// store) and stores each as it finishes, so a killed batch keeps what it finished; on_done(finished,
// total) after each.
class BatchRunner {
 public:
  virtual ~BatchRunner() = default;
  virtual void run(const Space& space, const std::vector<model::StackSpec>& specs, Store& store,
                   const std::function<void(int, int)>& on_done) = 0;
};
// `jobs` designs at a time on this machine, each in situ on one core.
std::unique_ptr<BatchRunner> local_runner(int jobs);

class Evaluator {
 public:
  Evaluator(const Space& space, Store& store, BatchRunner& runner) : space_(space), store_(store), runner_(runner) {}
  // The designs' evaluations, from the store where there, else measured (outside the
  // constraints: stored, not run) or run by the batch runner.
  std::vector<Evaluation> evaluate(const std::vector<model::StackSpec>& specs,
                                   const std::function<void(int, int)>& on_done = {});
  // The objectives of an evaluation, in the space's order; an infeasible design gets
  // kInfeasible * (1 + its relative violation) in each, behind every feasible one.
  std::vector<double> fitness(const Evaluation& e) const;
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
// Why the outcome `o` of the run `ran` is not final ("" when it is).
std::string not_final(const Space& space, const model::StackSpec& ran, const Outcome& o);
// The evaluation of `e` (measured) from the runs of its scenario_specs (each its spec as run, or
// its extension, and its outcome), in their order: its measures (aggregated over scenarios), and
// infeasible where a run was not final or a measure breaks its bound.
void record(const Space& space, Evaluation& e, const std::vector<std::pair<model::StackSpec, Outcome>>& runs);
// One design's evaluation, run now without a store (what `evaluate` runs for a missing one); a
// design outside the constraints is not run unless `run_anyway`.
Evaluation evaluate_design(const Space& space, const model::StackSpec& spec, bool run_anyway = false);

struct SearchOptions {
  int jobs = 1;                  // with no runner: designs at once on this machine
  BatchRunner* runner = nullptr;  // where batches run (none: local_runner(jobs))
  // Called after each design run (generation, finished, to run) and after each generation.
  std::function<void(int, int, int)> on_progress;
  std::function<void(const Generation&)> on_generation;
};

struct SearchResult {
  int first_generation = 0;  // the first this call ran (above 0: resumed)
  int last_generation = 0;
  int runs = 0;              // refsim runs this call needed
};

// Runs the search up to space.search.generations, resuming after the store's last generation.
SearchResult run_search(const Space& space, Store& store, const SearchOptions& options);

// The study's own designs at the space's footprint and fixed settings: 4 steel blocks, steel over
// Teflon, and the sandwich (steel / Teflon / steel), each with 8 rows and the ratio 2.
std::vector<std::pair<std::string, model::StackSpec>> study_designs(const Space& space);

// The feasible evaluations no other dominates in the space's objectives, best first objective first.
std::vector<Evaluation> pareto_front(const Space& space, const std::vector<Evaluation>& all);

// The hypervolume of the feasible points among `all` against `reference` (per objective).
double hypervolume(const Space& space, const std::vector<Evaluation>& all, const std::vector<double>& reference);

}  // namespace granstack::design
