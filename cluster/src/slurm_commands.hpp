#pragma once
// SLURM's client commands (sbatch, scontrol, squeue), started from an argument vector with
// their output captured.
#include <map>
#include <optional>
#include <utility>
#include <string>
#include <vector>

namespace granstack::cluster {

// SLURM's MaxArraySize default (22.05), used when scontrol is missing and nothing is submitted.
inline constexpr long kDefaultMaxArraySize = 1001;

struct SlurmResult {
  bool started = false;  // false: the program is missing (output says so)
  int code = -1;
  std::string output;    // stdout and stderr
  bool timed_out = false;  // it did not answer within the time given (and was stopped)
};

// Runs a SLURM client command, stopping it after `timeout_seconds` (a controller that does not
// answer keeps scontrol and squeue waiting for minutes).
SlurmResult run_slurm(const std::vector<std::string>& argv, double timeout_seconds = 30.0);
std::vector<std::string> lines(const std::string& text);

// An array task: (array job id, task id).
using Task = std::pair<std::string, std::string>;

// The jobs of `job_ids` in the queue, one line per array task (squeue -r).
struct QueueView {
  bool answered = false;           // squeue answered (an empty queue included)
  std::string error;               // why it did not: missing, no controller, its own words
  std::vector<std::string> lines;  // "JOB STATE TIME REASON", for people
  std::map<Task, std::string> tasks;  // queued task -> PENDING, RUNNING, ...
};
QueueView read_queue(const std::vector<std::string>& job_ids, const std::string& squeue = "squeue");

// How the tasks of `job_ids` that left the queue ended (COMPLETED, FAILED, TIMEOUT, CANCELLED,
// ...): from sacct where SLURM keeps accounts, else from scontrol (jobs that ended within the
// site's MinJobAge). Tasks neither knows are absent.
std::map<Task, std::string> ended_states(const std::vector<std::string>& job_ids, const std::string& sacct = "sacct",
                                         const std::string& scontrol = "scontrol");

}  // namespace granstack::cluster
