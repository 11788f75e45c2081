#pragma once
// A test's work directories are removed when the test passes: the suite writes gigabytes of runs
// (LIGGGHTS dumps, sweeps big enough to interrupt), and a CI machine's disk filled up with them
// before the suite ended. A failed test keeps what it wrote, for its diagnosis, and
// GRANSTACK_KEEP_TEST_WORK=1 keeps everything.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace granstack::test {

namespace detail {

struct Scratch {
  std::vector<std::filesystem::path> test;     // removed when the running test passes
  std::vector<std::filesystem::path> program;  // removed when every test of the process passed
};

inline Scratch& scratch_paths() {
  static Scratch s;
  return s;
}

inline void remove_scratch(std::vector<std::filesystem::path>& paths, bool passed) {
  const char* keep = std::getenv("GRANSTACK_KEEP_TEST_WORK");
  if (passed && (keep == nullptr || std::string(keep) != "1")) {
    for (const auto& p : paths) {
      std::error_code ec;
      std::filesystem::remove_all(p, ec);
    }
  }
  paths.clear();
}

class ScratchCleaner : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo& info) override {
    remove_scratch(scratch_paths().test, !info.result()->Failed());
  }
  void OnTestProgramEnd(const ::testing::UnitTest& unit) override {
    remove_scratch(scratch_paths().program, unit.failed_test_count() == 0);
  }
};

// gtest owns the listener; it is appended once per process, before main.
inline const bool scratch_cleaner_installed = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new ScratchCleaner);
  return true;
}();

inline void note(std::vector<std::filesystem::path>& paths, const std::filesystem::path& dir) {
  if (std::find(paths.begin(), paths.end(), dir) == paths.end()) paths.push_back(dir);
}

}  // namespace detail

// `dir`, to be removed when the running test passes (when every test of the process passed,
// where no test is running).
inline std::filesystem::path scratch(const std::filesystem::path& dir) {
  (void)detail::scratch_cleaner_installed;
  auto& s = detail::scratch_paths();
  detail::note(::testing::UnitTest::GetInstance()->current_test_info() != nullptr ? s.test : s.program, dir);
  return dir;
}

// `dir`, shared by the process's tests: removed when every test of the process passed.
inline std::filesystem::path scratch_for_process(const std::filesystem::path& dir) {
  (void)detail::scratch_cleaner_installed;
  detail::note(detail::scratch_paths().program, dir);
  return dir;
}

}  // namespace granstack::test
