// Writes the kernel tests' stacks (kernel_cases.hpp) as case files into a directory, for the
// emulated check of the ARM kernels (emulated_kernels.cpp), which cannot build them itself.
// Usage: granstack_write_kernel_cases DIR
#include <granstack/refsim/case_run.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

#include "kernel_cases.hpp"
#include "kernel_check.hpp"

int main(int argc, char** argv) {
  using namespace granstack;
  if (argc != 2) {
    std::fprintf(stderr, "usage: granstack_write_kernel_cases DIR\n");
    return 2;
  }
  std::filesystem::create_directories(argv[1]);
  for (const auto& c : test_support::kernel_cases()) {
    const auto path = (std::filesystem::path(argv[1]) / (c.name + ".case")).string();
    test_support::write_kernel_case(path, {refsim::case_parameters(c.stack), c.particles, c.output});
    std::printf("%s\n", path.c_str());
  }
  return 0;
}
