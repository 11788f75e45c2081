// LAMMPS behind the engine interface: the case's spec rendered as a LAMMPS deck (in.lammps, from
// templates/in.lammps.tmpl or the user's --lammps-template), run as LIGGGHTS is (program.hpp) on
// the same data file, writing the same dumps and series.
#include "deck_check.hpp"
#include "engine.hpp"
#include "program.hpp"

#include <granstack/formats/deck.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/os/mpi_session.hpp>
#include <granstack/os/process.hpp>
#include <granstack/runner/engine_options.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace granstack::runner {

namespace fs = std::filesystem;

namespace {

using formats::lammps_files;

// What `lmp -h` says of a LAMMPS: whether it lists pair style granular (the GRANULAR package), and
// its version. Asked once per program.
struct LammpsProgram {
  std::string failure;    // why `lmp -h` gave no answer (it did not end in time, granstack was stopped)
  int exit_code = 0;      // of `lmp -h`
  bool banner = false;    // it printed LAMMPS's name
  bool granular = false;
  std::optional<model::LammpsVersion> version;
};

LammpsProgram probe(const std::string& program) {
  static std::mutex mutex;
  static std::map<std::string, LammpsProgram> known;
  const std::lock_guard lock(mutex);
  if (const auto it = known.find(program); it != known.end()) return it->second;
  const auto help = fs::temp_directory_path() / fmt::format("granstack-lmp-help-{}", ::getpid());
  os::StartOptions start;
  start.output = help;
  const auto seconds = os::probe_seconds();
  const auto exit = os::run_open_mpi_program({program, "-h"}, start, nullptr, seconds);
  LammpsProgram p;
  if (exit.timed_out || exit.stopped) {
    p.failure = exit.stopped ? "was stopped with granstack, asked to stop"
                             : fmt::format("did not end within {:g} s (it was killed; GRANSTACK_PROBE_SECONDS sets the "
                                           "wait)", seconds);
    std::error_code ec;
    fs::remove(help, ec);
    return p;  // not kept: the next run asks again
  }
  p.exit_code = exit.ok() ? 0 : exit.signal != 0 ? 128 + exit.signal : exit.code;
  if (exit.ok()) {
    std::string text;
    try {
      text = formats::read_file(help);
    } catch (const std::exception&) {
    }
    p.banner = text.find(model::kLammpsBanner) != std::string::npos;
    p.version = model::parse_lammps_version(text);
    std::istringstream in(text);
    std::string line;
    bool pair_styles = false;
    while (std::getline(in, line)) {
      if (line.find("* Pair styles:") != std::string::npos) pair_styles = true;
      else if (pair_styles && line.rfind("* ", 0) == 0) break;  // the next section
      if (pair_styles && (" " + line + " ").find(" granular ") != std::string::npos) p.granular = true;
    }
  }
  std::error_code ec;
  fs::remove(help, ec);
  return known[program] = p;
}

// The rules of the LAMMPS `program` (its version's), or why granstack cannot map onto it.
const model::LammpsRules* rules_of(const std::string& program, const std::string& flag_value, std::string& why) {
  const auto p = probe(program);
  if (!p.failure.empty()) {
    why = fmt::format("'{} -h', asked which LAMMPS it is, {}; install Debian's 'lammps', or pass --lammps with the LAMMPS "
                      "executable",
                      flag_value, p.failure);
    return nullptr;
  }
  if (p.exit_code != 0 || !p.banner) {
    why = fmt::format("{} is not a LAMMPS: '{} -h' {}; install Debian's 'lammps', or pass --lammps with the LAMMPS "
                      "executable",
                      program, flag_value,
                      p.exit_code != 0 ? fmt::format("ended with exit status {}", p.exit_code)
                                       : fmt::format("does not print LAMMPS's banner ({})", model::kLammpsBanner));
    return nullptr;
  }
  if (!p.granular) {
    why = fmt::format("LAMMPS ({}) has no pair style 'granular' ('{} -h' does not list it): it was built without "
                      "the GRANULAR package; install Debian's 'lammps', or pass --lammps with a "
                      "LAMMPS that has it",
                      program, flag_value);
    return nullptr;
  }
  if (!p.version) {
    why = fmt::format("LAMMPS ({}) does not say its version ('{} -h' has no line 'Large-scale Atomic/Molecular "
                      "Massively Parallel Simulator - DATE'); granstack maps the spec onto LAMMPS's models only for "
                      "versions whose rules it knows: {}",
                      program, flag_value, model::known_lammps_versions());
    return nullptr;
  }
  const auto* rules = model::lammps_rules_for(*p.version);
  if (rules == nullptr) {
    why = fmt::format("LAMMPS ({}) is version '{}', whose granular rules granstack does not know (how its walls form "
                      "E* and which damping it has changed between versions: docs/explanation/lammps.md); the versions "
                      "it maps onto: {}. Pass --lammps with one of those",
                      program, p.version->text, model::known_lammps_versions());
  }
  return rules;
}

// The case's deck, from the template the options name (a user's, or templates/in.lammps.tmpl), for
// the LAMMPS of the family `rules`, its lines held to the case (deck_refusal).
constexpr const char* kOwnTemplate = "templates/in.lammps.tmpl";

// The deck granstack's own template gives the case on LAMMPS: what a deck and its run are held to.
std::string reference_deck(const formats::Case& c, const model::LammpsRules& rules) {
  return generator::lammps_deck(c.stack(), c.resolution(), c.files(), c.name(), generator::default_lammps_template(),
                                kOwnTemplate, rules);
}

// A deck from the user's template that does not run the case (deck_refusal says why).
struct DeckRefused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string render_deck(const formats::Case& c, const RunOptions& o, const model::LammpsRules& rules) {
  const auto& tmpl = o.own<LammpsOptions>().deck_template;
  if (tmpl.empty()) return reference_deck(c, rules);
  auto deck = generator::lammps_deck(c.stack(), c.resolution(), c.files(), c.name(), formats::read_file(tmpl), tmpl, rules);
  const auto name = lammps_files(c.files()).deck;
  if (const auto why = deck_refusal(c, deck, name, tmpl, reference_deck(c, rules)); !why.empty()) {
    throw DeckRefused(why);
  }
  return deck;
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
    if (c.spec().has_plate()) return "LAMMPS: " + case_refusal(Engine::lammps, c.spec());
    const auto lammps = o.program(Engine::lammps);
    if (auto why = program_unavailable("LAMMPS", lammps, "--lammps", "lammps", o); !why.empty()) return why;
    const auto program = *os::find_program(lammps);
    std::string why;
    const auto* rules = rules_of(program, lammps, why);
    if (rules == nullptr) return why;
    if (why = model::lammps_unmappable(c.spec(), *rules); !why.empty()) return "LAMMPS: " + why;
    try {
      (void)render_deck(c, o, *rules);
    } catch (const DeckRefused& e) {
      return fmt::format("LAMMPS: {}", e.what());
    } catch (const std::exception& e) {
      return fmt::format("LAMMPS: the deck cannot be rendered: {}", e.what());
    }
    return "";
  }

  EngineResult run(const formats::Case& c, const RunOptions& o, const std::function<void(long)>& on_step,
                   const std::function<void()>& on_started) const override {
    const auto files = lammps_files(c.files());
    EngineResult result;
    std::string why;
    const auto lammps = o.program(Engine::lammps);
    const auto* rules = rules_of(*os::find_program(lammps), lammps, why);  // unavailable() found them
    if (rules == nullptr) {
      result.error = why;
      return result;
    }
    try {
      formats::write_file_atomically(fs::path(c.dir()) / files.deck, render_deck(c, o, *rules));
    } catch (const std::exception& e) {
      result.error = fmt::format("LAMMPS: {} could not be written: {}", files.deck, e.what());
      return result;
    }
    result = run_program(c, o, {"LAMMPS", lammps, files, "lammps_version", {}, reference_deck(c, *rules), kOwnTemplate},
                         on_step, on_started);
    if (result.error.empty() && !result.interrupted) {
      try {
        result.error = drop_setup_rows(fs::path(c.dir()) / files.series);
      } catch (const std::exception& e) {
        result.error = e.what();
      }
    }
    result.record["lammps_deck"] = files.deck;
    result.record["lammps_rules"] = rules->name;
    const auto& tmpl = o.own<LammpsOptions>().deck_template;
    result.record["lammps_template"] = tmpl.empty() ? kOwnTemplate : tmpl;
    return result;
  }
};

void add_lammps_options(CLI::App& group, RunOptions& o) {
  group.add_option("--lammps-template", o.own<LammpsOptions>().deck_template,
                   "A template of yours for the LAMMPS deck instead of templates/in.lammps.tmpl")
      ->check(CLI::ExistingFile);
}

std::string_view lammps_refuses(const model::ContactModel& m, bool) { return model::lammps_refusal(m); }

}  // namespace

EngineRow lammps_row() {
  return {Engine::lammps,
          "lammps",
          "LAMMPS's GRANULAR package, the case's contacts mapped onto its models",
          {"--lammps", "--lammps-template", "--np", "--nodes"},
          {"--lammps", "lmp", "LAMMPS"},
          [] { return std::unique_ptr<CaseEngine>(std::make_unique<Lammps>()); },
          lammps_refuses,
          add_lammps_options,
          nullptr,
          mpi_cpus};
}

}  // namespace granstack::runner
