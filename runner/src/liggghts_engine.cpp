// LIGGGHTS behind the engine interface: the program (or mpirun with it) on the case's deck, its
// log followed for progress and errors.
#include "deck_check.hpp"
#include "engine.hpp"
#include "program.hpp"

#include <granstack/runner/decomposition.hpp>
#include <granstack/runner/engine_options.hpp>

#include <granstack/formats/files.hpp>
#include <granstack/formats/log.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/mpi_session.hpp>
#include <granstack/os/process.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <optional>
#include <thread>
#include <fcntl.h>
#include <unistd.h>

namespace granstack::runner {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// How long (in 50 ms steps) a LIGGGHTS that quit of a signal waits for granstack's own.
constexpr int kSignalGraceSteps = 20;

// Reads what the process has appended to its output since the last call.
class Tail {
 public:
  explicit Tail(fs::path path) : path_(std::move(path)) {}
  Tail(const Tail&) = delete;
  Tail& operator=(const Tail&) = delete;
  ~Tail() {
    if (fd_ >= 0) ::close(fd_);
  }
  // What the program wrote since the last look, line by line (the file kept open once it exists;
  // a blow-end run writes megabytes, a few hundred lines between two looks).
  void poll(formats::LogScanner& scanner) {
    if (fd_ < 0) fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) return;
    char piece[1 << 16];
    for (ssize_t n; (n = ::pread(fd_, piece, sizeof piece, static_cast<off_t>(offset_))) > 0;) {
      offset_ += static_cast<std::size_t>(n);
      partial_.append(piece, static_cast<std::size_t>(n));
    }
    std::size_t from = 0;
    for (std::size_t nl; (nl = partial_.find('\n', from)) != std::string::npos; from = nl + 1) {
      scanner.add_line(std::string_view(partial_).substr(from, nl - from));
    }
    partial_.erase(0, from);
  }
  void flush(formats::LogScanner& scanner) {
    poll(scanner);
    if (!partial_.empty()) scanner.add_line(partial_);
    partial_.clear();
  }

 private:
  fs::path path_;
  int fd_ = -1;
  std::size_t offset_ = 0;
  std::string partial_;
};

// Where the program may write (os::StartOptions::writable): the case (its dump folder too, where
// that is a link to scratch space), Open MPI's session folder (granstack's, or the user's own) and
// /dev (/dev/null, and /dev/shm for Open MPI's shared memory). A deck that writes elsewhere fails.
std::vector<fs::path> writable_folders(const fs::path& dir, const formats::CaseFiles& files, const std::string& tmpdir) {
  std::vector<fs::path> writable{fs::absolute(dir), "/dev"};
  std::error_code ec;
  const auto dumps = fs::canonical(dir / fs::path(files.dump).parent_path(), ec);
  if (!ec) writable.push_back(dumps);
  if (!tmpdir.empty()) writable.emplace_back(tmpdir);
  if (const char* own = std::getenv("OMPI_MCA_orte_tmpdir_base"); own != nullptr && own[0] != '\0') writable.emplace_back(own);
  return writable;
}

}  // namespace

std::string program_unavailable(const std::string& name, const std::string& executable, const std::string& flag,
                                const std::string& package, const RunOptions& o) {
  if (!os::find_program(executable)) {
    return executable.find('/') == std::string::npos
               ? fmt::format("{} ('{}') is not on PATH: install it with scripts/setup.sh (Debian package '{}') or "
                             "pass {} PATH",
                             name, executable, package, flag)
               : fmt::format("{} {}: not an executable file; pass the {} executable (the Debian package '{}' "
                             "installs it in /usr/bin)",
                             flag, executable, name, package);
  }
  if (o.ranks > 1 && !os::find_program(o.mpirun)) {
    return fmt::format("'{}' is not on PATH: it comes with Open MPI (Debian package 'openmpi-bin', which '{}' "
                       "installs)",
                       o.mpirun, package);
  }
  std::error_code ec;
  const auto tmp = fs::temp_directory_path(ec);
  if (ec || os::MpiSessionDir().path().empty()) {
    const char* env = std::getenv("TMPDIR");
    return fmt::format("no private directory can be made for Open MPI's session files in {}{}: set TMPDIR to a "
                       "writable directory",
                       ec ? std::string(env != nullptr ? env : "TMPDIR") : tmp.string(),
                       ec ? " (not a directory)" : " (not writable, or full)");
  }
  return "";
}

namespace {

// Whether `ranks` need mpirun's --oversubscribe: more than this machine's CPUs, unless a SLURM
// allocation holds them (its ranks may span several nodes, each with its own CPUs).
bool oversubscribed(int ranks) {
  const char* allocated = std::getenv("SLURM_NTASKS");
  if (allocated != nullptr && std::strtol(allocated, nullptr, 10) >= ranks) return false;
  return ranks > static_cast<int>(std::thread::hardware_concurrency());
}

// run.json's "decomposition": the grid granstack chose with its predicted loads, and the loads
// LIGGGHTS reported at the end of the run.
json decomposition_record(const Decomposition& d, const formats::LogScanner& log) {
  const auto loads = [](double owned_mean, double owned_max, double ghosts_mean) {
    return json{{"owned_mean", owned_mean},
                {"owned_max", owned_max},
                {"ghosts_mean", ghosts_mean},
                {"busiest_over_mean", owned_mean > 0 ? owned_max / owned_mean : 1.0},
                {"ghosts_per_owned", owned_mean > 0 ? ghosts_mean / owned_mean : 0.0}};
  };
  json r{{"grid", d.grid}, {"predicted", loads(d.owned_mean, d.owned_max, d.ghosts_mean)}};
  if (log.owned_per_rank() && log.ghosts_per_rank()) {
    auto& l = r["liggghts"] = loads(log.owned_per_rank()->mean, log.owned_per_rank()->max, log.ghosts_per_rank()->mean);
    l["owned_min"] = log.owned_per_rank()->min;
    l["ghosts_max"] = log.ghosts_per_rank()->max;
    if (log.processor_grid()) l["grid"] = *log.processor_grid();
  }
  return r;
}

}  // namespace

EngineResult run_program(const formats::Case& c, const RunOptions& o, const Program& program,
                         const std::function<void(long)>& on_step, const std::function<void()>& on_started) {
  EngineResult result;
  const fs::path dir(c.dir());
  const auto& files = program.files;
  const auto& name = program.name;
  std::vector<std::string> argv;
  const auto liggghts = os::find_program(program.executable);  // run_one checked the engine's unavailable() first
  if (!liggghts) {
    result.error = fmt::format("{} ('{}') is not an executable file", name, program.executable);
    return result;
  }
  if (o.ranks > 1) {
    argv = {o.mpirun, "-np", std::to_string(o.ranks)};
    if (::geteuid() == 0) argv.push_back("--allow-run-as-root");
    if (oversubscribed(o.ranks)) argv.push_back("--oversubscribe");
  }
  // Each rank is killed when mpirun dies, however it dies: killed outright with granstack (SIGKILL
  // reaches mpirun through its own death signal), mpirun cannot tell its ranks, and a rank waiting in
  // MPI could be left behind on a loaded machine (seen once in the suite). util-linux's setpriv
  // sets the death signal and execs the rank's program.
  if (o.ranks > 1) {
    if (const auto setpriv = os::find_program("setpriv")) argv.insert(argv.end(), {*setpriv, "--pdeathsig", "KILL", "--"});
  }
  // Unbuffered, so an MPI_Abort cannot swallow LIGGGHTS's error message (docs/liggghts.md section 9).
  const auto stdbuf = os::find_program("stdbuf");
  if (stdbuf) argv.insert(argv.end(), {*stdbuf, "-o0", "-e0"});
  // Absolute: the program starts in the case directory, where a relative path would mean something else.
  argv.insert(argv.end(), {fs::absolute(*liggghts).string(), "-in", files.deck, "-log", files.log});
  std::optional<Decomposition> decomposition;
  if (o.ranks > 1) {
    decomposition = program.grid[0] > 0 ? predict_decomposition(c, program.grid) : choose_decomposition(c, o.ranks);
    for (std::size_t d = 0; d < 3; ++d) {
      argv.insert(argv.end(), {"-var", std::string("gs_ranks_") + "xyz"[d], std::to_string(decomposition->grid[d])});
    }
  }
  result.record["command"] = argv;
  result.record["ranks"] = o.ranks;
  if (const char* nodes = std::getenv("SLURM_JOB_NODELIST"); nodes != nullptr && o.ranks > 1) {
    result.record["slurm_nodes"] = nodes;  // the allocation mpirun spread the ranks over
  }

  argv.insert(argv.end(), program.extra_arguments.begin(), program.extra_arguments.end());
  const long total_steps = c.derived().steps;
  formats::LogScanner scanner;
  int exit_code = -1;
  std::string signal_text;
  // A start that fails before LIGGGHTS prints its banner (MPI could not start) is tried again,
  // at most kStarts times in all; a failure after the banner is LIGGGHTS's own and final.
  constexpr int kStarts = 3;
  int starts = 0;
  for (; starts < kStarts; ++starts) {
    const os::MpiSessionDir tmpdir;
    os::StartOptions start;
    start.cwd = fs::absolute(dir);
    start.output = fs::absolute(dir / files.screen);
    start.extra_environment = os::mpi_environment(tmpdir.path(), o.ranks);
    start.writable = writable_folders(dir, files, tmpdir.path());
    const auto child = os::start(argv, start);
    if (child.pid < 0) {
      result.error = child.error;
      return result;
    }
    result.record["writes_confined"] = child.confined;
    scanner = formats::LogScanner();
    exit_code = -1;
    signal_text.clear();
    Tail tail(dir / files.screen);
    for (;;) {
      // Up to 0.1 s between looks at the screen file, ending as the program does.
      if (const auto end = os::poll_for(child, 0.1)) {
        exit_code = end->code;
        if (end->signal != 0) signal_text = fmt::format("killed by signal {}", end->signal);
        break;
      }
      if (os::interrupt_signal() != 0) {  // granstack is asked to stop: so is LIGGGHTS, at once
        os::kill_group(child);
        os::wait(child);
        result.interrupted = true;
        return result;
      }
      tail.poll(scanner);
      if (!result.started && !scanner.version().empty()) {
        result.started = true;
        on_started();
      }
      if (auto step = scanner.last_step()) on_step(*step);
    }
    tail.flush(scanner);
    if (!result.started && !scanner.version().empty()) {
      result.started = true;
      on_started();
    }
    const bool failed_to_start = exit_code != 0 && scanner.version().empty() && result.error.empty();
    if (!failed_to_start || starts + 1 == kStarts) break;
    result.record["failed_starts"].push_back(scanner.head());
  }
  result.record["starts"] = starts + 1;
  // A scheduler (SLURM's scancel or time limit) signals every process of a job at once, so
  // LIGGGHTS may end of the same signal before granstack's own handler has run: give that
  // signal a moment to arrive, and call the run interrupted, not failed.
  if (scanner.stopped_by_signal() || !signal_text.empty()) {
    for (int i = 0; i < kSignalGraceSteps && os::interrupt_signal() == 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (os::interrupt_signal() != 0) {
      result.interrupted = true;
      return result;
    }
  }

  const auto& loop = scanner.loop_time();
  if (result.error.empty()) {
    if (!scanner.errors().empty()) {
      result.error = scanner.errors().front();
    } else if (scanner.stopped_by_signal()) {
      result.error = name + " was sent SIGINT or SIGTERM directly and quit before the end of the run (its forced "
                            "restart file is removed); to stop granstack, signal granstack itself; run the case again";
    } else if (scanner.lost_atoms()) {
      result.error = name + " lost atoms (see " + files.screen + ")";
    } else if (!signal_text.empty()) {
      result.error = name + " was " + signal_text;
    } else if (exit_code != 0) {
      const bool started = !scanner.version().empty();
      const auto quote = started ? scanner.tail() : scanner.head();
      result.error = fmt::format("{} exited with code {}{}; {} ({}){}", name, exit_code,
                                 started ? "" : " before it started (could MPI not start?)",
                                 quote.empty() ? "it printed nothing" : started ? "its last lines" : "its first lines",
                                 files.screen, quote.empty() ? "" : ":");
      for (const auto& line : quote) result.error += "\n    " + line;
    } else if (auto held = hold_run(c, files, program.reference, program.reference_source, result.record); !held.empty()) {
      result.error = std::move(held);  // what ran, from the log: also a deck that ran more or fewer steps
    } else if (!loop || !(c.spec().stop == model::StopRule::blow_end ? loop->steps <= total_steps : loop->steps == total_steps)) {
      result.error = !loop || loop->steps < total_steps
                         ? fmt::format("{} ended without finishing the run of {} steps ({} ran; see {})", name,
                                       total_steps, loop ? std::to_string(loop->steps) : "none", files.screen)
                         : fmt::format("{} ran {} steps, more than the case's {} (see {})", name, loop->steps,
                                       total_steps, files.screen);
    }
  }
  if (result.record.value("writes_confined", false) && result.error.find("Cannot open") != std::string::npos) {
    result.error += "; granstack lets the program write only inside the case (and /dev and Open MPI's session "
                    "folder): a deck that writes elsewhere fails at that command, before it writes anything there";
  }
  result.record["exit_code"] = exit_code;
  result.record[program.version_key] = scanner.version();
  if (!scanner.warnings().empty()) result.record["warnings"] = scanner.warnings();
  if (loop) {
    result.loop_seconds = loop->seconds;
    result.particle_steps_per_second =
        loop->seconds > 0 ? static_cast<double>(loop->atoms) * static_cast<double>(loop->steps) / loop->seconds : 0.0;
    result.record["steps"] = loop->steps;
    result.record["atoms"] = loop->atoms;
    result.record["procs"] = loop->procs;
  }
  if (decomposition) result.record["decomposition"] = decomposition_record(*decomposition, scanner);
  return result;
}

namespace {

// LIGGGHTS writes restart_forced_liggghts_STEP.data when a signal reaches it directly; such a
// file made during this run is debris of the stop, never a result.
void remove_forced_restarts(const fs::path& dir, fs::file_time_type since) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const auto name = entry.path().filename().string();
    if (name.rfind("restart_forced_liggghts_", 0) == 0 && entry.is_regular_file(ec) &&
        entry.last_write_time(ec) >= since) {
      fs::remove(entry.path(), ec);
    }
  }
}

// The template generate rendered the case's deck from, as its command line names it.
std::string template_of(const formats::Manifest& m) {
  for (std::size_t i = 0; i < m.command_line.size(); ++i) {
    const auto& a = m.command_line[i];
    if (a == "--template" && i + 1 < m.command_line.size()) return m.command_line[i + 1];
    if (a.rfind("--template=", 0) == 0) return a.substr(11);
  }
  return "a template of yours";
}

class Liggghts final : public CaseEngine {
 public:
  std::string lock_holder() const override { return "granstack run"; }
  std::string unavailable(const formats::Case& c, const RunOptions& o) const override {
    if (const auto why = case_refusal(Engine::liggghts, c.spec()); !why.empty()) {
      return "LIGGGHTS: " + std::string(why);
    }
    if (const auto why = program_unavailable("LIGGGHTS", o.program(Engine::liggghts), "--liggghts", "liggghts", o);
        !why.empty()) {
      return why;
    }
    const auto deck = c.files().deck;
    return deck_refusal(c, formats::read_file(c.path(deck)), deck, template_of(c.manifest()),
                        generator::default_deck(c.manifest()));
  }
  EngineResult run(const formats::Case& c, const RunOptions& o, const std::function<void(long)>& on_step,
                   const std::function<void()>& on_started) const override {
    return run_program(c, o,
                       {"LIGGGHTS", o.program(Engine::liggghts), c.files(), "liggghts_version", {},
                        generator::default_deck(c.manifest()), "templates/in.granstack.tmpl", o.own<LiggghtsOptions>().grid},
                       on_step, on_started);
  }
  void tidy(const fs::path& dir, fs::file_time_type since) const override { remove_forced_restarts(dir, since); }
};

// "4,4,1" or "4x4x1": ranks along x, y and z.
std::optional<std::array<int, 3>> parse_grid(const std::string& text) {
  std::array<int, 3> g{};
  std::size_t at = 0;
  for (std::size_t d = 0; d < 3; ++d) {
    std::size_t used = 0;
    try {
      g[d] = std::stoi(text.substr(at), &used);
    } catch (const std::exception&) {
      return std::nullopt;
    }
    at += used;
    if (g[d] < 1 || (d < 2 && (at >= text.size() || (text[at] != ',' && text[at] != 'x')))) return std::nullopt;
    ++at;
  }
  if (at != text.size() + 1) return std::nullopt;
  return g;
}

void add_liggghts_options(CLI::App& group, RunOptions& o) {
  group.add_option("--grid", o.own<LiggghtsOptions>().grid_text,
                   "LIGGGHTS's MPI processor grid, ranks along x,y,z (product --np), e.g. 4,4,1; by default the grid "
                   "whose busiest rank holds the fewest spheres, owned and ghost (run.json's \"decomposition\")");
}

std::string check_liggghts_options(RunOptions& o) {
  auto& own = o.own<LiggghtsOptions>();
  if (own.grid_text.empty()) return "";
  const auto grid = parse_grid(own.grid_text);
  if (!grid || (*grid)[0] * (*grid)[1] * (*grid)[2] != o.ranks) {
    return fmt::format("--grid {}: give three whole numbers of ranks along x, y and z whose product is --np ({}), e.g. "
                       "--grid 4,4,1 with --np 16",
                       own.grid_text, o.ranks);
  }
  own.grid = *grid;
  return "";
}

std::string_view liggghts_refuses(const model::ContactModel& m, bool) { return model::liggghts_refusal(m); }

}  // namespace

EngineRow::Cpus mpi_cpus(const RunOptions& o) { return {o.ranks, "MPI ranks", "--np"}; }

EngineRow liggghts_row() {
  return {Engine::liggghts,
          "liggghts",
          "the real DEM code",
          {"--liggghts", "--np", "--grid", "--nodes"},
          {"--liggghts", "liggghts", "LIGGGHTS"},
          [] { return std::unique_ptr<CaseEngine>(std::make_unique<Liggghts>()); },
          liggghts_refuses,
          add_liggghts_options,
          check_liggghts_options,
          mpi_cpus,
          true};  // the plate as a mesh moved with an atom of its mass (model::plate_body)
}

}  // namespace granstack::runner
