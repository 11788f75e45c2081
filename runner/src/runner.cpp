#include <granstack/formats/case.hpp>
#include <granstack/formats/deck.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/model/version.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/os/workers.hpp>
#include <granstack/runner/runner.hpp>

#include "engine.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>
#include <sys/statvfs.h>

namespace granstack::runner {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

void clone_case_inputs(const std::string& case_dir, const std::string& target) {
  // (An edited case makes an edited copy: the copy's run refuses it, as the case's would.)
  const auto m = formats::Case::open(case_dir).manifest();
  // Only a copy granstack made earlier is replaced; anything else in its place is the user's.
  if (const auto why = formats::why_not_replaceable(target, formats::kGenerate); !why.empty()) {
    throw formats::RefusedError(fmt::format("cannot make the copy {}: {}; move it away first", target, why));
  }
  fs::remove_all(target);
  try {
    fs::create_directories(fs::path(target) / fs::path(m.files.dump).parent_path());
    for (const auto& f : {std::string("manifest.json"), m.files.data, m.files.deck}) {
      fs::copy_file(fs::path(case_dir) / f, fs::path(target) / f);
    }
  } catch (...) {  // a full disk: no half-made copy (which, holding no manifest, would not be granstack's)
    std::error_code ec;
    fs::remove_all(target, ec);
    throw;
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

namespace {

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

// The outputs of an earlier run, moved aside until the new run has started: a run that cannot
// start leaves them, and their run.json, as they were. Each file is moved into a stash folder
// (.granstack-earlier-run) in the folder that holds it, reached by the case's own path, so a
// dumps/ that is a link to scratch space keeps its files on scratch and nothing leaves the
// folder it was in. A stash found at the start is a granstack's that was killed before its run
// began: it is put back.
class EarlierOutputs {
 public:
  static constexpr const char* kStash = ".granstack-earlier-run";

  // `files`: the engine's; `case_files`: the case's (the manifest's, LIGGGHTS's): another engine's
  // log, screen output and LAMMPS's rendered deck go too, so that no earlier run's file stands
  // beside the new record.
  EarlierOutputs(const fs::path& dir, const formats::CaseFiles& files, const formats::CaseFiles& case_files) : dir_(dir) {
    const auto lammps = formats::lammps_files(case_files);
    std::vector<std::string> names{files.series, files.log, files.screen, files.run_record};
    for (const auto& other : {case_files.log, case_files.screen, lammps.deck, lammps.log, lammps.screen}) {
      if (std::find(names.begin(), names.end(), other) == names.end() && other != case_files.deck) names.push_back(other);
    }
    // Every piece of an earlier dump (per step, per rank, compressed), and nothing else; named
    // lexically from the case (never through a resolved link).
    for (const auto& piece : formats::dump_files_matching((dir / files.dump).string())) {
      for (const char* suffix : {"", ".gz", ".zst"}) names.push_back(fs::path(piece + suffix).lexically_relative(dir).string());
    }
    for (const auto& name : names) folders_.insert(fs::path(name).parent_path());
    for (const auto& folder : folders_) put_back_stash(folder);
    for (const auto& name : names) {
      std::error_code ec;
      if (!fs::exists(fs::symlink_status(dir / name, ec))) continue;
      fs::create_directories(stash_of(name).parent_path());
      fs::rename(dir / name, stash_of(name));
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
    for (const auto& folder : folders_) fs::remove_all(dir_ / folder / kStash, ec);
    moved_.clear();
  }
  // The new run never started: its few files go and the earlier ones come back.
  void restore() {
    std::error_code ec;
    for (const auto& name : moved_) {
      fs::remove(dir_ / name, ec);
      fs::rename(stash_of(name), dir_ / name, ec);
    }
    moved_.clear();
    for (const auto& folder : folders_) fs::remove_all(dir_ / folder / kStash, ec);
  }

 private:
  // CASE/FOLDER/.granstack-earlier-run/NAME for CASE/FOLDER/NAME.
  fs::path stash_of(const std::string& name) const {
    const fs::path p(name);
    return dir_ / p.parent_path() / kStash / p.filename();
  }
  void put_back_stash(const fs::path& folder) {
    std::error_code ec;
    const auto stash = dir_ / folder / kStash;
    if (!fs::is_directory(fs::symlink_status(stash, ec))) return;
    for (const auto& entry : fs::recursive_directory_iterator(stash, ec)) {
      if (!entry.is_regular_file(ec)) continue;
      const auto back = dir_ / folder / entry.path().lexically_relative(stash);
      fs::remove(back, ec);
      fs::create_directories(back.parent_path(), ec);
      fs::rename(entry.path(), back, ec);
    }
    fs::remove_all(stash, ec);
  }
  fs::path dir_;
  std::set<fs::path> folders_;  // the folders the outputs lie in, relative to the case
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
void write_final_record(const formats::Case& c, const json& record, RunOutcome& outcome) {
  const auto path = c.path(c.files().run_record);
  try {
    c.write_run_record(record);
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

// The regular files in a case (relative), but for reduce/, paraview/, validate/ and the stashes
// of an earlier run's outputs.
std::set<std::string> files_in_case(const fs::path& dir) {
  std::set<std::string> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator() && found.size() < 100000;
       it.increment(ec)) {
    const auto name = it->path().filename().string();
    if ((it.depth() == 0 && (name == "reduce" || name == "paraview" || name == "validate")) ||
        name == EarlierOutputs::kStash) {
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
  std::optional<formats::Case> opened;
  std::optional<os::CaseLock> lock;
  const auto engine = make_engine(o.engine);
  try {
    opened.emplace(formats::Case::open(case_dir));
    lock.emplace(opened->lock(engine->lock_holder()));
    formats::check_deck_matches_manifest(*opened);
  } catch (const std::exception& e) {
    outcome.message = e.what();
    monitor.skipped();
    return outcome;
  }
  const auto& c = *opened;
  const auto files = engine->files(c);
  const auto earlier_record = c.run_record();
  if (earlier_record.done() && !o.force) {
    outcome.status = RunStatus::skipped;
    outcome.message = "already run (run.json says done); pass --force to run it again";
    monitor.skipped();
    return outcome;
  }
  // What would stop the engine from starting is found before an earlier run's outputs are touched.
  if (const auto why = engine->unavailable(c, o); !why.empty()) {
    outcome.message = why + (earlier_record.exists() ? " (the case's earlier outputs are kept)" : "");
    monitor.skipped();
    return outcome;
  }
  json record = running_record(o);
  EarlierOutputs earlier(dir, files, c.files());
  fs::create_directories((dir / files.dump).parent_path());
  c.write_run_record(record);
  const auto started = fs::file_time_type::clock::now();
  const auto before = files_in_case(dir);

  const auto slot = monitor.start(c.name(), c.derived().steps);
  const auto on_step = [&](long step) { monitor.update(slot, step); };
  const auto on_started = [&] { earlier.discard(); };
  const auto t0 = Clock::now();
  auto result = engine->run(c, o, on_step, on_started);
  outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  monitor.finish(slot);
  engine->tidy(dir, started);
  if (!result.started && earlier.had_record()) {  // nothing ran: the case is as it was
    earlier.restore();
    outcome.status = result.interrupted ? RunStatus::interrupted : RunStatus::failed;
    outcome.message = result.interrupted ? fmt::format("stopped by signal {} before it started", os::interrupt_signal())
                                         : result.error;
    outcome.message += " (the case's earlier outputs and run.json are kept)";
    return outcome;
  }
  earlier.discard();
  auto made = files_made(dir, files, before);
  // Another engine's deck, log and screen files are the run's too (the manifest names LIGGGHTS's).
  for (const auto& [mine, case_own] : {std::pair{files.deck, c.files().deck}, std::pair{files.log, c.files().log},
                                       std::pair{files.screen, c.files().screen}}) {
    std::error_code ec;
    if (mine != case_own && fs::exists(dir / mine, ec) && std::find(made.begin(), made.end(), mine) == made.end()) {
      made.push_back(mine);
    }
  }
  if (!made.empty()) record["outputs"] = made;
  if (const auto full = disk_full(dir, files); !full.empty() && !result.interrupted) {
    result.error = result.error.empty() ? full : full + "; " + result.error;
  }

  outcome.message = result.error;
  outcome.loop_seconds = result.loop_seconds;
  outcome.particle_steps_per_second = result.particle_steps_per_second;
  outcome.status = status_of(result);
  if (result.interrupted) outcome.message = fmt::format("stopped by signal {}", os::interrupt_signal());
  record.update(result.record);
  if (outcome.status == RunStatus::done) {
    try {  // what the readers will read, so that nothing else is ever read under this case's labels
      record["digests"] = formats::run_digests(c);
    } catch (const std::exception& e) {
      outcome.status = RunStatus::failed;
      outcome.message = fmt::format("its outputs cannot be read back to record their digests: {}", e.what());
    }
  }
  record["status"] = status_word(outcome.status);
  record["finished"] = formats::utc_timestamp();
  record["wall_seconds"] = outcome.wall_seconds;
  if (!outcome.message.empty()) record["error"] = outcome.message;
  if (result.loop_seconds > 0) {
    record["loop_seconds"] = result.loop_seconds;
    record["particle_steps_per_second"] = result.particle_steps_per_second;
  }
  write_final_record(c, record, outcome);
  return outcome;
}

}  // namespace

std::vector<RunOutcome> run_cases(const std::vector<std::string>& case_dirs, const RunOptions& options) {
  std::vector<RunOutcome> outcomes(case_dirs.size());
  Monitor monitor(static_cast<int>(case_dirs.size()));
  std::atomic<bool> all_done{false};
  std::mutex reporter_mutex;
  std::condition_variable reporter_wake;
  std::mutex done_mutex;
  const int jobs = std::max(1, std::min<int>(options.jobs, static_cast<int>(case_dirs.size())));
  RunOptions each = options;
  each.jobs = jobs;  // the cases that run at the same time, as each case sees it
  const auto run_case = [&](std::size_t i) {
    if (os::interrupt_signal() != 0) {  // asked to stop: no new case starts
      outcomes[i].case_dir = case_dirs[i];
      outcomes[i].status = RunStatus::not_started;
      return;
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
  };
  std::thread reporter;
  if (options.on_progress) {
    reporter = std::thread([&] {
      std::unique_lock lock(reporter_mutex);
      while (!all_done) {
        options.on_progress(monitor.snapshot());
        reporter_wake.wait_for(lock, std::chrono::milliseconds(500), [&] { return all_done.load(); });
      }
    });
  }
  // The reporter is woken at once: the last case's end is the command's.
  const auto stop_reporter = [&] {
    {
      const std::lock_guard lock(reporter_mutex);
      all_done = true;
    }
    reporter_wake.notify_all();
    if (reporter.joinable()) reporter.join();
  };
  try {
    os::for_each(case_dirs.size(), jobs, run_case);
  } catch (...) {
    stop_reporter();
    throw;
  }
  stop_reporter();
  if (options.on_progress) options.on_progress(monitor.snapshot());
  return outcomes;
}

}  // namespace granstack::runner
