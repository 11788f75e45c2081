// A program the scratch test (tests/cli/test_trust.cpp) runs, one of its tests at a time: each
// writes into a directory of its own, one fails on purpose. ctest does not list these; only the
// scratch test runs them, to see what tests/support/scratch.hpp leaves behind.
#include "scratch.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

std::filesystem::path evidence(const char* name) {
  const auto dir = granstack::test::scratch(std::filesystem::path(GRANSTACK_TEST_WORKDIR) / name);
  std::filesystem::create_directories(dir);
  return dir / "evidence";
}

TEST(Probe, WritesAndFails) {
  std::ofstream(evidence("Probe_WritesAndFails")) << "what the failure left";
  FAIL() << "failing on purpose";
}

TEST(Probe, WritesAndPasses) { std::ofstream(evidence("Probe_WritesAndPasses")) << "what the pass left"; }

}  // namespace
