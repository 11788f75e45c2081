#pragma once
// What granstack asks of a batch system. Submission is generic (submit.cpp: the pending cases,
// their tasks and times, the records; status.cpp: the cases' states): everything a batch system
// spells its own way is behind this interface. SLURM's is slurm_scheduler.cpp; another batch
// system is one more such file and a line in make_scheduler.
#include "slurm_commands.hpp"

#include <granstack/cluster/slurm.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace granstack::cluster {

// The site's limits that shape a submission.
struct SiteLimits {
  long max_array_size = kDefaultMaxArraySize;
  long max_job_count = 0;  // job records the controller holds at most; 0: not said
};

// One job to submit: its script, name, log file (in the submission's directory) and the jobs it
// waits for (whatever their end).
struct JobRequest {
  std::string script, name, log;
  std::vector<std::string> after;
};

class Scheduler {
 public:
  virtual ~Scheduler() = default;
  // Its name as users know it ("SLURM"), for messages.
  virtual std::string name() const = 0;
  // Refuses (SubmitError) a submission directory its logs cannot live in.
  virtual void check_directory(const std::string& directory) const = 0;
  // Throws SubmitError, saying what to install, when its submit command is missing (a dry run
  // needs none).
  virtual void require_submit() const = 0;
  // The site's limits; with dry_run, its defaults (said in a note) when no controller answers.
  virtual SiteLimits limits(bool dry_run, std::vector<std::string>& notes) const = 0;
  // Job records the controller holds now.
  virtual long jobs_held() const = 0;
  // The script of array `index` of the submission (task i runs `granstack run` on its lines of
  // cases.txt), and of the gather job (`granstack table` over the targets).
  virtual std::string array_script(const Submission& sub, const ArrayJob& a, std::size_t index, const SubmitOptions& o) const = 0;
  virtual std::string gather_script(const Submission& sub, const std::vector<std::string>& targets, const SubmitOptions& o) const = 0;
  // The log file name of an array's tasks (for the request) and of one task (for status).
  virtual std::string array_log() const = 0;
  virtual std::string task_log(const Task& task) const = 0;
  // Submits one job; its id. Throws SubmitError with the batch system's own words.
  virtual std::string submit(const JobRequest& job, const SubmitOptions& o) const = 0;
  // Whether its queue can be asked at all (the command is there).
  virtual bool can_read_queue() const = 0;
  // The queue's tasks of these jobs, and how those that left it ended.
  virtual QueueView queue(const std::vector<std::string>& job_ids) const = 0;
  virtual std::map<Task, std::string> ended(const std::vector<std::string>& job_ids) const = 0;
};

// The client commands a scheduler runs, by name or path.
struct SchedulerPrograms {
  std::string submit = "sbatch", config = "scontrol", queue = "squeue", accounts = "sacct";
};

std::unique_ptr<Scheduler> make_slurm_scheduler(const SchedulerPrograms& programs);

// The batch system granstack submits to (SLURM: the only one it has yet).
inline std::unique_ptr<Scheduler> make_scheduler(const SchedulerPrograms& programs) { return make_slurm_scheduler(programs); }

}  // namespace granstack::cluster
