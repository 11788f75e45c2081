// refsim's step loop alone, in this process: the 961-sphere stack (4 blocks, 8 top
// columns, the default e = 1 and mu = 0, or e = 0.9 and mu = 0.25 with --damped), each
// kernel run alternately, best of REPEATS. Steadier than timing whole `granstack run`s on a
// noisy machine, since nothing but System::advance is timed.
// Usage: granstack_bench_refsim_steps [STEPS [REPEATS]] [--damped]
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/refsim/case_run.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>
#include <string_view>

int main(int argc, char** argv) {
  using namespace granstack;
  const bool damped = argc > 1 && std::string_view(argv[argc - 1]) == "--damped";
  const int positional = argc - 1 - (damped ? 1 : 0);
  const long steps = positional >= 1 ? std::atol(argv[1]) : 3190;
  const int repeats = positional >= 2 ? std::atoi(argv[2]) : 9;
  model::StackSpec spec;
  spec.blocks = 4;
  spec.top_columns = 8;
  if (damped) {
    spec.restitution.value = 0.9;
    spec.friction.value = 0.25;
  }
  const auto stack = model::Stack::build(spec);
  const auto particles = refsim::particles_from(generator::data_file(stack, "bench"));
  using Kernel = refsim::Parameters::Kernel;
  const Kernel kernels[] = {Kernel::reference, Kernel::automatic};
  double best[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  bool avx512 = false;
  for (int r = 0; r < repeats; ++r) {
    for (int k = 0; k < 2; ++k) {
      auto params = refsim::case_parameters(stack);
      params.kernel = kernels[k];
      refsim::System s(particles, params);
      if (k == 1) avx512 = s.uses_avx512();
      s.setup();
      const auto t0 = std::chrono::steady_clock::now();
      s.advance(steps);
      best[k] = std::min(best[k], std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  const double n = static_cast<double>(particles.size());
  fmt::print("{} spheres, e = {}, mu = {}, {} steps, best of {}\n", particles.size(), damped ? 0.9 : 1.0,
             damped ? 0.25 : 0.0, steps, repeats);
  for (int k = 0; k < 2; ++k) {
    fmt::print("  {:26s} {:6.2f} us per step, {:.3e} particle-steps/s\n",
               k == 0 ? "reference kernel" : avx512 ? "automatic kernel (avx512)" : "automatic kernel (reference)",
               best[k] / static_cast<double>(steps) * 1e6, n * static_cast<double>(steps) / best[k]);
  }
}
