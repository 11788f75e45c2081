// refsim's step loop alone, in this process: the 961-sphere stack (4 blocks, 8 top
// columns, the default e = 1 and mu = 0, or e = 0.9 and mu = 0.25 with --damped), the
// reference kernels and every vector instruction set this CPU runs, each run in turn, REPEATS
// rounds; median (and best) time per step. Steadier than timing whole `granstack run`s on a
// noisy machine, since nothing but System::advance is timed. With --threads, the best vector
// kernels on one thread and on two instead, alternately. With --thornton, Thornton's
// elastic-plastic law against Hertz, each on the reference kernels and on the best vector
// kernels, alternately: the cost of yielding contacts per particle-step.
// Usage: granstack_bench_refsim_steps [STEPS [REPEATS]] [--damped] [--threads] [--thornton]
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/refsim/case_run.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace {
struct Run {
  std::string label, kernel;
  int threads;
  granstack::model::NormalModel normal = granstack::model::NormalModel::hertz;
};
}  // namespace

int main(int argc, char** argv) {
  using namespace granstack;
  bool damped = false, threads = false, thornton = false;
  std::vector<std::string_view> positional;
  for (int a = 1; a < argc; ++a) {
    const std::string_view arg(argv[a]);
    if (arg == "--damped") {
      damped = true;
    } else if (arg == "--threads") {
      threads = true;
    } else if (arg == "--thornton") {
      thornton = true;
    } else {
      positional.push_back(arg);
    }
  }
  const long steps = !positional.empty() ? std::atol(positional[0].data()) : 3190;
  const int repeats = positional.size() >= 2 ? std::atoi(positional[1].data()) : 9;
  model::StackSpec spec;
  spec.blocks = 4;
  spec.top_columns = 8;
  if (damped) {
    spec.restitution.value = 0.9;
    spec.friction.value = 0.25;
  }
  const auto stack = model::Stack::build(spec);
  const auto particles = refsim::particles_from(generator::data_file(stack, "bench"));
  std::vector<Run> runs;
  if (threads) {
    const std::string best = refsim::vector_kernels().front();
    runs = {{best + ", 1 thread", best, 1}, {best + ", 2 threads", best, 2}};
  } else if (thornton) {
    const std::string best = refsim::vector_kernels().front();
    runs = {{"hertz, " + best, best, 1},
            {"hertz, reference", "reference", 1},
            {"thornton, reference", "reference", 1, model::NormalModel::thornton},
            {"thornton, " + best, best, 1, model::NormalModel::thornton}};
  } else {
    runs.push_back({"reference", "reference", 1});
    for (const auto& k : refsim::vector_kernels()) runs.push_back({k, k, 1});
  }
  std::vector<std::vector<double>> times(runs.size());
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t k = 0; k < runs.size(); ++k) {
      auto run_spec = spec;
      run_spec.normal_model = runs[k].normal;
      auto params = refsim::case_parameters(model::Stack::build(run_spec));
      params.kernel = runs[k].kernel;
      params.threads = runs[k].threads;
      refsim::System s(particles, params);
      s.setup();
      const auto t0 = std::chrono::steady_clock::now();
      s.advance(steps);
      times[k].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  const double n = static_cast<double>(particles.size());
  fmt::print("{} spheres, e = {}, mu = {}, {} steps, {} rounds, median (best)\n", particles.size(), damped ? 0.9 : 1.0,
             damped ? 0.25 : 0.0, steps, repeats);
  double reference = 0.0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    auto& t = times[k];
    std::sort(t.begin(), t.end());
    const double median = t.size() % 2 == 1 ? t[t.size() / 2] : 0.5 * (t[t.size() / 2 - 1] + t[t.size() / 2]);
    if (k == 0) reference = median;
    fmt::print("  {:18s} {:6.2f} us per step ({:6.2f}), {:.3e} particle-steps/s, {:5.2f}x the first\n", runs[k].label,
               median / static_cast<double>(steps) * 1e6, t.front() / static_cast<double>(steps) * 1e6,
               n * static_cast<double>(steps) / median, reference / median);
  }
}
