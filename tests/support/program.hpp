#pragma once
// Running the granstack program (or SLURM's commands) from a test as a user would, from an
// argument vector (never a shell), with its stdout and stderr captured.
#include <granstack/os/process.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace granstack::test {

struct ProgramResult {
  int code = -1;       // the exit code, or minus the signal that ended it
  std::string output;  // stdout and stderr
};

inline std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs argv (argv[0] looked up on PATH when it has no '/'), its output into `log`; `env` adds or
// replaces environment variables (NAME=VALUE).
inline ProgramResult run_program(std::vector<std::string> argv, const std::filesystem::path& log,
                                 const std::vector<std::string>& env = {}) {
  std::filesystem::create_directories(log.parent_path());
  if (const auto p = os::find_program(argv.front())) argv.front() = *p;
  os::StartOptions o;
  o.output = log;
  o.extra_environment = env;
  std::string error;
  const auto end = os::run(argv, o, &error);
  EXPECT_TRUE(error.empty()) << error;
  return {end.signal != 0 ? -end.signal : end.code, read_bytes(log)};
}

}  // namespace granstack::test
