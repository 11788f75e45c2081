#include <granstack/formats/deck.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/log.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/version.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>
#include <sys/statvfs.h>
#include <unistd.h>

namespace granstack::runner {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

void clone_case_inputs(const std::string& case_dir, const std::string& target) {
  // (An edited case makes an edited copy: the copy's run refuses it, as the case's would.)
  const auto m = formats::read_manifest(case_dir);
  // Only a copy granstack made earlier is replaced; anything else in its place is the user's.
  if (const auto why = formats::why_not_replaceable(target); !why.empty()) {
    throw formats::RefusedError(fmt::format("cannot make the copy {}: {}; move it away first", target, why));
  }
  fs::remove_all(target);
  fs::create_directories(fs::path(target) / fs::path(m.files.dump).parent_path());
  for (const auto& f : {std::string("manifest.json"), m.files.data, m.files.deck}) {
    fs::copy_file(fs::path(case_dir) / f, fs::path(target) / f);
  }
}

std::string copy_dir(const std::string& case_dir, Engine engine) {
  return (fs::path(case_dir) / "validate" / to_string(engine)).string();
}

std::vector<RunOutcome> run_copies(const std::vector<std::string>& case_dirs, Engine engine, RunOptions options) {
  std::vector<std::string> copies;
  for (const auto& d : case_dirs) {
    copies.push_back(copy_dir(d, engine));
    clone_case_inputs(d, copies.back());
  }
  options.engine = engine;
  options.force = true;
  return run_cases(copies, options);
}

std::string recorded_status(const std::string& case_dir) {
  std::ifstream in(fs::path(case_dir) / "run.json");
  if (!in) return "";
  try {
    return json::parse(in).value("status", "");
  } catch (const json::exception&) {
    return "";
  }
}

namespace {

// How long (in 50 ms steps) a LIGGGHTS that quit of a signal waits for granstack's own.
constexpr int kSignalGraceSteps = 20;

void write_record(const fs::path& path, const json& record) {
  formats::write_file_atomically(path, record.dump(2) + "\n");
}

class Monitor {
 public:
  explicit Monitor(int total) { snapshot_.total = total; }
  std::size_t start(const std::string& name, long total_steps) {
    std::lock_guard lock(mutex_);
    slots_.push_back({name, 0, total_steps, 0.0});
    starts_.push_back(Clock::now());
    return slots_.size() - 1;
  }
  void update(std::size_t slot, long step) {
    std::lock_guard lock(mutex_);
    slots_[slot].step = step;
  }
  void finish(std::size_t slot) {
    std::lock_guard lock(mutex_);
    slots_[slot].total_steps = -1;  // marks the slot finished
    ++snapshot_.finished;
  }
  void skipped() {
    std::lock_guard lock(mutex_);
    ++snapshot_.finished;
  }
  ProgressSnapshot snapshot() {
    std::lock_guard lock(mutex_);
    ProgressSnapshot s = snapshot_;
    const auto now = Clock::now();
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (slots_[i].total_steps < 0) continue;
      auto p = slots_[i];
      p.elapsed = std::chrono::duration<double>(now - starts_[i]).count();
      s.running.push_back(p);
    }
    return s;
  }

 private:
  std::mutex mutex_;
  ProgressSnapshot snapshot_;
  std::vector<CaseProgress> slots_;
  std::vector<Clock::time_point> starts_;
};

// A private directory for Open MPI's session files, removed with everything in it at the end.
// Open MPI processes started at the same time share /tmp/ompi.HOST.UID by default, and one that
// ends can remove it while another is still creating its own part: the second then fails in
// orte_init and exits with code 1 before LIGGGHTS prints anything (open-mpi/ompi#3818). A
// directory per run removes the race.
class PrivateTmpDir {
 public:
  PrivateTmpDir() {
    auto pattern = (fs::temp_directory_path() / "granstack-mpi-XXXXXX").string();
    if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
  }
  ~PrivateTmpDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  PrivateTmpDir(const PrivateTmpDir&) = delete;
  PrivateTmpDir& operator=(const PrivateTmpDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Environment added for one LIGGGHTS start; a variable the user has set is left as it is.
std::vector<std::string> mpi_environment(const std::string& tmpdir, int ranks) {
  std::vector<std::string> env;
  const auto add = [&](const char* name, const std::string& value) {
    if (std::getenv(name) == nullptr && !value.empty()) env.push_back(std::string(name) + "=" + value);
  };
  add("OMPI_MCA_orte_tmpdir_base", tmpdir);
  // A single rank started without mpirun need not launch Open MPI's daemon (0.1 s per start).
  if (ranks == 1) add("OMPI_MCA_ess_singleton_isolated", "1");
  return env;
}

// Reads what the process has appended to its output since the last call.
class Tail {
 public:
  explicit Tail(fs::path path) : path_(std::move(path)) {}
  void poll(formats::LogScanner& scanner) {
    std::ifstream in(path_, std::ios::binary);
    if (!in) return;
    in.seekg(static_cast<std::streamoff>(offset_));
    std::string chunk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    offset_ += chunk.size();
    partial_ += chunk;
    std::size_t nl;
    while ((nl = partial_.find('\n')) != std::string::npos) {
      scanner.add_line(std::string_view(partial_).substr(0, nl));
      partial_.erase(0, nl + 1);
    }
  }
  void flush(formats::LogScanner& scanner) {
    poll(scanner);
    if (!partial_.empty()) scanner.add_line(partial_);
    partial_.clear();
  }

 private:
  fs::path path_;
  std::size_t offset_ = 0;
  std::string partial_;
};

// What one engine run produced: an error message (empty on success) and the figures for run.json.
struct EngineResult {
  std::string error;
  nlohmann::json record = nlohmann::json::object();
  bool interrupted = false;  // stopped by a signal to granstack
  bool started = false;      // the engine began the run (LIGGGHTS printed its banner; refsim stepped)
  double loop_seconds = 0.0;
  double particle_steps_per_second = 0.0;
};

// Why LIGGGHTS cannot be started at all (its program, mpirun, a temporary directory for Open
// MPI), or "": checked before anything of an earlier run is touched.
std::string liggghts_unavailable(const RunOptions& o) {
  if (!os::find_program(o.liggghts)) {
    return o.liggghts.find('/') == std::string::npos
               ? fmt::format("LIGGGHTS ('{}') is not on PATH: install it with scripts/setup.sh (Debian package "
                             "'liggghts') or pass --liggghts PATH",
                             o.liggghts)
               : fmt::format("--liggghts {}: not an executable file; pass the LIGGGHTS executable (the Debian "
                             "package 'liggghts' installs /usr/bin/liggghts)",
                             o.liggghts);
  }
  if (o.ranks > 1 && !os::find_program(o.mpirun)) {
    return fmt::format("'{}' is not on PATH: it comes with the Debian package 'liggghts' (Open MPI)", o.mpirun);
  }
  std::error_code ec;
  const auto tmp = fs::temp_directory_path(ec);
  if (ec || PrivateTmpDir().path().empty()) {
    const char* env = std::getenv("TMPDIR");
    return fmt::format("no private directory can be made for Open MPI's session files in {}{}: set TMPDIR to a "
                       "writable directory",
                       ec ? std::string(env != nullptr ? env : "TMPDIR") : tmp.string(),
                       ec ? " (not a directory)" : " (not writable, or full)");
  }
  return "";
}

EngineResult run_liggghts(const fs::path& dir, const formats::Manifest& manifest, const RunOptions& o,
                          const std::function<void(long)>& on_step, const std::function<void()>& on_started) {
  EngineResult result;
  const auto& files = manifest.files;
  std::vector<std::string> argv;
  const auto liggghts = os::find_program(o.liggghts);  // run_one checked liggghts_unavailable() first
  if (!liggghts) {
    result.error = liggghts_unavailable(o);
    return result;
  }
  if (o.ranks > 1) {
    argv = {o.mpirun, "-np", std::to_string(o.ranks)};
    if (::geteuid() == 0) argv.push_back("--allow-run-as-root");
    if (o.ranks > static_cast<int>(std::thread::hardware_concurrency())) argv.push_back("--oversubscribe");
  }
  // Unbuffered, so an MPI_Abort cannot swallow LIGGGHTS's error message (docs/liggghts.md section 9).
  const auto stdbuf = os::find_program("stdbuf");
  if (stdbuf) argv.insert(argv.end(), {*stdbuf, "-o0", "-e0"});
  // Absolute: the program starts in the case directory, where a relative path would mean something else.
  argv.insert(argv.end(), {fs::absolute(*liggghts).string(), "-in", files.deck, "-log", files.log});
  result.record["command"] = argv;
  result.record["ranks"] = o.ranks;

  const long total_steps = manifest.derived.value("steps", 0L);
  formats::LogScanner scanner;
  int exit_code = -1;
  std::string signal_text;
  // A start that fails before LIGGGHTS prints its banner (MPI could not start) is tried again,
  // at most kStarts times in all; a failure after the banner is LIGGGHTS's own and final.
  constexpr int kStarts = 3;
  int starts = 0;
  for (; starts < kStarts; ++starts) {
    const PrivateTmpDir tmpdir;
    os::StartOptions start;
    start.cwd = fs::absolute(dir);
    start.output = fs::absolute(dir / files.screen);
    start.extra_environment = mpi_environment(tmpdir.path(), o.ranks);
    const auto child = os::start(argv, start);
    if (child.pid < 0) {
      result.error = child.error;
      return result;
    }
    scanner = formats::LogScanner();
    exit_code = -1;
    signal_text.clear();
    Tail tail(dir / files.screen);
    for (;;) {
      if (const auto end = os::poll(child)) {
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
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
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
      result.error = "LIGGGHTS was sent SIGINT or SIGTERM directly and quit before the end of the run (its forced "
                     "restart file is removed); to stop granstack, signal granstack itself; run the case again";
    } else if (scanner.lost_atoms()) {
      result.error = "LIGGGHTS lost atoms (see " + files.screen + ")";
    } else if (!signal_text.empty()) {
      result.error = "LIGGGHTS was " + signal_text;
    } else if (exit_code != 0) {
      const bool started = !scanner.version().empty();
      const auto quote = started ? scanner.tail() : scanner.head();
      result.error = fmt::format("LIGGGHTS exited with code {}{}; {} ({}){}", exit_code,
                                 started ? "" : " before it started (could MPI not start?)",
                                 quote.empty() ? "it printed nothing" : started ? "its last lines" : "its first lines",
                                 files.screen, quote.empty() ? "" : ":");
      for (const auto& line : quote) result.error += "\n    " + line;
    } else if (!loop || loop->steps != total_steps) {
      result.error = fmt::format("LIGGGHTS ended without finishing the run of {} steps (see {})", total_steps,
                                 files.screen);
    }
  }
  result.record["exit_code"] = exit_code;
  result.record["liggghts_version"] = scanner.version();
  if (!scanner.warnings().empty()) result.record["warnings"] = scanner.warnings();
  if (loop) {
    result.loop_seconds = loop->seconds;
    result.particle_steps_per_second =
        loop->seconds > 0 ? static_cast<double>(loop->atoms) * static_cast<double>(loop->steps) / loop->seconds : 0.0;
    result.record["steps"] = loop->steps;
    result.record["atoms"] = loop->atoms;
    result.record["procs"] = loop->procs;
  }
  return result;
}

// Thrown from refsim's progress callback to end its loop when granstack is asked to stop.
struct Interrupted {};

// refsim takes its physics from the manifest, LIGGGHTS from the deck: they must say the same.
std::string refsim_unavailable(const fs::path& dir, const formats::Manifest& manifest) {
  if (generator::has_default_deck(dir.string(), manifest)) return "";
  return fmt::format("refsim: {} is not the deck granstack's own template gives for this case (it was rendered from "
                     "a --template of yours), so refsim cannot be sure to run the same physics; run it with LIGGGHTS, "
                     "or generate the case without --template",
                     (dir / manifest.files.deck).string());
}

EngineResult run_refsim(const fs::path& dir, const RunOptions& o,
                        const std::function<void(long)>& on_step, const std::function<void()>& on_started) {
  EngineResult result;
  try {
    refsim::RunOptions ro;
    ro.threads = o.threads;
    ro.kernel = o.kernel;
    // The outputs on a thread of their own where a CPU is left over by every case's threads.
    ro.write_behind = os::usable_cpus() >= (o.threads + 1) * std::max(1, o.jobs);
    ro.on_progress = [&](long step, long) {
      if (!result.started) {
        result.started = true;
        on_started();
      }
      on_step(step);
      if (os::interrupt_signal() != 0) throw Interrupted();
    };
    const auto stats = refsim::run_case(dir.string(), ro);
    result.started = true;
    result.loop_seconds = stats.loop_seconds;
    result.particle_steps_per_second = stats.particle_steps_per_second;
    result.record["steps"] = stats.steps;
    result.record["atoms"] = stats.atoms;
    result.record["threads"] = o.threads;
    result.record["kernel"] = stats.kernel;
    result.record["write_behind"] = stats.write_behind;
    result.record["neighbor_builds"] = stats.neighbor_builds;
  } catch (const Interrupted&) {
    result.interrupted = true;
  } catch (const std::exception& e) {
    result.error = std::string("refsim: ") + e.what();
  }
  return result;
}

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

// The outputs of an earlier run, moved aside into CASE/.granstack-earlier-run until the new run
// has started: a run that cannot start leaves them, and their run.json, as they were. A stash
// found at the start is a granstack's that was killed before its run began: it is put back.
class EarlierOutputs {
 public:
  static constexpr const char* kStash = ".granstack-earlier-run";

  EarlierOutputs(const fs::path& dir, const formats::CaseFiles& files) : dir_(dir), stash_(dir / kStash) {
    put_back_stash();
    std::vector<std::string> names{files.series, files.log, files.screen, files.run_record};
    // Every piece of an earlier dump (per step, per rank, compressed), and nothing else.
    for (const auto& piece : formats::dump_files_matching((dir / files.dump).string())) {
      for (const char* suffix : {"", ".gz", ".zst"}) names.push_back(fs::relative(piece + suffix, dir).string());
    }
    for (const auto& name : names) {
      std::error_code ec;
      if (!fs::exists(fs::symlink_status(dir / name, ec))) continue;
      fs::create_directories((stash_ / name).parent_path());
      fs::rename(dir / name, stash_ / name);
      moved_.push_back(name);
      had_record_ = had_record_ || name == files.run_record;
    }
  }
  ~EarlierOutputs() {
    if (!moved_.empty()) restore();
  }
  EarlierOutputs(const EarlierOutputs&) = delete;
  EarlierOutputs& operator=(const EarlierOutputs&) = delete;

  bool had_record() const { return had_record_; }
  // The new run has started: the earlier outputs are gone for good.
  void discard() {
    std::error_code ec;
    fs::remove_all(stash_, ec);
    moved_.clear();
  }
  // The new run never started: its few files go and the earlier ones come back.
  void restore() {
    std::error_code ec;
    for (const auto& name : moved_) {
      fs::remove(dir_ / name, ec);
      fs::rename(stash_ / name, dir_ / name, ec);
    }
    moved_.clear();
    fs::remove_all(stash_, ec);
  }

 private:
  void put_back_stash() {
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(stash_, ec))) return;
    for (const auto& entry : fs::recursive_directory_iterator(stash_, ec)) {
      if (!entry.is_regular_file(ec)) continue;
      const auto name = fs::relative(entry.path(), stash_, ec);
      fs::remove(dir_ / name, ec);
      fs::create_directories((dir_ / name).parent_path(), ec);
      fs::rename(entry.path(), dir_ / name, ec);
    }
    fs::remove_all(stash_, ec);
  }
  fs::path dir_, stash_;
  std::vector<std::string> moved_;
  bool had_record_ = false;
};

// Where the disk holding the case has (almost) no room left after a run, why its outputs cannot be
// trusted, naming the largest of them (LIGGGHTS does not check its writes: a full disk cuts its
// dumps short without an error); else "".
std::string disk_full(const fs::path& dir, const formats::CaseFiles& files) {
  struct statvfs st {};
  constexpr double kFullBytes = 64.0 * 1024;
  if (::statvfs(dir.c_str(), &st) != 0) return "";
  const double free_bytes = static_cast<double>(st.f_bfree) * static_cast<double>(st.f_frsize);
  if (free_bytes >= kFullBytes) return "";
  std::string largest;
  std::uintmax_t size = 0;
  std::vector<std::string> outputs = formats::dump_files_matching((dir / files.dump).string());
  for (const auto& f : {files.series, files.log, files.screen}) outputs.push_back((dir / f).string());
  for (const auto& f : outputs) {
    std::error_code ec;
    const auto n = fs::file_size(f, ec);
    if (!ec && n >= size) {
      size = n;
      largest = f;
    }
  }
  return fmt::format("the disk holding {} is full ({:.0f} bytes left): {} ({} bytes) and the run's other outputs may "
                     "be cut short; free some space (or generate the case elsewhere) and run it again",
                     dir.string(), free_bytes, largest.empty() ? "its dump" : largest, size);
}

// Writes the run's final record; on a full disk, where the atomic write has no room for its
// temporary file, in place over the running record (whose blocks that frees).
void write_final_record(const fs::path& path, const json& record, RunOutcome& outcome) {
  try {
    write_record(path, record);
    return;
  } catch (const std::exception& first) {
    std::error_code ec;
    fs::remove(path.string() + ".tmp", ec);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << record.dump(2) << "\n";
    out.close();
    if (out) return;
    outcome.status = RunStatus::failed;
    outcome.message += fmt::format("{}{} (its run record) could not be written: {}", outcome.message.empty() ? "" : "; ",
                                   path.string(), first.what());
  }
}

// The regular files in a case (relative), but for reduce/, paraview/, validate/ and the stash of
// an earlier run's outputs.
std::set<std::string> files_in_case(const fs::path& dir) {
  std::set<std::string> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator() && found.size() < 100000;
       it.increment(ec)) {
    const auto name = it->path().filename().string();
    if (it.depth() == 0 &&
        (name == "reduce" || name == "paraview" || name == "validate" || name == EarlierOutputs::kStash)) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file(ec)) found.insert(fs::relative(it->path(), dir, ec).string());
  }
  return found;
}

// Files the run made in the case beyond granstack's own (a user's template may have LIGGGHTS
// write more, e.g. a fix ave/time file): new since `before`, recorded in run.json so that
// generate --force knows them as the run's, never a user's. At most 1000.
std::vector<std::string> files_made(const fs::path& dir, const formats::CaseFiles& files, const std::set<std::string>& before) {
  std::set<std::string> known{files.series, files.log, files.screen, files.run_record};
  for (const auto& piece : formats::dump_files_matching((dir / files.dump).string())) {
    known.insert(fs::path(piece).lexically_relative(dir).string());
  }
  std::vector<std::string> made;
  for (const auto& f : files_in_case(dir)) {
    if (made.size() < 1000 && before.count(f) == 0 && known.count(f) == 0) made.push_back(f);
  }
  return made;
}

json running_record(const RunOptions& o) {
  return {{"status", "running"},
          {"engine", to_string(o.engine)},
          {"started", formats::utc_timestamp()},
          {"host_threads", std::thread::hardware_concurrency()},
          {"granstack_version", std::string(version())}};
}

RunStatus status_of(const EngineResult& result) {
  return result.interrupted ? RunStatus::interrupted : result.error.empty() ? RunStatus::done : RunStatus::failed;
}

const char* status_word(RunStatus s) {
  return s == RunStatus::done ? "done" : s == RunStatus::interrupted ? "interrupted" : "failed";
}

RunOutcome run_one(const std::string& case_dir, const RunOptions& o, Monitor& monitor) {
  RunOutcome outcome;
  outcome.case_dir = case_dir;
  const fs::path dir(case_dir);
  formats::Manifest manifest;
  std::optional<os::CaseLock> lock;
  try {
    manifest = formats::read_manifest(case_dir);
    lock.emplace(dir, o.engine == Engine::refsim ? "granstack run --engine refsim" : "granstack run");
    formats::check_deck_matches_manifest(case_dir, manifest);
  } catch (const std::exception& e) {
    outcome.message = e.what();
    monitor.skipped();
    return outcome;
  }
  const auto& files = manifest.files;
  if (recorded_status(case_dir) == "done" && !o.force) {
    outcome.status = RunStatus::skipped;
    outcome.message = "already run (run.json says done); pass --force to run it again";
    monitor.skipped();
    return outcome;
  }
  const bool refsim_engine = o.engine == Engine::refsim;
  // What would stop the engine from starting is found before an earlier run's outputs are touched.
  if (const auto why = refsim_engine ? refsim_unavailable(dir, manifest) : liggghts_unavailable(o); !why.empty()) {
    outcome.message = why + (recorded_status(case_dir).empty() ? "" : " (the case's earlier outputs are kept)");
    monitor.skipped();
    return outcome;
  }
  json record = running_record(o);
  EarlierOutputs earlier(dir, files);
  fs::create_directories((dir / files.dump).parent_path());
  write_record(dir / files.run_record, record);
  const auto started = fs::file_time_type::clock::now();
  const auto before = files_in_case(dir);

  const auto slot = monitor.start(manifest.case_name, manifest.derived.value("steps", 0L));
  const auto on_step = [&](long step) { monitor.update(slot, step); };
  const auto on_started = [&] { earlier.discard(); };
  const auto t0 = Clock::now();
  auto result = refsim_engine ? run_refsim(dir, o, on_step, on_started)
                              : run_liggghts(dir, manifest, o, on_step, on_started);
  outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  monitor.finish(slot);
  if (!refsim_engine) remove_forced_restarts(dir, started);
  if (!result.started && earlier.had_record()) {  // nothing ran: the case is as it was
    earlier.restore();
    outcome.status = result.interrupted ? RunStatus::interrupted : RunStatus::failed;
    outcome.message = result.interrupted ? fmt::format("stopped by signal {} before it started", os::interrupt_signal())
                                         : result.error;
    outcome.message += " (the case's earlier outputs and run.json are kept)";
    return outcome;
  }
  earlier.discard();
  if (const auto made = files_made(dir, files, before); !made.empty()) record["outputs"] = made;
  if (const auto full = disk_full(dir, files); !full.empty() && !result.interrupted) {
    result.error = result.error.empty() ? full : full + "; " + result.error;
  }

  outcome.message = result.error;
  outcome.loop_seconds = result.loop_seconds;
  outcome.particle_steps_per_second = result.particle_steps_per_second;
  outcome.status = status_of(result);
  if (result.interrupted) outcome.message = fmt::format("stopped by signal {}", os::interrupt_signal());
  record.update(result.record);
  record["status"] = status_word(outcome.status);
  record["finished"] = formats::utc_timestamp();
  record["wall_seconds"] = outcome.wall_seconds;
  if (!outcome.message.empty()) record["error"] = outcome.message;
  if (result.loop_seconds > 0) {
    record["loop_seconds"] = result.loop_seconds;
    record["particle_steps_per_second"] = result.particle_steps_per_second;
  }
  write_final_record(dir / files.run_record, record, outcome);
  return outcome;
}

}  // namespace

std::vector<RunOutcome> run_cases(const std::vector<std::string>& case_dirs, const RunOptions& options) {
  std::vector<RunOutcome> outcomes(case_dirs.size());
  Monitor monitor(static_cast<int>(case_dirs.size()));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> all_done{false};
  std::mutex done_mutex;
  const int jobs = std::max(1, std::min<int>(options.jobs, static_cast<int>(case_dirs.size())));
  RunOptions each = options;
  each.jobs = jobs;  // the cases that run at the same time, as each case sees it
  auto worker = [&] {
    for (std::size_t i = next++; i < case_dirs.size(); i = next++) {
      if (os::interrupt_signal() != 0) {  // asked to stop: no new case starts
        outcomes[i].case_dir = case_dirs[i];
        outcomes[i].status = RunStatus::not_started;
        continue;
      }
      try {
        outcomes[i] = run_one(case_dirs[i], each, monitor);
      } catch (const std::exception& e) {  // e.g. a disk error: this case fails, the others go on
        outcomes[i].case_dir = case_dirs[i];
        outcomes[i].status = RunStatus::failed;
        outcomes[i].message = e.what();
      }
      if (options.on_case_done) {
        const std::lock_guard lock(done_mutex);
        options.on_case_done(outcomes[i]);
      }
    }
  };
  std::thread reporter;
  if (options.on_progress) {
    reporter = std::thread([&] {
      while (!all_done) {
        options.on_progress(monitor.snapshot());
        for (int i = 0; i < 5 && !all_done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
    });
  }
  std::vector<std::thread> workers;
  for (int j = 1; j < jobs; ++j) workers.emplace_back(worker);
  worker();
  for (auto& w : workers) w.join();
  all_done = true;
  if (reporter.joinable()) reporter.join();
  if (options.on_progress) options.on_progress(monitor.snapshot());
  return outcomes;
}

}  // namespace granstack::runner
