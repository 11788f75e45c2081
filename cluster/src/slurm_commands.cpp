#include "slurm_commands.hpp"

#include <granstack/formats/files.hpp>
#include <granstack/os/process.hpp>

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <thread>
#include <filesystem>
#include <sstream>
#include <unistd.h>

namespace granstack::cluster {

namespace fs = std::filesystem;

SlurmResult run_slurm(const std::vector<std::string>& argv, double timeout_seconds) {
  SlurmResult r;
  const auto program = os::find_program(argv.front());
  if (!program) {
    r.output = fmt::format("{} is not on PATH", argv.front());
    return r;
  }
  auto temp = (fs::temp_directory_path() / "granstack-slurm-XXXXXX").string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) throw std::runtime_error("cannot make a temporary file for SLURM's output");
  ::close(fd);
  std::vector<std::string> args = argv;
  args.front() = *program;
  os::StartOptions o;
  o.output = temp;
  const auto child = os::start(args, o);
  r.started = child.pid >= 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  std::optional<os::Exit> end;
  while (r.started && !(end = os::poll(child))) {
    if (std::chrono::steady_clock::now() > deadline) {
      os::kill_group(child);
      os::wait(child);
      r.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  r.code = end ? end->code : -1;
  const std::string error = r.started ? "" : child.error;
  try {
    r.output = formats::read_file(temp);
  } catch (const std::exception&) {
  }
  std::error_code ec;
  fs::remove(temp, ec);
  if (!r.started) r.output = error;
  if (r.timed_out) r.output = fmt::format("{} did not answer within {:.0f} s (is the SLURM controller up?)", argv.front(), timeout_seconds);
  while (!r.output.empty() && (r.output.back() == '\n' || r.output.back() == ' ')) r.output.pop_back();
  return r;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

}  // namespace granstack::cluster
