#pragma once
// Sweeps as SLURM job arrays, beside the local runner: no database and no daemon, the case
// directories are the state. Each array task runs `granstack run` on its cases, so case locks,
// run.json and failure detection are those of a laptop run.
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace granstack::cluster {

struct SubmitOptions {
  std::string engine = "liggghts";       // or refsim, lammps
  int ranks = 1;                         // MPI ranks per case (--np)
  // Nodes per task (sbatch --nodes), for a case bigger than one node: its --np ranks are spread
  // over them and mpirun starts them inside the allocation. 0: SLURM places the ranks.
  int nodes = 0;
  int cases_per_task = 1;                // M
  bool cases_per_task_given = false;     // M was asked for: never packed to fit MaxJobCount
  int max_parallel = 0;                  // K: the array's %K throttle; 0 = none
  std::string partition, account;
  std::string time;                      // HH:MM:SS per task; empty: estimated (estimate_task_time)
  std::optional<long> mem_mb;
  std::vector<std::string> sbatch_args;  // passed to sbatch as they are
  bool gather = false;                   // a dependent job runs `table` over the targets
  bool dry_run = false;                  // write the scripts, submit nothing
  bool force = false;                    // every case, done or not
  std::string granstack;                 // this program, as the tasks run it (absolute path)
  std::string sbatch = "sbatch", scontrol = "scontrol", squeue = "squeue";
};

struct ArrayJob {
  std::string script;            // its sbatch script
  std::string job_id;            // empty with dry_run
  int first_case = 0, tasks = 0; // its cases are pending[first_case ...]
  std::string time;              // its wall time: its longest task's
  int throttle = 0;              // its %K: its share of --max-parallel
  bool after_previous = false;   // it waits for the array before it (more arrays than --max-parallel)
};

struct Submission {
  std::string directory;          // TARGET/slurm/submit-N: scripts, case lists, task output
  std::vector<std::string> cases; // the pending cases submitted, in order
  std::vector<ArrayJob> arrays;   // one per MaxArraySize tasks
  std::string gather_script, gather_job_id;
  std::string time;               // the longest array's
  std::string gather_time;
  long max_array_size = 0;
  std::vector<std::string> skipped;  // pending cases already queued or running: not submitted again
  std::vector<std::string> notes;    // what was assumed or changed (no controller, MaxJobCount, a damaged record)
};

// What cannot be submitted: sbatch or scontrol missing, SLURM refusing (its own words), a path
// a script cannot hold. Nothing is left half-written.
class SubmitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The cases of the targets (case or sweep directories) that are not done (all with force), less
// those already queued by an earlier submission or running (skipped, and listed), split into
// tasks of cases_per_task (more when MaxJobCount leaves no room) and arrays of at most
// MaxArraySize tasks (read from `scontrol show config`; 1001, SLURM's default, when there is no
// cluster to ask and dry_run), written into TARGET/slurm/submit-N (N the next free number, under
// the first target; slurm/dry-run for a dry run) and submitted. Each array is recorded in every
// target's slurm/submissions.json as SLURM accepts it; a refused first array leaves nothing.
Submission submit(const std::vector<std::string>& targets, const SubmitOptions& options);

// Wall time for a task of these cases: their LIGGGHTS time estimate (model::estimate_cost, the
// slowest rate measured here) times kTimeSafety, over `ranks` (no better than linear), at least
// kMinTaskSeconds; as HH:MM:SS.
std::string estimate_task_time(const std::vector<std::string>& case_dirs, int ranks);
inline constexpr double kTimeSafety = 3.0;

// A wall time in one of SLURM's forms (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS) as
// seconds; nullopt for anything else, for zero (which SLURM reads as no limit at all) and for
// more than a year.
std::optional<long> parse_slurm_time(const std::string& text);
// A memory size as SLURM's --mem takes it (a whole number, with M, G or T as binary multiples of
// a megabyte; none means M) in MB; nullopt for anything else, zero or above 1024 T.
std::optional<long> parse_memory_mb(const std::string& text);
inline constexpr double kMinTaskSeconds = 300.0;

struct CaseState {
  std::string dir, status;  // done, changed (done, but edited or its outputs replaced since), failed, running,
                            // interrupted, pending
  std::string error;        // the first line of a failed case's error, or of why a changed one is
};

struct StatusReport {
  std::vector<CaseState> cases;
  int done = 0, changed = 0, failed = 0, running = 0, interrupted = 0, pending = 0;
  int damaged = 0;                        // not run, and its manifest cannot be read (generate it again)
  std::vector<std::string> job_ids;       // of the last submission, when there is one
  std::vector<std::string> queue;         // squeue's lines for those jobs (when squeue answered)
  bool squeue_available = false;          // squeue answered
  std::vector<std::string> notes;         // what could not be read (a damaged record, no controller)
};

// From the case directories (run.json and the case's lock) and, when squeue is there, the
// queue. A case whose run.json says running while no granstack holds its lock was killed
// outright: interrupted. A case of the last submission with no run.json whose task has left the
// queue was never run by its task: failed, naming the task's log; how SLURM ended a task
// (TIMEOUT, CANCELLED, FAILED) comes from sacct, or scontrol for recent jobs.
StatusReport status(const std::vector<std::string>& targets, const std::string& squeue = "squeue",
                    const std::string& sacct = "sacct", const std::string& scontrol = "scontrol");

}  // namespace granstack::cluster
