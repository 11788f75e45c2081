#pragma once
// A design search's batches as SLURM job arrays, through `granstack submit`'s machinery: each
// batch's designs are generated as cases under DIR/batches/bN, submitted (refsim, a case per
// task unless said), waited for, and each finished case reduced into the store (reduce's values
// are the in-situ ones: InSitu.EqualsReduceOfTheSameCaseRunOnRefsim). A task that was cancelled,
// timed out or failed leaves its case undone: the batch submits just those again, up to
// `attempts` times, and stops the search (resumable) if any still has no result.
#include <granstack/cluster/slurm.hpp>
#include <granstack/design/search.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace granstack::design {

struct SlurmBatchOptions {
  cluster::SubmitOptions submit;  // engine refsim; partition, time, account, ... as submit takes them
  double poll_seconds = 5.0;      // between looks at the batch's cases and the queue
  int attempts = 3;               // submissions of a design before the search stops
  std::function<void(const std::string&)> on_note;  // submissions, resubmissions, notes
};

std::unique_ptr<BatchRunner> slurm_runner(const std::filesystem::path& batches_dir, SlurmBatchOptions options);

}  // namespace granstack::design
