// The kernel check for a CPU this machine is not: built with a cross compiler from refsim's
// system sources alone and run under emulation (qemu-aarch64 for ARM's NEON kernels). For each
// case file (write_kernel_cases.cpp) it runs the reference kernel and every vector instruction
// set the emulated CPU offers, step by step and advancing, 3000 steps, and requires every one to
// give the reference's bits (kernel_check.hpp), as the native test
// Kernels.EveryVectorInstructionSetGivesExactlyTheReferenceResult does. On one thread: under
// qemu-user a thread spinning at refsim's step barrier keeps the other waiting in the
// emulator's own lock (measured: no progress in minutes), and the emulator runs ARM's weaker
// memory order on this host's stronger one, so a second thread would check nothing of ARM's;
// the native tests hold two threads to one.
// Usage: emulated_kernels EXPECTED_TARGET CASE_FILE...
#include <granstack/refsim/system.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "kernel_check.hpp"

namespace {

using namespace granstack;

std::unique_ptr<refsim::System> run(const test_support::KernelCaseFile& c, const std::string& kernel, bool advance) {
  auto params = c.params;
  params.kernel = kernel;
  return test_support::run_3000_steps(c.particles, params, advance);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: emulated_kernels EXPECTED_TARGET CASE_FILE...\n");
    return 2;
  }
  const std::string expected = argv[1];
  const auto targets = refsim::vector_kernels();
  std::string offered;
  for (const auto& t : targets) offered += " " + t;
  std::printf("vector instruction sets offered:%s\n", offered.c_str());
  if (std::find(targets.begin(), targets.end(), expected) == targets.end()) {
    std::printf("FAILED: %s is not among them, so it was not checked\n", expected.c_str());
    return 1;
  }
  int passed = 0, failed = 0;
  try {
    for (int f = 2; f < argc; ++f) {
      const auto c = test_support::read_kernel_case(argv[f]);
      const auto reference = run(c, "reference", false);
      if (reference->v(c.output) == refsim::Vec3{0, 0, 0} || reference->neighbor_builds() < 2) {
        std::printf("FAILED %s: the reference run did not get the pulse to the output sphere through rebuilds\n", argv[f]);
        ++failed;
        continue;
      }
      for (const auto& target : targets) {
        for (const bool advance : {false, true}) {
          const auto difference = test_support::first_difference(*run(c, target, advance), *reference);
          std::printf("%s %s, %s, %s%s%s\n", difference.empty() ? "ok" : "FAILED", argv[f], target.c_str(),
                      advance ? "advancing" : "step by step", difference.empty() ? "" : ": ", difference.c_str());
          std::fflush(stdout);  // line by line, as each run ends
          (difference.empty() ? passed : failed) += 1;
        }
      }
    }
  } catch (const std::exception& e) {
    std::printf("FAILED: %s\n", e.what());
    return 1;
  }
  std::printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 && passed > 0 ? 0 : 1;
}
