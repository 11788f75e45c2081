#pragma once
// Runs LIGGGHTS on generated case directories, several at once, with a progress display,
// failure detection and a run record (run.json) in each case directory.
#include <any>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <typeindex>
#include <vector>

namespace granstack::runner {

struct CaseProgress {
  std::string name;
  long step = 0;          // last thermo step seen
  long total_steps = 0;
  double elapsed = 0.0;   // s
};

struct ProgressSnapshot {
  int finished = 0;  // cases done, skipped or failed
  int total = 0;
  std::vector<CaseProgress> running;
};

// The engines, each a row of engine_table() (engines.hpp).
enum class Engine {
  liggghts,  // the real DEM code, as a separate process
  refsim,    // the in-house reference integrator, in this process
  lammps     // LAMMPS's GRANULAR package, as a separate process (docs/explanation/lammps.md)
};

// The engines' names, as flags, run.json and folder names spell them (engines.hpp's table).
std::vector<std::string> engine_names();
std::string to_string(Engine e);
// The engine a name (one of engine_names()) stands for; std::invalid_argument for another.
Engine parse_engine(const std::string& name);
// The engine a cross-check sets beside `e`: refsim beside a DEM code, LIGGGHTS beside refsim.
inline Engine other_engine(Engine e) { return e == Engine::refsim ? Engine::liggghts : Engine::refsim; }

// interrupted: stopped by SIGINT/SIGTERM/SIGHUP to granstack (run.json says so); not_started:
// not begun because such a signal came first.
enum class RunStatus { done, skipped, failed, interrupted, not_started };

struct RunOutcome {
  std::string case_dir;
  RunStatus status = RunStatus::failed;
  std::string message;  // why it failed or was skipped; LIGGGHTS's own error line when there is one
  double wall_seconds = 0.0;
  double loop_seconds = 0.0;
  double particle_steps_per_second = 0.0;
};

// What every engine's runs share; each engine's own options are a struct of its own
// (engine_options.hpp for the built-in ones), kept here by type: `own<RefsimOptions>().threads = 4`.
// A struct no one set reads as its defaults.
struct RunOptions {
  Engine engine = Engine::liggghts;
  int jobs = 1;           // cases run at the same time
  // The engines that run a program (LIGGGHTS, LAMMPS): MPI ranks per case (mpirun when > 1) and
  // mpirun itself.
  int ranks = 1;
  std::string mpirun = "mpirun";
  // Each engine's program, by engine (its row's `program`: --liggghts, --lammps); absent: the
  // row's name on PATH (program()).
  std::map<Engine, std::string> programs;
  bool force = false;     // rerun cases that finished
  // Called about twice a second while cases run, and once at the end.
  std::function<void(const ProgressSnapshot&)> on_progress;
  // Called as each case ends (done, skipped, failed, interrupted), one call at a time.
  std::function<void(const RunOutcome&)> on_case_done;

  // Engine `e`'s program as given, else its row's default.
  std::string program(Engine e) const;
  // An engine's own options (made with their defaults at first use).
  template <class T>
  T& own() {
    auto& slot = own_[std::type_index(typeid(T))];
    if (!slot.has_value()) slot = T{};
    return std::any_cast<T&>(slot);
  }
  template <class T>
  const T& own() const {
    static const T defaults{};
    const auto it = own_.find(std::type_index(typeid(T)));
    return it == own_.end() ? defaults : std::any_cast<const T&>(it->second);
  }

 private:
  std::map<std::type_index, std::any> own_;
};

// Runs every case (already expanded from sweep directories), each under its case lock (a case
// another granstack is running fails with that one named). Never throws for a failing case: the
// failure is in its outcome and its run.json. After os::interrupt_signal() is set, running cases
// are stopped (their LIGGGHTS killed) and marked interrupted, and no other case starts.
std::vector<RunOutcome> run_cases(const std::vector<std::string>& case_dirs, const RunOptions& options);

// Takes the outputs of cases whose deck was run outside granstack (`liggghts -in in.stack` in the
// case's folder, or scripts of the user's own) as their runs (adopt.cpp): the deck as generated,
// what its log shows LIGGGHTS executed held to the case, a whole run, the dump's frames and the
// series' rows; then run.json records the run with its digests and "run_by": "hand". A case with
// a finished run is skipped unless `force`; a case refused is `failed`, its message saying why,
// and keeps its run.json.
std::vector<RunOutcome> adopt_cases(const std::vector<std::string>& case_dirs, bool force);

// Copies the inputs of a case (manifest, data file, deck) into a new directory `target`
// (replacing a granstack case there; anything else there is refused), so the same case can be
// run again elsewhere, e.g. by the other engine.
void clone_case_inputs(const std::string& case_dir, const std::string& target);

// Where `engine` runs its copy of a case for a cross-check: CASE/validate/ENGINE.
std::string copy_dir(const std::string& case_dir, Engine engine);

// The cross-check's runs (validate, reproduce --validate): `engine` on a fresh copy of each case's
// inputs (copy_dir), every copy run anew. The callers compare the copies' outputs with
// postproc::compare_runs.
std::vector<RunOutcome> run_copies(const std::vector<std::string>& case_dirs, Engine engine, RunOptions options);

}  // namespace granstack::runner
