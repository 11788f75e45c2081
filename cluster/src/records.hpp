#pragma once
// What granstack remembers of its submissions: TARGET/slurm/submissions.json (one entry per
// submission, newest last) and each submission's cases.txt. Written as each array is accepted,
// so a submission that fails part-way leaves no running array unrecorded.
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace granstack::cluster {

struct RecordedArray {
  std::string job_id;
  int first_case = 0, tasks = 0;
};

struct RecordedSubmission {
  std::string directory;
  int cases_per_task = 1;
  std::vector<RecordedArray> arrays;
  std::string gather_job_id;
  // The submission's cases, from its cases.txt.
  std::vector<std::string> cases() const;
  // The array task (job id, task) of each of the first `count` cases, indexed like cases().
  std::vector<std::pair<std::string, std::string>> case_tasks(std::size_t count) const;
};

struct Records {
  std::vector<RecordedSubmission> submissions;  // oldest first
  std::string damage;  // why submissions.json could not be read ("" when it could, or is absent)
};

// A target's records. A damaged file is reported in `damage`, never thrown.
Records read_records(const std::string& target);

// Writes (or rewrites, by its directory) one submission's entry into every target's records. A
// damaged submissions.json is first moved aside (to submissions.json.damaged-TIME); returns what
// was moved, for the user to hear of it.
std::vector<std::string> record_submission(const std::vector<std::string>& targets, const nlohmann::json& entry);

}  // namespace granstack::cluster
