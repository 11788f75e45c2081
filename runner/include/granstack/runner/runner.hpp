#pragma once
// Runs LIGGGHTS on generated case directories, several at once, with a progress display,
// failure detection and a run record (run.json) in each case directory.
#include <array>
#include <functional>
#include <optional>
#include <string>
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
const std::vector<std::string>& engine_names();
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

struct RunOptions {
  Engine engine = Engine::liggghts;
  int jobs = 1;           // cases run at the same time
  int ranks = 1;          // MPI ranks per case (mpirun when > 1; LIGGGHTS and LAMMPS)
  // The MPI processor grid (ranks along x, y, z); all zero: chosen for each case's stack
  // (choose_decomposition in decomposition.hpp).
  std::array<int, 3> grid{0, 0, 0};
  int threads = 1;        // threads per case (refsim only)
  // refsim by LAMMPS's contact rules instead of LIGGGHTS's (refsim::Parameters::lammps_rules): the
  // model a case has on LAMMPS, for a cross-check with it.
  bool lammps_rules = false;
  std::string kernel = "auto";  // refsim's kernels: auto, reference or a vector instruction set (refsim::vector_kernels())
  bool force = false;     // rerun cases that finished
  std::string liggghts = "liggghts";
  std::string lammps = "lmp";
  std::string lammps_template;  // a template of the user's for the LAMMPS deck; "": templates/in.lammps.tmpl
  std::string mpirun = "mpirun";
  // Called about twice a second while cases run, and once at the end.
  std::function<void(const ProgressSnapshot&)> on_progress;
  // Called as each case ends (done, skipped, failed, interrupted), one call at a time.
  std::function<void(const RunOutcome&)> on_case_done;
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
