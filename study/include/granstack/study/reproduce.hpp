#pragma once
// `granstack reproduce`: the study's experiments (catalogue.hpp) generated, run, reduced, measured
// by their named analyses and judged against the paper's statements, into a report.
#include <granstack/postproc/document.hpp>
#include <granstack/postproc/reduce.hpp>
#include <granstack/study/catalogue.hpp>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace granstack::study {

using postproc::Figure;
using postproc::Table;

// A claim judged on its primary reading alone; the sensitivity readings are shown beside it.
struct Verdict {
  const Claim* claim = nullptr;
  std::optional<double> value;       // the primary reading (none: not measured)
  std::optional<double> error;       // its standard error, where the analysis has one
  std::string verdict;               // "within", "outside" or "not measured"
  // Outside: the distance from the value to the nearer band edge over that edge's magnitude
  // ("outside, by 6 %": 6 % beyond the edge).
  double off = 0.0;
  std::optional<double> from_paper;  // (value - paper) / |paper|, where the paper states a value
  std::optional<double> sigmas;      // (value - paper) / error, where the value has a standard error
  std::vector<std::pair<std::string, std::optional<double>>> sensitivity;  // quantity, value
  std::vector<std::pair<std::string, std::optional<double>>> context;      // other quantities, not judged
  // The sensitivity readings that fall on the other side of the band from the primary one: a
  // verdict that holds only at the reading chosen.
  std::vector<std::string> other_side() const;
};

// One case of an experiment as it ran.
struct CaseRecord {
  std::string name, dir;
  std::string status;                     // done, failed, interrupted, not run
  std::string engine;                     // what its run.json names (formats::run_engine); "" when not run
  std::string pinned;                     // the catalogue's engine for it (CaseEntry::engine): "" the reproduction's
  std::string run_sha256;                 // of its run.json when done: what a later --against checks
  double wall_seconds = 0.0;              // of this invocation's run (0 when reused)
  std::optional<double> validate_worst;   // with --validate: refsim against LIGGGHTS, worst relative difference
  std::string validate_quantity;          // and where
  std::optional<double> validate_output;  // the output fractions' relative difference
  std::optional<postproc::CaseReduction> reduction;
  std::string problem;                    // why it has no reduction
};

struct ExperimentResult {
  const Experiment* experiment = nullptr;
  std::vector<CaseRecord> cases;
  std::map<std::string, double> values;   // the analysis's quantities, by name
  std::map<std::string, double> errors;   // standard errors, where it has them
  std::vector<Table> tables;
  std::vector<Figure> figures;
  std::vector<std::string> notes;          // what the analysis found worth saying
  std::map<std::string, std::string> claim_notes;  // by a claim's primary reading: what its summary row adds
  std::vector<Verdict> verdicts;
  const CaseRecord* find_case(const std::string& name) const;
};

struct ReproduceOptions {
  std::string output;                      // DIR
  std::vector<std::string> experiments;    // empty: all (with quick: the quick ones)
  bool quick = false;
  bool full = false;                       // also the cases and experiments marked full
  bool validate = false;                   // also run refsim on every case and compare
  bool force = false;                      // regenerate and rerun every case
  // "liggghts", "refsim" or "lammps"; "" : the engine the directory's finished cases ran on (their
  // run.json), LIGGGHTS for a new reproduction. Cases run on another engine are refused without force.
  std::string engine;
  int jobs = 1;
  // Each engine's program by the engine's name (its row's option: --liggghts, --lammps); absent:
  // the row's name on PATH.
  std::map<std::string, std::string> programs;
  std::string against;                     // another engine's reproduction to set this one beside ("": none)
  std::string gnuplot = "gnuplot";
  // Why the options given are for engines that will not run, once the engine is chosen (`running`:
  // the chosen one and, with validate, the other), or "": a refusal (AgainstError's exit) before
  // any case is made or changed. None: not checked.
  std::function<std::string(const std::vector<std::string>& running)> refuse_engine_options;
  // Progress: a stage name and a line of detail, about twice a second while cases run.
  std::function<void(const std::string& line)> on_progress;
  // A line per event worth a log line (a case done, reused, failed), flushed at once by the caller.
  std::function<void(const std::string& line)> on_event;
};

// reproduce --against DIR: this reproduction beside another engine's (engines.hpp).
struct EngineDifference {
  std::string experiment, claim;
  std::optional<double> here, there;  // the claim's primary reading on this engine and the other
  std::optional<double> relative;     // |here - there| / max(|here|, |there|); none where either is missing
  std::string verdict_here, verdict_there;
  std::string cause;                  // why the engines differ on the experiment's cases
};

struct EngineComparison {
  std::string dir;                     // the other reproduction
  std::string engine_here, engine_there;
  std::vector<EngineDifference> claims;
  int changed() const;                 // claims whose verdict differs
  int compared() const;                // claims run on both engines
  // "K of N statements run on both change their verdict" (and how many were not run there), or,
  // where none was run on both, that the other reproduction ran none of these statements.
  std::string verdict_changes() const;
};

struct StudyResult {
  std::vector<ExperimentResult> experiments;
  double wall_seconds = 0.0;
  bool quick = false, full = false, validated = false;
  std::string engine;         // the engine every run case ran on, by their run records
  int failed_cases = 0;       // failed to run or to reduce
  int interrupted_cases = 0;  // stopped by a signal, or not begun because one came first
  bool interrupted = false;
  bool report_kept = false;   // interrupted: the report of an earlier run was left as it was
  std::vector<OutOfScope> out_of_scope;  // the catalogue's statements not tested, for the report
  std::optional<EngineComparison> against;  // with ReproduceOptions::against
};

// Thrown when DIR or one of its cases is not granstack's, or holds a case of another spec and
// force is off: nothing is changed. (Also formats::RefusedError / ExistsError.)
class ReproduceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// An --against DIR2 that cannot be compared with (not a reproduction's, of the same engine, or
// changed since its report): bad input, refused before anything is made or run.
class AgainstError : public ReproduceError {
 public:
  using ReproduceError::ReproduceError;
};

// Generates the missing cases under DIR/<experiment>/<case>, runs those not done, reduces them,
// measures and judges. Cases already done are reused, so an interrupted reproduction continues
// where it stopped. An interrupted one writes no report or figure over an earlier run's.
StudyResult reproduce(const Catalogue& catalogue, const ReproduceOptions& options);

// Judges one claim from an experiment's values.
Verdict judge(const Claim& claim, const std::map<std::string, double>& values, const std::map<std::string, double>& errors);

}  // namespace granstack::study
