#pragma once
// The design store: one SQLite file holding every evaluation of a search (keyed by the canonical
// digest of the design's spec, so no design is run twice), every generation's population and
// hypervolume (a killed search resumes from its last finished generation), and the LIGGGHTS
// confirmations. Users may query it with sqlite3 or pandas (docs/design.md gives the tables).
#include <granstack/model/spec.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

struct sqlite3;

namespace granstack::design {

// One scenario's run of a design (a space with [scenarios]): the spec it ran and its measures.
struct ScenarioRun {
  std::string label;
  model::StackSpec spec;
  std::map<std::string, double> measures;
  std::string not_final;  // why its measures are not final ("" when they are)
  double seconds = 0.0;   // wall time of its refsim run(s)
};

struct Evaluation {
  std::string digest;       // spec_digest
  std::string description;  // describe()
  model::StackSpec spec;
  long spheres = 0;
  bool feasible = true;
  std::string violations;   // the broken constraints, when not feasible
  // What its run measured, by objective name (objective_table's run measures its bottom allows);
  // with scenarios, each taken over them as the space says (worst or mean).
  std::map<std::string, double> measures;
  std::vector<ScenarioRun> scenarios;  // with [scenarios]: each one's run (spec: the design's own)
  // With a free bottom: the output sphere had left every contact when the run ended, so its
  // output fraction is final (refsim::InSituResult::output_separated).
  bool output_separated = true;
  double areal_mass = 0.0;  // kg/m^2
  double height = 0.0;      // m
  double seconds = 0.0;     // wall time of the refsim run
  bool searched = true;     // the search asked for it (not only a study design placed beside the front)
  // The search's shortcut (#50; search.hpp, evaluate_design): how the design was settled before
  // all its scenarios ran ("" when each ran): "censored", "constraint" or "dominated"; and why, with
  // the scenarios not run. Its measures are then over the scenarios that ran (lower bounds of the
  // worst over all): a dominated design's feasibility is that of the scenarios run.
  std::string shortcut;
  std::string shortcut_why;
};

struct Generation {
  int run = 0;                              // which of the space's seeds (0: the first)
  int index = 0;                            // 0 = the initial population
  std::vector<std::vector<double>> population;  // decision vectors
  std::vector<std::string> digests;         // their designs, in the same order
  double hypervolume = 0.0;                 // of the feasible front, against Store::reference_point
  int evaluations = 0;                      // refsim runs this generation needed (new designs)
};

struct Confirmation {
  std::string digest;
  std::string case_dir;
  double liggghts_output_fraction = 0.0;
  std::optional<double> liggghts_peak_wall_force;
  double largest_difference = 0.0;          // validate's, of the two engines' whole runs
  // The largest relative difference between the objectives LIGGGHTS gives (reduce of its run)
  // and the store's in-situ ones: what the search ranked the design by.
  double objective_difference = 0.0;
  // "agree" (objectives within validate's tolerance), or "DISAGREE"; the whole runs' agreement
  // is largest_difference (a long, chaotic run parts from round-off late, after its peaks).
  std::string verdict;
  // The physical confirmation: the largest relative change of an objective when LIGGGHTS runs the
  // design twice as long as it was measured (none: not run; below kFinalTolerance: "final").
  std::optional<double> longer_difference;
  // The physical variant the space asked for (ConfirmVariant; "" when none): its run on LIGGGHTS
  // of the design's worst scenario, to its blow's end: each run measure, and why not final ("").
  std::string variant;
  std::map<std::string, double> variant_measures;
  std::string variant_not_final;
  // Where LIGGGHTS lacks the search's normal law (Thornton 1997's), the law it ran instead
  // (model::liggghts_counterpart: thornton_ning), and each objective's spread between the two laws,
  // LIGGGHTS's over the search's less 1, aggregated over the scenarios as the space aggregates
  // them: a model-form uncertainty, not a disagreement (the verdict then compares LIGGGHTS with
  // refsim, both under LIGGGHTS's law). "" and none where LIGGGHTS ran the search's law.
  std::string law;
  std::map<std::string, double> law_spread;
  // Under that law, the least and largest of the design's contacts' yield pressure over their
  // materials' (model::yield_pressure_departure: thornton_ning's one yield radius), part of the
  // spread; none where every contact yields at its materials'.
  std::optional<std::pair<double, double>> law_yield;
  // Why the design was not run on LIGGGHTS ("" when it was): generate refused its cases there
  // (thornton_ning gives every contact one yield radius, which some stacks cannot take).
  std::string not_run;
};
inline constexpr double kFinalTolerance = 1e-2;

class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// The store's file could not be written or read (a full disk, a read-only directory): an I/O
// error (exit 7), naming the file.
class StoreIoError : public StoreError {
 public:
  using StoreError::StoreError;
};
// Throws StoreIoError for SQLite's I/O failures (full, I/O, read-only, cannot open), else
// StoreError; `what` says what failed. Names the store's file.
[[noreturn]] void throw_store_error(sqlite3* db, const std::string& what);

class Store {
 public:
  // Opens (creates when missing) the store at `path` for the space whose digest is
  // `space_digest`; refuses one written for another space (StoreError naming both).
  static Store open(const std::string& path, const std::string& space_digest, const std::string& space_text);
  // Opens an existing store to read (design status, report); StoreError when it is missing, or
  // unfinished.
  static Store open_existing(const std::string& path);
  // Whether the file at `path` is a store whose first write did not finish: empty, or SQLite with
  // no space recorded and no design (a full disk as its search began). `design run` begins such a
  // store anew.
  static bool unfinished(const std::string& path);
  Store(Store&&) noexcept;
  ~Store();

  std::optional<Evaluation> find(const std::string& digest) const;
  void put(const Evaluation& e);  // thread-safe
  std::vector<Evaluation> evaluations() const;  // the searched ones, in the order they were stored
  // The study's designs placed beside the front (search.hpp, study_designs), by name.
  std::vector<std::pair<std::string, Evaluation>> study_designs() const;
  void put_study_design(const std::string& name, const std::string& digest);
  // A design's elastic twin (search.hpp, evaluate_elastic_twins): the same stack under Hertz's
  // elastic law, stored as not searched; by the design's digest.
  std::map<std::string, Evaluation> elastic_twins() const;
  void put_elastic_twin(const std::string& digest, const Evaluation& twin);

  void put_generation(const Generation& g);
  std::optional<Generation> last_generation(int run = 0) const;
  std::vector<Generation> generations() const;  // every run's, by run then generation
  std::vector<Generation> generations(int run) const;
  // The designs a run joined, in order (an asynchronous search rebuilds its population from them;
  // a generational one's are its batches'): one design may be in several runs, run once.
  void put_join(int run, long position, const std::string& digest);
  std::vector<std::string> joins(int run) const;

  void put_confirmation(const Confirmation& c);
  std::vector<Confirmation> confirmations() const;

  // Small named values: the space's digest and text, the hypervolume's reference point.
  std::optional<std::string> meta(const std::string& key) const;
  // The measure rules (kMeasureRules) its evaluations were taken by; 1 for a store that recorded none.
  int measure_rules() const;
  void set_meta(const std::string& key, const std::string& value);

 private:
  explicit Store(sqlite3* db);
  void exec(const std::string& sql) const;
  std::vector<std::string> columns(const std::string& table) const;
  // Refuses (StoreError) a store whose evaluations were taken by other measure rules; records
  // this granstack's in a store with none.
  void require_measure_rules(const std::string& path);
  void find_measures();  // measures_: the table's run measures the store has columns for; has_runs_, has_joins_
  std::string generation_columns() const;
  sqlite3* db_ = nullptr;
  std::vector<std::string> measures_;
  bool has_scenarios_ = false, has_shortcuts_ = false;
  bool has_runs_ = true, has_joins_ = true;  // a store from before several seeds has neither
  std::unique_ptr<std::mutex> mutex_;
};

}  // namespace granstack::design
