#include <granstack/design/batch.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/postproc/reduce.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <thread>

namespace granstack::design {

namespace fs = std::filesystem;

namespace {

class SlurmRunner : public BatchRunner {
 public:
  SlurmRunner(fs::path dir, SlurmBatchOptions o) : dir_(std::move(dir)), o_(std::move(o)) {}

  // One design of the asynchronous search: its scenarios as one batch (a job array), run again
  // longer where first_run's length did not reach a final output, as run() does for many.
  // Every scenario runs (the shortcuts are this machine's, in situ).
  Evaluation evaluate_one(const Space& space, const model::StackSpec& spec, bool run_anyway,
                          const std::atomic<bool>* abandon, const Dominator& /*dominator*/) override {
    auto e = measured(space, spec);
    if (!e.feasible && !run_anyway) return e;
    const auto scenarios = scenario_specs(space, spec);
    std::vector<model::StackSpec> ran;
    for (const auto& one : scenarios) ran.push_back(first_run(space, one));
    std::vector<std::optional<std::pair<model::StackSpec, Outcome>>> done(scenarios.size());
    std::vector<std::size_t> todo(scenarios.size());
    std::iota(todo.begin(), todo.end(), std::size_t{0});
    while (!todo.empty()) {
      std::vector<model::StackSpec> batch;
      for (const auto k : todo) batch.push_back(ran[k]);
      const auto outcomes = run_cases(batch, abandon);
      std::vector<std::size_t> again;
      for (std::size_t i = 0; i < todo.size(); ++i) {
        const auto k = todo[i];
        if (auto longer = extended(scenarios[k], ran[k], outcomes[i])) {
          ran[k] = std::move(*longer);
          again.push_back(k);
        } else {
          done[k].emplace(ran[k], outcomes[i]);
        }
      }
      todo = std::move(again);
    }
    std::vector<std::pair<model::StackSpec, Outcome>> runs;
    for (auto& r : done) runs.push_back(std::move(*r));
    record(space, e, runs);
    return e;
  }

  void run(const Space& space, const std::vector<model::StackSpec>& specs, Store& store,
           const std::function<void(int, int)>& on_done, const Dominator& /*dominator*/) override {
    // A job: one scenario of one design (design index, scenario index, the spec it runs). Round 1
    // runs each as first_run says (to its blow's end); round 2, with gravity only, those whose
    // output was not final, longer. A design is stored once every scenario of it is done.
    struct ScenarioJob {
      std::size_t design, scenario;
      model::StackSpec spec;
    };
    std::vector<std::vector<model::StackSpec>> scenario_of(specs.size());
    std::vector<std::vector<std::optional<std::pair<model::StackSpec, Outcome>>>> done(specs.size());
    std::vector<ScenarioJob> jobs;
    for (std::size_t d = 0; d < specs.size(); ++d) {
      scenario_of[d] = scenario_specs(space, specs[d]);
      done[d].resize(scenario_of[d].size());
      for (std::size_t k = 0; k < scenario_of[d].size(); ++k) jobs.push_back({d, k, first_run(space, scenario_of[d][k])});
    }
    int stored = 0;
    while (!jobs.empty()) {
      std::vector<model::StackSpec> ran;
      for (const auto& j : jobs) ran.push_back(j.spec);
      const auto outcomes = run_cases(ran, nullptr);
      std::vector<ScenarioJob> again;
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        const auto& j = jobs[i];
        if (auto longer = extended(scenario_of[j.design][j.scenario], j.spec, outcomes[i])) {
          again.push_back({j.design, j.scenario, std::move(*longer)});
          continue;
        }
        done[j.design][j.scenario].emplace(j.spec, outcomes[i]);
        if (std::any_of(done[j.design].begin(), done[j.design].end(), [](const auto& r) { return !r; })) continue;
        std::vector<std::pair<model::StackSpec, Outcome>> runs;
        for (auto& r : done[j.design]) runs.push_back(std::move(*r));
        auto e = measured(space, specs[j.design]);
        record(space, e, runs);
        store.put(e);
        if (on_done) on_done(++stored, static_cast<int>(specs.size()));
      }
      jobs = std::move(again);
    }
  }

 private:
  // Each spec run as a case of a new batch through SLURM, its outcome by reduce; throws when a
  // case still has none after `attempts` submissions (the batch directory is kept to look at).
  // Stops (its jobs cancelled) and throws once *abandon is set.
  std::vector<Outcome> run_cases(const std::vector<model::StackSpec>& specs, const std::atomic<bool>* abandon) {
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
      submit_and_wait(batch, attempt, static_cast<int>(left), abandon);
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

  // A batch directory no other batch of this search has taken (the asynchronous search makes
  // several at once, from its threads).
  fs::path new_batch_dir() {
    const std::lock_guard<std::mutex> lock(mutex_);
    fs::create_directories(dir_);
    for (;; ++next_batch_) {
      const auto d = dir_ / fmt::format("b{}", next_batch_);
      if (!fs::exists(d)) return dir_ / fmt::format("b{}", next_batch_++);
    }
  }
  void note(const std::string& text) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (o_.on_note) o_.on_note(text);
  }

  // Submits the batch's cases that are not done, and waits until none is queued or running; once
  // *abandon is set, cancels its jobs (scancel) and throws.
  void submit_and_wait(const fs::path& batch, int attempt, int left, const std::atomic<bool>* abandon) {
    const auto s = cluster::submit({batch.string()}, o_.submit);
    std::vector<std::string> ids;
    for (const auto& a : s.arrays) ids.push_back(a.job_id);
    note(fmt::format("{} {} case(s) as SLURM job{} {}", attempt == 1 ? "submitted" : "submitted again", left,
                     ids.size() == 1 ? "" : "s", fmt::join(ids, ", ")));
    for (;;) {
      const auto st = cluster::status({batch.string()}, o_.submit.squeue);
      if (st.pending == 0 && st.running == 0) return;
      if (os::interrupt_signal() != 0) throw std::runtime_error("stopped by a signal while the batch was queued");
      if (abandon != nullptr && abandon->load()) {
        std::vector<std::string> argv{"scancel"};
        argv.insert(argv.end(), ids.begin(), ids.end());
        (void)os::run(argv, {}, nullptr, os::probe_seconds());
        throw refsim::InSituStopped(fmt::format("abandoned: the search ended while {} ran (SLURM jobs {} cancelled)",
                                                batch.string(), fmt::join(ids, ", ")));
      }
      // An asynchronous search looks at least twice a second for its end.
      const double wait = abandon != nullptr ? std::min(o_.poll_seconds, 0.5) : o_.poll_seconds;
      for (double slept = 0.0; slept < o_.poll_seconds; slept += wait) {
        std::this_thread::sleep_for(std::chrono::duration<double>(wait));
        if ((abandon != nullptr && abandon->load()) || os::interrupt_signal() != 0) break;
      }
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
  std::mutex mutex_;  // new_batch_dir and note, from the asynchronous search's threads
  int next_batch_ = 1;
};

}  // namespace

std::unique_ptr<BatchRunner> slurm_runner(const fs::path& batches_dir, SlurmBatchOptions options) {
  return std::make_unique<SlurmRunner>(batches_dir, std::move(options));
}

}  // namespace granstack::design
