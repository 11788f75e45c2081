// LAMMPS behind the engine interface: the case's spec rendered as a LAMMPS deck (in.lammps, from
// templates/in.lammps.tmpl or the user's --lammps-template), run as LIGGGHTS is (program.hpp) on
// the same data file, writing the same dumps and series.
#include "engine.hpp"
#include "program.hpp"

#include <granstack/formats/files.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/os/process.hpp>

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

namespace granstack::runner {

namespace fs = std::filesystem;

namespace {

// The names of a LAMMPS run's own files in the case.
formats::CaseFiles lammps_files(formats::CaseFiles files) {
  files.deck = "in.lammps";
  files.log = "log.lammps";
  files.screen = "lammps.out";
  return files;
}

// Whether `lmp -h` lists pair style granular (the GRANULAR package), asked once per program.
bool has_granular(const std::string& program) {
  static std::mutex mutex;
  static std::map<std::string, bool> known;
  const std::lock_guard lock(mutex);
  if (const auto it = known.find(program); it != known.end()) return it->second;
  const auto help = fs::temp_directory_path() / fmt::format("granstack-lmp-help-{}", ::getpid());
  os::StartOptions start;
  start.output = help;
  const auto exit = os::run({program, "-h"}, start);
  bool found = false;
  if (exit.ok()) {
    std::ifstream in(help);
    std::string line;
    bool pair_styles = false;
    while (std::getline(in, line)) {
      if (line.find("* Pair styles:") != std::string::npos) pair_styles = true;
      else if (pair_styles && line.rfind("* ", 0) == 0) break;  // the next section
      if (pair_styles && (" " + line + " ").find(" granular ") != std::string::npos) found = true;
    }
  }
  std::error_code ec;
  fs::remove(help, ec);
  return known[program] = found;
}

// The case's deck, from the template the options name (a user's, or templates/in.lammps.tmpl).
std::string render_deck(const formats::Case& c, const RunOptions& o) {
  const bool own = o.lammps_template.empty();
  const auto text = own ? std::string(generator::default_lammps_template()) : formats::read_file(o.lammps_template);
  return generator::lammps_deck(c.stack(), c.resolution(), c.files(), c.name(), text,
                                own ? "templates/in.lammps.tmpl" : o.lammps_template);
}

// LAMMPS's fix print also prints when each run sets up (fix_print.cpp's setup()): at step 0, and
// at the first step of every interval of a blow-end run, again. LIGGGHTS's does not, and the
// series reader expects its rows: the setup rows are removed, each checked to repeat the row
// of its step already written (the same state, so the same text). Returns why not, or "".
std::string drop_setup_rows(const fs::path& path) {
  const auto text = formats::read_file(path);
  std::string out, last_step, last_row;
  out.reserve(text.size());
  std::size_t at = 0, line_number = 0;
  while (at < text.size()) {
    auto end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(at, end - at);
    at = end + 1;
    ++line_number;
    if (line.empty() || line[0] == '#') {
      out += line + '\n';
      continue;
    }
    const auto step = line.substr(0, line.find(' '));
    if (step == "0" && last_step.empty()) continue;  // the first run's setup
    if (step == last_step) {
      if (line != last_row) {
        return fmt::format("{}:{}: LAMMPS printed step {} twice with different values", path.string(), line_number, step);
      }
      continue;
    }
    last_step = step;
    last_row = line;
    out += line + '\n';
  }
  if (out.size() != text.size()) formats::write_file_atomically(path, out);
  return "";
}

class Lammps final : public CaseEngine {
 public:
  std::string lock_holder() const override { return "granstack run --engine lammps"; }

  formats::CaseFiles files(const formats::Case& c) const override { return lammps_files(c.files()); }

  std::string unavailable(const formats::Case& c, const RunOptions& o) const override {
    if (auto why = program_unavailable("LAMMPS", o.lammps, "--lammps", "lammps", o); !why.empty()) return why;
    const auto program = *os::find_program(o.lammps);
    if (!has_granular(program)) {
      return fmt::format("LAMMPS ({}) has no pair style 'granular' ('{} -h' does not list it): it was built without "
                         "the GRANULAR package; install Debian's 'lammps', or pass --lammps with a LAMMPS that has it",
                         program, o.lammps);
    }
    if (const auto why = model::lammps_unmappable(c.spec()); !why.empty()) return "LAMMPS: " + why;
    try {
      (void)render_deck(c, o);
    } catch (const std::exception& e) {
      return fmt::format("LAMMPS: the deck cannot be rendered: {}", e.what());
    }
    return "";
  }

  EngineResult run(const formats::Case& c, const RunOptions& o, const std::function<void(long)>& on_step,
                   const std::function<void()>& on_started) const override {
    const auto files = lammps_files(c.files());
    EngineResult result;
    try {
      formats::write_file_atomically(fs::path(c.dir()) / files.deck, render_deck(c, o));
    } catch (const std::exception& e) {
      result.error = fmt::format("LAMMPS: {} could not be written: {}", files.deck, e.what());
      return result;
    }
    result = run_program(c, o, {"LAMMPS", o.lammps, files, "lammps_version", {}}, on_step, on_started);
    if (result.error.empty() && !result.interrupted) {
      try {
        result.error = drop_setup_rows(fs::path(c.dir()) / files.series);
      } catch (const std::exception& e) {
        result.error = e.what();
      }
    }
    result.record["lammps_deck"] = files.deck;
    result.record["lammps_template"] = o.lammps_template.empty() ? "templates/in.lammps.tmpl" : o.lammps_template;
    return result;
  }
};

}  // namespace

std::unique_ptr<CaseEngine> make_lammps_engine() { return std::make_unique<Lammps>(); }

}  // namespace granstack::runner
