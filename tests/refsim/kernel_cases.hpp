#pragma once
// The stacks the kernel tests run: one that takes every path (damped and frictional with walls
// and gravity: sticking, sliding, history reset and walls) and one elastic and frictionless
// (kn delta n, no torques, pairs of still spheres skipped), the latter also in reversed sphere
// order, so that the pulse reaches the higher-numbered sphere of a pair first in one and the
// lower-numbered one in the other. Used by the native kernel tests and written to files for the
// emulated check of the ARM kernels (kernel_case_file.hpp).
#include <granstack/model/stack.hpp>
#include <granstack/refsim/system.hpp>

#include <string>
#include <vector>

namespace granstack::test_support {

struct KernelCase {
  std::string name;
  model::Stack stack;
  std::vector<refsim::Particle> particles;
  std::size_t output = 0;  // the output sphere's index in `particles`
};

std::vector<KernelCase> kernel_cases();

}  // namespace granstack::test_support
