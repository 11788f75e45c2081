#pragma once
// What the design report's parts share: the store read once (Snapshot), the figures and their
// reruns (report_figures.cpp), and the run a figure and confirm take of a design. report.cpp
// writes the report, report_figures.cpp its figures, confirm.cpp the LIGGGHTS confirmation.
#include <granstack/design/convergence.hpp>
#include <granstack/design/report.hpp>
#include <granstack/design/search.hpp>
#include <granstack/design/store.hpp>
#include <granstack/postproc/document.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace granstack::design::report_parts {

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
std::vector<RunSummary> summarise_runs(const Space& space, const Store& store, const std::vector<Evaluation>& all,
                                       const std::vector<Generation>& generations);

struct Snapshot;  // below: the store read once

// A measure in a report's table: four digits, or "-" where there is none.
inline std::string value_text(std::optional<double> v) { return v ? fmt::format("{:.4g}", *v) : "-"; }

// The run of a design the figures and confirm show: its own (no scenarios), else its scenario
// with the largest peak wall force.
model::StackSpec worst_run(const Evaluation& e);

// Figure: an objective against another, every feasible design, the front and the study's designs.
postproc::Figure pair_figure(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front, Objective x,
                             Objective y, const std::filesystem::path& dir);

// The front's designs and the study's, each rerun in situ as the store measured it (to its blow's
// end; with scenarios, the one with the largest peak force). The figure shows the front's first
// kFiguredFront (least first objective) beside the study's; the energy table all of them.
inline constexpr std::size_t kFiguredFront = 3;
struct Rerun {
  std::string name;
  refsim::InSituResult r;
  double striker_speed = 0.0;  // m/s, of the run
  bool figured = true;
};
// Each front design's and study design's worst blow run again (refsim, to its blow's end), `jobs`
// at a time; throws refsim::InSituStopped when a signal came meanwhile.
std::vector<Rerun> rerun_shown(const Snapshot& s, const std::vector<Evaluation>& front, int jobs);
postproc::Figure force_figure(const std::vector<Rerun>& shown, const std::filesystem::path& dir);
postproc::Table energy_table(const std::vector<Rerun>& shown, bool wall);
postproc::Figure hypervolume_figure(const Snapshot& s, const std::filesystem::path& dir);

// The designs seed number `run` joined, in order, from `all` (budget.cpp).
std::vector<Evaluation> run_designs(const Store& store, int run, const std::vector<Evaluation>& all);
// The scenarios (indices into e.scenarios) that decided each of the space's run objectives: the
// worst's, or all of them for a mean. Without scenarios, none.
std::map<std::size_t, std::vector<std::string>> deciding_scenarios(const Space& space, const Evaluation& e);

// What one seed's run spent refsim's time on, over the designs it joined (#50).
struct RunBudget {
  std::uint64_t seed = 0;
  std::size_t designs = 0;
  double seconds = 0.0;     // refsim wall time of its designs
  double censored = 0.0;    // of it, on runs whose blow had not ended by the cap
  double undecided = 0.0;   // on scenario runs of a design run in full, within its constraints, that decided no objective
  double off_front = 0.0;   // on designs off its front
  std::map<std::string, std::size_t> settled;  // designs settled early, by shortcut
  std::size_t scenario_runs = 0, skipped_runs = 0;
  bool timed = true;        // every scenario run timed (a store from before: its shares unknown)
};
std::vector<RunBudget> run_budgets(const Space& space, const Store& store, const std::vector<Evaluation>& all);
postproc::Table budget_table(const std::vector<RunBudget>& budgets);

// A seed's run after every `population` distinct designs it joined (and its last): the
// hypervolume of those designs' front in the box and its IGD+ against the front of all runs.
struct ProgressPoint {
  std::size_t designs = 0;
  double hypervolume = 0.0, igd_plus = 0.0;
};
struct Progress {
  std::uint64_t seed = 0;
  std::vector<ProgressPoint> points;
};
std::vector<Progress> run_progress(const Space& space, const Store& store, const std::vector<Evaluation>& all,
                                   const Normalisation& box);
// The report's rule for a run that has stopped improving: its hypervolume gained at most
// [search] stagnation_tolerance of itself over `convergence_window` generations' worth of designs
// ([search] stagnation, else kConvergenceWindow), the rule [search] stagnation ends a search by.
// Ten, not three: on the example, runs the three-generation rule had stopped went on to gain
// (bench/design_budget.sh, STAGNATION=3 against 10; bench/results/design-budget-2026-11-28.json).
inline constexpr int kConvergenceWindow = 10;
int convergence_window(const Space& space);
std::string stopped_improving(const Space& space, const Progress& p);
std::vector<postproc::Figure> convergence_figures(const std::vector<Progress>& progress, const std::filesystem::path& dir);

// What the report shows, read from the store once (each read parses every design's spec), with
// each run's spending and progress (budget.cpp), computed once for the report and its JSON.
struct Snapshot {
  Snapshot(const Space& space, const Store& store)
      : all(store.evaluations()), studies(store.study_designs()), twins(store.elastic_twins()), generations(store.generations()),
        confirmations(store.confirmations()), box(stored_normalisation(store)),
        runs(summarise_runs(space, store, all, generations)), budgets(run_budgets(space, store, all)),
        progress(box ? run_progress(space, store, all, *box) : std::vector<Progress>{}) {}
  std::vector<Evaluation> all;
  std::vector<std::pair<std::string, Evaluation>> studies;
  std::map<std::string, Evaluation> twins;  // elastic twins by design digest (a space that yields)
  std::vector<Generation> generations;
  std::vector<Confirmation> confirmations;
  std::optional<Normalisation> box;
  std::vector<RunSummary> runs;
  std::vector<RunBudget> budgets;
  std::vector<Progress> progress;  // none without the normalised box
};

// The report's section beside the elastic model (elastic.cpp), for a space whose contacts yield
// and whose store holds elastic twins: the front's designs and the study's under both laws, which
// design leads under each, the rank correlation of the two orders, the factors against the
// study's designs. Empty otherwise.
std::vector<postproc::Block> elastic_blocks(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front);

}  // namespace granstack::design::report_parts
