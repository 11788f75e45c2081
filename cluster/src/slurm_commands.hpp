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
};

SlurmResult run_slurm(const std::vector<std::string>& argv);
std::vector<std::string> lines(const std::string& text);

}  // namespace granstack::cluster
