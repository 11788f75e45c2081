#include "analyses.hpp"

#include <granstack/formats/case.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/runner/engine_options.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/runner/runner.hpp>
#include <granstack/study/report.hpp>
#include <granstack/study/engines.hpp>
#include <granstack/study/reproduce.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <set>
#include <thread>
#include <cmath>
#include <filesystem>

namespace granstack::study {

namespace fs = std::filesystem;

const CaseRecord* ExperimentResult::find_case(const std::string& name) const {
  for (const auto& c : cases) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

namespace {
std::optional<double> measured(const std::map<std::string, double>& values, const std::string& q) {
  const auto it = values.find(q);
  return it == values.end() || !std::isfinite(it->second) ? std::nullopt : std::optional<double>(it->second);
}
}  // namespace

std::vector<std::string> Verdict::other_side() const {
  std::vector<std::string> out;
  if (!value) return out;
  const auto in = [&](double x) { return x >= claim->low && x <= claim->high; };
  for (const auto& [q, x] : sensitivity) {
    if (x && in(*x) != in(*value)) out.push_back(fmt::format("{} = {:.4g}", q, *x));
  }
  return out;
}

Verdict judge(const Claim& claim, const std::map<std::string, double>& values, const std::map<std::string, double>& errors) {
  Verdict v;
  v.claim = &claim;
  for (const auto& q : claim.sensitivity) v.sensitivity.emplace_back(q, measured(values, q));
  for (const auto& q : claim.context) v.context.emplace_back(q, measured(values, q));
  v.value = measured(values, claim.quantity);
  if (!v.value) {
    v.verdict = "not measured";
    return v;
  }
  const double x = *v.value;
  v.error = measured(errors, claim.quantity);
  const double edge = x < claim.low ? claim.low : claim.high;
  const double scale = edge != 0.0 ? std::fabs(edge) : std::max({std::fabs(claim.low), std::fabs(claim.high), 1e-300});
  v.verdict = x >= claim.low && x <= claim.high ? "within" : "outside";
  v.off = v.verdict == "within" ? 0.0 : std::fabs(x - edge) / scale;
  if (claim.paper && *claim.paper != 0.0) v.from_paper = (x - *claim.paper) / std::fabs(*claim.paper);
  if (claim.paper && v.error && *v.error > 0.0) v.sigmas = (x - *claim.paper) / *v.error;
  return v;
}

namespace {

using Clock = std::chrono::steady_clock;

// DIR: new, empty, or a reproduction granstack made; anything else is refused.
void prepare_directory(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir, ec)) && fs::is_directory(dir, ec) && !fs::is_empty(dir, ec) &&
      !fs::exists(dir / formats::kOutputMarker, ec)) {
    throw formats::RefusedError(fmt::format("{} exists and was not made by granstack reproduce: granstack does not write "
                                            "into a directory of yours; choose a new directory with -o",
                                            dir.string()));
  }
  if (const auto maker = formats::output_written_by(dir); !maker.empty() && maker != "granstack reproduce") {
    throw formats::RefusedError(fmt::format("{} was made by {}, not by granstack reproduce: choose a new directory with -o",
                                            dir.string(), maker));
  }
  formats::prepare_output_directory(dir, {"report.md", "report.html", "report.json"}, true, "granstack reproduce");
}

// Generates the case unless it is there with the same spec; with `force`, anew.
void ensure_case(const fs::path& dir, const CaseEntry& entry, bool force, const ReproduceOptions& o) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir, ec)) && !force) {
    try {
      if (formats::read_manifest(dir.string()).spec == entry.spec) return;
    } catch (const std::exception&) {
    }
    throw ReproduceError(fmt::format("{} holds another case than the catalogue's {} (made by another granstack, or "
                                     "edited): pass --force to generate it again, or choose a new directory with -o",
                                     dir.string(), entry.name));
  }
  generator::GenerateOptions g;
  g.output = dir;
  g.force = true;  // only ever a case granstack made (generate refuses anything else)
  g.command_line = {"granstack", "reproduce", "-o", o.output};
  fs::create_directories(dir.parent_path());
  generator::generate({{entry.name, entry.spec}}, g);
}

// `pinned`: the cases run on the engine their catalogue entries name, by its own rules.
runner::RunOptions run_options(const ReproduceOptions& o, runner::Engine engine, const std::string& stage, bool pinned = false) {
  runner::RunOptions r;
  r.engine = engine;
  r.jobs = o.jobs;
  for (const auto& [name, program] : o.programs) r.programs[runner::parse_engine(name)] = program;
  // refsim checking LAMMPS runs LAMMPS's contact rules (the same spec as LAMMPS runs it).
  r.own<runner::RefsimOptions>().lammps_rules =
      !pinned && engine == runner::Engine::refsim && runner::parse_engine(o.engine) == runner::Engine::lammps;
  if (o.on_progress) {
    r.on_progress = [&o, stage](const runner::ProgressSnapshot& s) {
      std::string line = fmt::format("{}: {}/{} cases finished", stage, s.finished, s.total);
      for (const auto& c : s.running) {
        line += fmt::format(" | {} {:.0f}%", fs::path(c.name).filename().string(),
                            c.total_steps > 0 ? 100.0 * static_cast<double>(c.step) / static_cast<double>(c.total_steps) : 0.0);
      }
      o.on_progress(line);
    };
  }
  return r;
}

std::string status_name(runner::RunStatus s) {
  switch (s) {
    case runner::RunStatus::done: return "done";
    case runner::RunStatus::skipped: return "done";
    case runner::RunStatus::failed: return "failed";
    case runner::RunStatus::interrupted: return "interrupted";
    case runner::RunStatus::not_started: return "not run";
  }
  return "failed";
}

// A case's expected run time, to start the longest cases first (the last to start is then a
// short one and the cores stay busy to the end): LIGGGHTS's estimate, and for a run that stops at
// its blow's end that of one automatic duration (its cap's over cap_durations).
double expected_cost(const model::StackSpec& spec) {
  const auto stack = model::Stack::build(spec);
  const auto res = model::resolve(stack);
  const double seconds = model::estimate_cost(stack, res).liggghts_seconds;
  return res.stops_at_blow_end ? seconds / spec.cap_durations : seconds;
}

// The engine each finished case ran on, by its run.json (formats::run_engine), with its cases.
std::map<std::string, std::vector<std::string>> engines_of(const std::vector<CaseRecord*>& records) {
  std::map<std::string, std::vector<std::string>> found;
  for (const auto* rec : records) {
    const auto run = formats::read_run_record(rec->dir, formats::CaseFiles{});
    if (run.done()) found[formats::run_engine(run)].push_back(rec->dir);
  }
  return found;
}

std::string some_cases(const std::vector<std::string>& dirs) {
  return dirs.size() == 1 ? dirs.front() : fmt::format("{} and {} more", dirs.front(), dirs.size() - 1);
}

// The engine this call runs the study on: the one asked for, else the one its finished cases ran
// on (a reproduction goes on as it began), else LIGGGHTS. Cases run on another engine than the one
// asked for are never reused under its name: refused, unless `force` runs them all again.
std::string choose_engine(const ReproduceOptions& o, const std::vector<CaseRecord*>& records) {
  const auto found = engines_of(records);
  const auto& names = runner::engine_names();
  if (o.engine.empty()) {
    if (found.empty()) return runner::to_string(runner::RunOptions{}.engine);
    if (found.size() == 1 && std::find(names.begin(), names.end(), found.begin()->first) != names.end()) {
      return found.begin()->first;
    }
    std::vector<std::string> parts;
    for (const auto& [engine, dirs] : found) parts.push_back(fmt::format("{} ran {}", engine.empty() ? "no engine named" : engine, some_cases(dirs)));
    throw ReproduceError(fmt::format("{} holds cases run on several engines ({}): pass --engine E --force to run every "
                                     "case again on one, or choose a new directory with -o",
                                     o.output, fmt::join(parts, "; ")));
  }
  if (o.force) return o.engine;
  for (const auto& [engine, dirs] : found) {
    if (engine == o.engine) continue;
    throw ReproduceError(fmt::format("{}'s cases ran on {} ({}); this call asks for --engine {}: leave --engine out (or "
                                     "give --engine {}) to go on with that reproduction, add --force to run every case "
                                     "again on {}, or choose a new directory with -o",
                                     o.output, engine.empty() ? "an engine their run.json does not name" : engine,
                                     some_cases(dirs), o.engine, engine, o.engine));
  }
  return o.engine;
}

// Reduces each case as its run ends, on a thread of its own beside the runs: reduce's time goes into
// the cores the runs leave idle (LIGGGHTS's start-up and writing), not after the last run. One
// frame thread per case, so that it takes one core from the runs at most. reduce_all reduces what
// this did not (reused cases) and reports what it could not.
class OverlappedReduce {
 public:
  OverlappedReduce() : thread_([this] { work(); }) {}
  OverlappedReduce(const OverlappedReduce&) = delete;
  OverlappedReduce& operator=(const OverlappedReduce&) = delete;
  ~OverlappedReduce() { finish(); }
  void add(CaseRecord* record) {
    {
      const std::lock_guard lock(mutex_);
      queue_.push_back(record);
    }
    wake_.notify_one();
  }
  // Reduces what is queued and stops; after it every record it took is reduced or in errors().
  void finish() {
    {
      const std::lock_guard lock(mutex_);
      closed_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }
  bool tried(const CaseRecord* r) const { return tried_.count(r) != 0; }
  const std::map<const CaseRecord*, std::string>& errors() const { return errors_; }

 private:
  void work() {
    for (;;) {
      CaseRecord* r = nullptr;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return closed_ || !queue_.empty(); });
        if (queue_.empty()) return;
        r = queue_.front();
        queue_.pop_front();
      }
      if (os::interrupt_signal() != 0) continue;
      tried_.insert(r);
      postproc::ReduceOptions ro;
      ro.threads = 1;
      try {
        r->reduction = postproc::reduce_case(r->dir, ro);
      } catch (const std::exception& e) {
        errors_[r] = e.what();
      }
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<CaseRecord*> queue_;
  bool closed_ = false;
  std::set<const CaseRecord*> tried_;
  std::map<const CaseRecord*, std::string> errors_;
  std::thread thread_;  // last: it starts once the members it uses are made
};

// Runs `records` on the reproduction's engine, or (`pinned`) on the one their catalogue entries name.
void run_on(std::vector<CaseRecord*>& records, const std::string& pinned, const ReproduceOptions& o, StudyResult& result,
            OverlappedReduce& reducer) {
  if (records.empty()) return;
  const auto& engine = pinned.empty() ? o.engine : pinned;
  std::vector<std::string> dirs;
  std::map<std::string, CaseRecord*> by_dir;
  for (auto* r : records) {
    dirs.push_back(r->dir);
    by_dir[r->dir] = r;
  }
  auto ro = run_options(o, runner::parse_engine(engine), "run", !pinned.empty());
  ro.on_case_done = [&o, &by_dir, &reducer](const runner::RunOutcome& r) {
    if (r.status == runner::RunStatus::done) {
      if (const auto it = by_dir.find(r.case_dir); it != by_dir.end()) reducer.add(it->second);
    }
    if (!o.on_event) return;
    if (r.status == runner::RunStatus::done) o.on_event(fmt::format("done     {}  ({:.1f} s)", r.case_dir, r.wall_seconds));
    if (r.status == runner::RunStatus::failed) o.on_event(fmt::format("FAILED   {}  {}", r.case_dir, r.message));
  };
  const auto outcomes = runner::run_cases(dirs, ro);
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    auto& rec = *records[i];
    rec.status = status_name(outcomes[i].status);
    const auto run = formats::read_run_record(rec.dir, formats::CaseFiles{});
    rec.engine = formats::run_engine(run);
    if (run.done()) rec.run_sha256 = formats::sha256_file(fs::path(rec.dir) / formats::CaseFiles{}.run_record);
    if (outcomes[i].status == runner::RunStatus::done) rec.wall_seconds = outcomes[i].wall_seconds;
    if (rec.status == "done") continue;
    rec.reduction.reset();  // a case whose run did not end done has no reduction, whatever ran before
    rec.problem = outcomes[i].message;
    if (rec.status == "failed") {
      ++result.failed_cases;
    } else {
      ++result.interrupted_cases;
    }
  }
}

// Runs every case on its engine: the reproduction's, and refsim for the cases the catalogue pins
// to it; the records get their status.
void run_all(std::vector<CaseRecord*>& records, const ReproduceOptions& o, StudyResult& result, OverlappedReduce& reducer) {
  std::map<std::string, std::vector<CaseRecord*>> by_pin;
  for (auto* r : records) by_pin[r->pinned].push_back(r);
  for (auto& [pinned, group] : by_pin) run_on(group, pinned, o, result, reducer);
  reducer.finish();
}

void reduce_all(std::vector<CaseRecord*>& records, const ReproduceOptions& o, StudyResult& result, const OverlappedReduce& done) {
  std::size_t n = 0;
  for (auto* rec : records) {
    ++n;
    if (rec->status != "done" || os::interrupt_signal() != 0) continue;
    std::string error;
    if (done.tried(rec)) {
      if (const auto it = done.errors().find(rec); it != done.errors().end()) error = it->second;
    } else {
      if (o.on_progress) o.on_progress(fmt::format("reduce: {}/{} {}", n, records.size(), rec->dir));
      try {
        rec->reduction = postproc::reduce_case(rec->dir);
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    if (error.empty()) continue;
    rec->reduction.reset();
    rec->problem = error;
    ++result.failed_cases;
    if (o.on_event) o.on_event(fmt::format("FAILED   {}  reduce: {}", rec->dir, error));
  }
}

// refsim (or LIGGGHTS, when refsim ran the cases) on a copy of each case, compared; beside
// LAMMPS, refsim by LAMMPS's contact rules.
void validate_all(std::vector<CaseRecord*>& records, const ReproduceOptions& o) {
  const auto other = runner::other_engine(runner::parse_engine(o.engine));
  std::vector<std::string> dirs;
  std::vector<CaseRecord*> compared;
  for (auto* rec : records) {
    if (!rec->reduction || !rec->pinned.empty()) continue;  // a pinned case has no other engine to meet
    dirs.push_back(rec->dir);
    compared.push_back(rec);
  }
  const auto outcomes = runner::run_copies(dirs, other, run_options(o, other, "validate"));
  for (std::size_t i = 0; i < compared.size(); ++i) {
    if (outcomes[i].status != runner::RunStatus::done) {
      compared[i]->validate_quantity = fmt::format("{} failed: {}", runner::to_string(other), outcomes[i].message);
      compared[i]->validate_worst = INFINITY;
      continue;
    }
    const auto c = postproc::compare_runs(compared[i]->dir, runner::copy_dir(dirs[i], other));
    compared[i]->validate_worst = c.worst();
    compared[i]->validate_output = c.output_fraction.relative;
    compared[i]->validate_quantity = c.mismatches.empty() ? c.largest().quantity : c.mismatches.front();
  }
}

void analyse(ExperimentResult& e, const std::map<std::string, const CaseRecord*>& all, const ReproduceOptions& o,
             const std::vector<ExperimentResult>& results) {
  const auto analysis = find_analysis(e.experiment->analysis);
  if (analysis == nullptr) {
    e.notes.push_back(fmt::format("granstack has no analysis '{}'", e.experiment->analysis));
  } else {
    const AnalysisInput in{*e.experiment, all, (fs::path(o.output) / "figures").string(), o.gnuplot, results};
    try {
      analysis(in, e);
    } catch (const std::exception& ex) {
      e.notes.push_back(fmt::format("the analysis stopped: {}", ex.what()));
    }
  }
  for (const auto& c : e.experiment->claims) e.verdicts.push_back(judge(c, e.values, e.errors));
}

}  // namespace

StudyResult reproduce(const Catalogue& catalogue, const ReproduceOptions& options) {
  const auto start = Clock::now();
  auto o = options;
  StudyResult result;
  result.quick = o.quick;
  result.full = o.full;
  result.validated = o.validate;
  result.out_of_scope = catalogue.out_of_scope;
  const auto selected = select(catalogue, o.experiments, o.quick, o.full);
  std::optional<OtherReproduction> other;  // read first: a bad --against runs nothing
  if (!o.against.empty()) other = read_other_report(o.against);
  const fs::path root(o.output);

  std::vector<std::pair<double, CaseRecord*>> by_cost;
  std::vector<const CaseEntry*> entries;  // each case's catalogue entry, in the experiments' order
  std::vector<bool> beyond;               // and whether its experiment is beyond the paper
  result.experiments.reserve(selected.size());
  for (const auto* e : selected) {
    auto& er = result.experiments.emplace_back();
    er.experiment = e;
    for (const auto& c : e->cases) {
      if ((o.quick && !c.quick) || (!o.full && c.full)) continue;
      CaseRecord record;
      record.name = c.name;
      record.dir = (root / e->name / c.name).string();
      record.status = "not run";
      record.pinned = c.engine;
      er.cases.push_back(std::move(record));
      by_cost.emplace_back(expected_cost(c.spec), nullptr);
      entries.push_back(&c);
      beyond.push_back(e->beyond);
    }
    for (std::size_t i = 0; i < er.cases.size(); ++i) by_cost[by_cost.size() - er.cases.size() + i].second = &er.cases[i];
  }
  // The engine is chosen before any case is made or changed: a refusal leaves the directory as it was.
  std::vector<CaseRecord*> in_order, unpinned;
  for (auto& er : result.experiments) {
    for (auto& rec : er.cases) {
      in_order.push_back(&rec);
      if (rec.pinned.empty()) unpinned.push_back(&rec);
    }
  }
  o.engine = result.engine = choose_engine(o, unpinned);
  if (o.refuse_engine_options) {
    std::vector<std::string> running{o.engine};
    if (o.validate) running.push_back(runner::to_string(runner::other_engine(runner::parse_engine(o.engine))));
    if (const auto why = o.refuse_engine_options(running); !why.empty()) throw AgainstError(why);
  }
  if (other && other->engine == o.engine) {
    throw AgainstError(fmt::format("--against {}: that reproduction ran on {} too; give one made with another --engine",
                                   o.against, o.engine));
  }
  prepare_directory(root);
  // Beyond the paper, a case whose contact model the reproduction's engine lacks (thornton_ning on
  // LAMMPS) is not run, and says why: nothing is judged there, and the rest of its experiment stands.
  std::set<const CaseRecord*> refused;
  for (std::size_t i = 0; i < in_order.size(); ++i) {
    const auto why = in_order[i]->pinned.empty() && beyond[i]
                         ? runner::case_refusal(runner::parse_engine(o.engine), entries[i]->spec)
                         : std::string();
    if (why.empty()) {
      ensure_case(in_order[i]->dir, *entries[i], o.force, o);
      continue;
    }
    in_order[i]->problem = fmt::format("not run on {}: {}", o.engine, why);
    refused.insert(in_order[i]);
  }
  std::stable_sort(by_cost.begin(), by_cost.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<CaseRecord*> records;
  for (const auto& [cost, rec] : by_cost) {
    if (refused.count(rec) == 0) records.push_back(rec);
  }
  OverlappedReduce reducer;
  run_all(records, o, result, reducer);
  reduce_all(records, o, result, reducer);
  if (o.validate && os::interrupt_signal() == 0) validate_all(records, o);
  result.interrupted = os::interrupt_signal() != 0;
  if (result.interrupted && fs::exists(root / "report.json")) {
    result.report_kept = true;
    result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

  std::map<std::string, const CaseRecord*> all;
  for (const auto& e : result.experiments) {
    for (const auto& c : e.cases) all[e.experiment->name + "/" + c.name] = &c;
  }
  if (o.on_progress) o.on_progress("analyse and write the report");
  for (auto& e : result.experiments) analyse(e, all, o, result.experiments);
  if (other) result.against = compare_engines(result, *other);
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  write_report(result, o.output);
  return result;
}

}  // namespace granstack::study
