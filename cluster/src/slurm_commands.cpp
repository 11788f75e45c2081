#include "slurm_commands.hpp"

#include <granstack/formats/files.hpp>
#include <granstack/os/process.hpp>

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <unistd.h>

namespace granstack::cluster {

namespace fs = std::filesystem;

SlurmResult run_slurm(const std::vector<std::string>& argv) {
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
  std::string error;
  const auto end = os::run(args, o, &error);
  r.started = error.empty();
  r.code = end.code;
  try {
    r.output = formats::read_file(temp);
  } catch (const std::exception&) {
  }
  std::error_code ec;
  fs::remove(temp, ec);
  if (!r.started) r.output = error;
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
