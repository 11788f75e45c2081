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
  std::string engine = "liggghts";       // or refsim
  int ranks = 1;                         // MPI ranks per case (--np)
  int cases_per_task = 1;                // M
  int max_parallel = 0;                  // K: the array's %K throttle; 0 = none
  std::string partition, account;
  std::string time;                      // HH:MM:SS per task; empty: estimated (estimate_task_time)
  std::optional<long> mem_mb;
  std::vector<std::string> sbatch_args;  // passed to sbatch as they are
  bool gather = false;                   // a dependent job runs `table` over the targets
  bool dry_run = false;                  // write the scripts, submit nothing
  bool force = false;                    // every case, done or not
  std::string granstack;                 // this program, as the tasks run it (absolute path)
  std::string sbatch = "sbatch", scontrol = "scontrol";
};

struct ArrayJob {
  std::string script;            // its sbatch script
  std::string job_id;            // empty with dry_run
  int first_case = 0, tasks = 0; // its cases are pending[first_case ...]
};

struct Submission {
  std::string directory;          // TARGET/slurm/submit-N: scripts, case lists, task output
  std::vector<std::string> cases; // the pending cases submitted, in order
  std::vector<ArrayJob> arrays;   // one per MaxArraySize tasks
  std::string gather_script, gather_job_id;
  std::string time;               // per task
  long max_array_size = 0;
  std::string note;               // what was assumed (a dry run with no controller to ask)
};

// What cannot be submitted: sbatch or scontrol missing, SLURM refusing (its own words), a path
// a script cannot hold. Nothing is left half-written.
class SubmitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The cases of the targets (case or sweep directories) that are not done (all with force),
// split into tasks of cases_per_task and arrays of at most MaxArraySize tasks (read from
// `scontrol show config`; 1001, SLURM's default, when there is no cluster to ask and dry_run), written
// into TARGET/slurm/submit-N (N the next free number, under the first target) and submitted.
// The submission is recorded in every target's slurm/submissions.json.
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
inline constexpr double kMinTaskSeconds = 300.0;

struct CaseState {
  std::string dir, status;  // done, failed, running, interrupted, pending
  std::string error;        // the first line of a failed case's error
};

struct StatusReport {
  std::vector<CaseState> cases;
  int done = 0, failed = 0, running = 0, interrupted = 0, pending = 0;
  std::vector<std::string> job_ids;       // of the last submission, when there is one
  std::vector<std::string> queue;         // squeue's lines for those jobs (when squeue is there)
  bool squeue_available = false;
};

// From the case directories (run.json) and, when squeue is there, the queue. A case whose
// run.json says running while none of the last submission's jobs is in the queue any more was
// killed outright (time limit, node failure): it counts as interrupted.
StatusReport status(const std::vector<std::string>& targets, const std::string& squeue = "squeue");

}  // namespace granstack::cluster
