#include <granstack/design/batch.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/postproc/reduce.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
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
    std::map<std::string, model::StackSpec> cases;  // case directory -> its design
    for (std::size_t i = 0; i < specs.size(); ++i) cases[made.case_dirs.at(i).string()] = specs[i];
    int stored = 0;
    for (int attempt = 1; attempt <= o_.attempts && !cases.empty(); ++attempt) {
      submit_and_wait(batch, attempt, static_cast<int>(cases.size()));
      for (auto it = cases.begin(); it != cases.end();) {
        if (auto e = result(space, it->first, it->second)) {
          store.put(*e);
          it = cases.erase(it);
          if (on_done) on_done(++stored, static_cast<int>(specs.size()));
        } else {
          ++it;
        }
      }
    }
    if (!cases.empty()) {
      std::vector<std::string> left;
      for (const auto& [dir, spec] : cases) left.push_back(dir);
      throw std::runtime_error(fmt::format("{} design(s) of the batch have no result after {} submissions (see 'granstack "
                                           "status {}' for why): {}; run the search again to resume",
                                           left.size(), o_.attempts, batch.string(), fmt::join(left, ", ")));
    }
    fs::remove_all(batch);  // granstack made it; every result is in the store
  }

 private:
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

  // The evaluation of a finished case (reduce's values, which are the in-situ ones), or nullopt.
  static std::optional<Evaluation> result(const Space& space, const std::string& dir, const model::StackSpec& spec) {
    postproc::ReduceOptions quiet;
    quiet.write_files = false;
    quiet.threads = 1;
    postproc::CaseReduction r;
    try {
      r = postproc::reduce_case(dir, quiet);
    } catch (const std::exception&) {
      return std::nullopt;  // not run, interrupted or failed: submitted again
    }
    auto e = measured(space, spec);
    if (spec.bottom == model::Boundary::free_surface) {
      e.output_fraction = r.output_fraction;
      e.output_separated = r.output_separated;
    }
    e.peak_wall_force = r.peak_wall_force;
    return e;
  }

  fs::path dir_;
  SlurmBatchOptions o_;
};

}  // namespace

std::unique_ptr<BatchRunner> slurm_runner(const fs::path& batches_dir, SlurmBatchOptions options) {
  return std::make_unique<SlurmRunner>(batches_dir, std::move(options));
}

}  // namespace granstack::design
