#pragma once
// SLURM's client commands (sbatch, scontrol, squeue), started from an argument vector with
// their output captured.
#include <optional>
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

}  // namespace granstack::cluster
