#include <granstack/design/batch.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/postproc/reduce.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <map>
#include <thread>

namespace granstack::design {

namespace fs = std::filesystem;

namespace {

class SlurmRunner : public BatchRunner {
 public:
  SlurmRunner(fs::path dir, SlurmBatchOptions o) : dir_(std::move(dir)), o_(std::move(o)) {}

  void run(const Space& space, const std::vector<model::StackSpec>& specs, Store& store,
           const std::function<void(int, int)>& on_done) override {
    // Round 1: the designs to the cap (first_run); round 2: those whose blow ended before it, run
    // to that end (or, with gravity, those whose output was not final, run longer).
    std::vector<std::pair<model::StackSpec, model::StackSpec>> jobs;  // (the design, the spec run)
    for (const auto& spec : specs) jobs.emplace_back(spec, first_run(spec));
    int stored = 0;
    while (!jobs.empty()) {
      std::vector<model::StackSpec> ran;
      for (const auto& j : jobs) ran.push_back(j.second);
      const auto outcomes = run_cases(ran);
      std::vector<std::pair<model::StackSpec, model::StackSpec>> again;
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        if (auto longer = extended(jobs[i].first, jobs[i].second, outcomes[i])) {
          again.emplace_back(jobs[i].first, std::move(*longer));
          continue;
        }
        auto e = measured(space, jobs[i].first);
        record(space, e, jobs[i].second, outcomes[i]);
        store.put(e);
        if (on_done) on_done(++stored, static_cast<int>(specs.size()));
      }
      jobs = std::move(again);
    }
  }

 private:
  // Each spec run as a case of a new batch through SLURM, its outcome by reduce; throws when a
  // case still has none after `attempts` submissions (the batch directory is kept to look at).
  std::vector<Outcome> run_cases(const std::vector<model::StackSpec>& specs) {
    const auto batch = new_batch_dir();
    std::vector<generator::CaseSpec> to_write;
    for (const auto& spec : specs) {
      auto written = spec;
      written.dump_format = model::DumpFormat::binary;  // outputs only: a third of the text's bytes, the same doubles
      to_write.push_back({spec_digest(spec).substr(0, 16), written});
    }
    generator::GenerateOptions g;
    g.output = batch;
    const auto made = generator::generate(to_write, g);
    std::vector<std::optional<Outcome>> outcomes(specs.size());
    std::size_t left = specs.size();
    for (int attempt = 1; attempt <= o_.attempts && left > 0; ++attempt) {
      submit_and_wait(batch, attempt, static_cast<int>(left));
      for (std::size_t i = 0; i < specs.size(); ++i) {
        if (outcomes[i]) continue;
        outcomes[i] = result(made.case_dirs.at(i).string(), specs[i]);
        if (outcomes[i]) --left;
      }
    }
    std::vector<Outcome> out;
    std::vector<std::string> missing;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (outcomes[i]) out.push_back(*outcomes[i]);
      else missing.push_back(made.case_dirs.at(i).string());
    }
    if (!missing.empty()) {
      throw std::runtime_error(fmt::format("{} design(s) of the batch have no result after {} submissions (see 'granstack "
                                           "status {}' for why): {}; run the search again to resume",
                                           missing.size(), o_.attempts, batch.string(), fmt::join(missing, ", ")));
    }
    fs::remove_all(batch);  // granstack made it; every outcome is taken
    return out;
  }

  fs::path new_batch_dir() const {
    fs::create_directories(dir_);
    for (int n = 1;; ++n) {
      const auto d = dir_ / fmt::format("b{}", n);
      if (!fs::exists(d)) return d;
    }
  }

  // Submits the batch's cases that are not done, and waits until none is queued or running.
  void submit_and_wait(const fs::path& batch, int attempt, int left) {
    const auto s = cluster::submit({batch.string()}, o_.submit);
    std::vector<std::string> ids;
    for (const auto& a : s.arrays) ids.push_back(a.job_id);
    if (o_.on_note) {
      o_.on_note(fmt::format("{} {} design(s) as SLURM job{} {}", attempt == 1 ? "submitted" : "submitted again", left,
                             ids.size() == 1 ? "" : "s", fmt::join(ids, ", ")));
    }
    for (;;) {
      const auto st = cluster::status({batch.string()}, o_.submit.squeue);
      if (st.pending == 0 && st.running == 0) return;
      if (os::interrupt_signal() != 0) throw std::runtime_error("stopped by a signal while the batch was queued");
      std::this_thread::sleep_for(std::chrono::duration<double>(o_.poll_seconds));
    }
  }

  // The outcome of a finished case (reduce's values, which are the in-situ ones), or nullopt.
  static std::optional<Outcome> result(const std::string& dir, const model::StackSpec& spec) {
    postproc::ReduceOptions quiet;
    quiet.write_files = false;
    quiet.threads = 1;
    postproc::CaseReduction r;
    try {
      r = postproc::reduce_case(dir, quiet);
    } catch (const std::exception&) {
      return std::nullopt;  // not run, interrupted or failed: submitted again
    }
    return outcome_of(r, spec);
  }

  fs::path dir_;
  SlurmBatchOptions o_;
};

}  // namespace

std::unique_ptr<BatchRunner> slurm_runner(const fs::path& batches_dir, SlurmBatchOptions options) {
  return std::make_unique<SlurmRunner>(batches_dir, std::move(options));
}

}  // namespace granstack::design
