// granstack design: search a space of nested stacks (docs/design.md). run: the NSGA-II search on
// refsim, resumable; status: what the store holds; report: the front, the study's designs and
// the hypervolume as md, html and json; confirm: the front's best re-run on LIGGGHTS.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/design/batch.hpp>
#include <granstack/design/report.hpp>
#include <granstack/design/search.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>

namespace granstack::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStoreName = "design.sqlite";
constexpr const char* kSpaceName = "space.toml";

struct DesignFlags {
  std::string space_file, dir;
  int jobs = 1;
  bool slurm = false;
  design::SlurmBatchOptions batch;
  int generations = -1;
  long max_designs = 0;
  double time_limit = 0.0;
  int top = 3;
  bool no_report = false;
  std::string liggghts = runner::engine_row(runner::Engine::liggghts).program.name;  // confirm: the LIGGGHTS executable
  std::string geometry, sides;  // confirm: the physical variant, over the space's [confirm]
};

// A design directory holds its store, its space and its report; anything else in it is not ours.
void require_design_dir(const fs::path& dir) {
  if (!fs::exists(dir)) return;
  if (!fs::is_directory(dir)) throw formats::OutputError(fmt::format("{} exists and is not a directory: give another --output", dir.string()));
  if (fs::exists(dir / kStoreName)) return;
  // Empty, or holding only the lock a design run that kept nothing left.
  const auto only_lock = std::all_of(fs::directory_iterator(dir), fs::directory_iterator(),
                                     [](const fs::directory_entry& e) { return e.path().filename() == os::CaseLock::kFileName; });
  if (only_lock) return;
  throw formats::OutputError(fmt::format("{} holds files but no design store ({}): it is not a design directory; give "
                                         "another --output", dir.string(), kStoreName));
}

int print_status(const fs::path& dir) {
  const auto store = design::Store::open_existing((dir / kStoreName).string());
  const auto space = design::stored_space(store, (dir / kSpaceName).string());
  fmt::print("{}", design::status_text(space, store));
  return kOk;
}

// Why a search ended, in words.
std::string ended_because(const std::string& why, const design::Space& space, const std::string& exhausted_because) {
  if (why == "max_designs") return fmt::format("its budget of {} designs is spent", *space.search.max_designs);
  if (why == "time limit") return "its time limit has passed";
  if (why == "stagnation") {
    return fmt::format("it stagnated (the hypervolume gained no more than {:g} of itself over {} generations)",
                       space.search.stagnation_tolerance, space.search.stagnation);
  }
  if (why == "exhausted") {
    return fmt::format("the space is exhausted (no new design within its constraints in {} draws{})", design::kDrawsPerDesign,
                       exhausted_because.empty() ? "" : "; " + exhausted_because);
  }
  return fmt::format("generation {} reached", space.search.generations);
}

// A store whose designs ran with free sides because its file, read before side walls were the
// default, named none: resuming it with this file would run the rest confined, in one store.
void refuse_free_sides_search(const design::Store& existing, const design::Space& space, const std::string& text,
                              const std::string& file, const fs::path& store_path) {
  const auto digest = existing.meta("space_digest");
  if (!digest || *digest == space.digest() || design::parse_space(text, file, false, true).digest() != *digest) return;
  throw design::StoreError(fmt::format(
      "{}: its designs were run with free sides (design spaces were not confined by default when it was written), "
      "and {} names no sides, which now means side walls: add sides = \"free\" to its [fixed] to resume that search, "
      "or give another directory for a confined one",
      store_path.string(), file));
}

// Writes the report and prints its path; false when a signal stopped it (said, with how to write
// it later: the store holds everything it needs).
bool print_report(const design::Space& space, const design::Store& store, const fs::path& dir, int jobs) {
  try {
    fmt::print("report: {}\n", design::write_report(space, store, dir / "report", jobs).string());
    return true;
  } catch (const refsim::InSituStopped&) {
    fmt::print(stderr, "design: stopped by signal {} while writing the report; the store is complete: 'granstack design "
                       "report {}' writes it\n",
               os::interrupt_signal(), dir.string());
    return false;
  }
}

int run_design(const DesignFlags& f) {
  const auto text = formats::read_file(f.space_file);
  auto space = design::parse_space(text, f.space_file);
  if (f.generations >= 0) space.search.generations = f.generations;
  if (f.max_designs > 0) space.search.max_designs = f.max_designs;
  const fs::path dir(f.dir);
  require_design_dir(dir);
  const bool dir_made_now = !fs::exists(dir);
  const bool store_made_now = !fs::exists(dir / kStoreName) || design::Store::unfinished((dir / kStoreName).string());
  if (!store_made_now) {
    const auto existing = design::Store::open_existing((dir / kStoreName).string());
    design::adopt_schedule(space, existing);
    refuse_free_sides_search(existing, space, text, f.space_file, dir / kStoreName);
  }
  const bool space_made_now = !fs::exists(dir / kSpaceName);
  fs::create_directories(dir);
  const os::CaseLock lock(dir, "granstack design run");
  std::optional<design::Store> held;  // closed before a store this call made is removed
  held.emplace(design::Store::open((dir / kStoreName).string(), space.digest(), text));
  auto& store = *held;
  if (!fs::exists(dir / kSpaceName)) formats::write_file_atomically(dir / kSpaceName, text);
  StatusLine line;
  design::SearchOptions o;
  o.jobs = f.jobs;
  std::unique_ptr<design::BatchRunner> slurm;
  if (f.slurm) {
    auto b = f.batch;
    b.submit.engine = "refsim";
    b.submit.granstack = fs::read_symlink("/proc/self/exe").string();
    b.on_note = [&](const std::string& note) {
      line.clear();
      fmt::print(stderr, "{}\n", note);
    };
    slurm = design::slurm_runner(dir / "batches", b);
    o.runner = slurm.get();
  }
  o.on_progress = [&](int gen, int done, int total) { line.count(fmt::format("generation {}: designs", gen), done, total); };
  o.time_limit = f.time_limit > 0.0 ? f.time_limit : space.search.time_limit;  // the flag, else the space's
  o.on_generation = [&](const design::Generation& g) {  // a line each, on a terminal or in a log
    line.clear();
    fmt::print(stderr, "generation {}: {} new designs, hypervolume {:.6g}\n", g.index, g.evaluations, g.hypervolume);
  };
  design::SearchResult r;
  try {
    r = design::run_search(space, store, o);
  } catch (const refsim::InSituStopped&) {  // a signal: the designs running were abandoned, none stored
    line.clear();
    fmt::print(stderr, "design run: stopped by signal {}; the store keeps the {} designs that finished and its "
                       "finished generations: 'granstack design run {} -o {}' resumes\n",
               os::interrupt_signal(), store.evaluations().size(), f.space_file, dir.string());
    return kCaseFailed;  // the caller's exit code says the signal (130, 143)
  }
  if (r.ended == "exhausted" && store.evaluations().empty()) {
    // Nothing ran: what this call made goes, so that the space corrected runs in the same folder.
    if (store_made_now) {
      held.reset();
      for (const char* suffix : {"", "-wal", "-shm", "-journal"}) fs::remove(dir / (std::string(kStoreName) + suffix));
      if (space_made_now) fs::remove(dir / kSpaceName);
      if (dir_made_now && fs::is_empty(dir)) fs::remove(dir);
    }
    line.clear();
    fmt::print(stderr, "error: no design of {} can run ({}): change the space so that its designs keep within their "
                       "constraints{}\n",
               f.space_file, r.exhausted_because.empty() ? "every one drawn breaks a constraint" : r.exhausted_because,
               store_made_now ? "; nothing was kept" : "");
    return kBadInput;
  }
  try {
    design::evaluate_study_designs(space, store, f.jobs);
    if (design::yields(space)) {
      line.clear();
      fmt::print(stderr, "beside the elastic model: the front's and the study's designs under Hertz's law, e = 1 ...\n");
      const int twins = design::evaluate_elastic_twins(space, store, f.jobs);
      fmt::print(stderr, "beside the elastic model: {} elastic twin{} run ({} stored)\n", twins, twins == 1 ? "" : "s",
                 store.elastic_twins().size());
    }
  } catch (const refsim::InSituStopped&) {  // a signal: what finished is stored, the rest runs on a rerun
    line.clear();
    fmt::print(stderr, "design run: stopped by signal {} while running the study's designs or the elastic twins; the "
                       "store keeps the search and what finished: 'granstack design run {} -o {}' runs the rest\n",
               os::interrupt_signal(), f.space_file, dir.string());
    return kCaseFailed;  // the caller's exit code says the signal (130, 143)
  }
  const auto gens = store.generations();
  const bool beyond = !gens.empty() && r.ended == "generations" && gens.back().index > space.search.generations;
  fmt::print("{}: {}; {} ({} designs run this time{}; the store holds {} distinct designs)\n", dir.string(),
             beyond ? fmt::format("the store is at generation {} already, beyond the {} asked for: nothing to run (give "
                                  "more generations to go on)",
                                  gens.back().index, space.search.generations)
                    : ended_because(r.ended, space, r.exhausted_because),
             gens.empty() ? std::string("no generation finished") : fmt::format("generation {} done", gens.back().index),
             r.runs,
             r.probes > 0 ? fmt::format(", {} of them the study's designs and the probes that fix the objectives' box", r.probes)
                          : std::string(),
             store.evaluations().size());
  if (!f.no_report && !print_report(space, store, dir, f.jobs)) return kCaseFailed;
  return kOk;
}

int report(const DesignFlags& f) {
  const fs::path dir(f.dir);
  auto store = design::Store::open_existing((dir / kStoreName).string());
  const auto space = design::stored_space(store, (dir / kSpaceName).string());
  return print_report(space, store, dir, f.jobs) ? kOk : kCaseFailed;
}

int confirm(const DesignFlags& f) {
  const fs::path dir(f.dir);
  const os::CaseLock lock(dir, "granstack design confirm");
  const auto existing = design::Store::open_existing((dir / kStoreName).string());
  const auto text = existing.meta("space");
  auto space = design::stored_space(existing, (dir / kSpaceName).string());
  auto store = design::Store::open((dir / kStoreName).string(), space.digest(), *text);
  if (!f.geometry.empty()) space.confirm_variant.geometry = model::Geometry::nested3d;  // CLI's check: nested3d only
  if (!f.sides.empty()) space.confirm_variant.sides = *model::parse_boundary(f.sides);
  if (const auto why = space.confirm_variant.problem(space.fixed); !why.empty()) {
    fmt::print(stderr, "error: the variant to confirm on ({}): {}\n", space.confirm_variant.label(), why);
    return kBadInput;
  }
  StatusLine line;
  std::vector<design::Confirmation> results;
  try {
    results = design::confirm_front(
        space, store, dir / "confirm", f.top, [&](const std::string& what) { line.show(what); }, f.liggghts,
        [&](const std::string& plan) {
          line.clear();
          fmt::print("{}\n", plan);
          std::fflush(stdout);
        },
        f.jobs);
  } catch (const design::ConfirmRunFailed& e) {  // a run that failed: exit 1, as run's
    line.clear();
    fmt::print(stderr, "error: {}\n", e.what());
    return kCaseFailed;
  } catch (const refsim::InSituStopped& e) {  // a stop signal: the exit code says which (130, 143)
    line.clear();
    fmt::print(stderr, "{}\n", e.what());
    return kCaseFailed;
  }
  line.clear();
  if (results.empty()) {
    fmt::print(stderr, "error: {} has no design on its front (no feasible design in the store): nothing to confirm; run "
                       "the search further, or loosen the space's constraints\n",
               dir.string());
    return kCaseFailed;
  }
  int disagreements = 0, not_run = 0;
  for (const auto& c : results) {
    if (!c.not_run.empty()) {
      fmt::print("{}  {}\n", c.digest.substr(0, 12), c.verdict);
      ++not_run;
      continue;
    }
    const double longer = c.longer_difference.value_or(0.0);
    fmt::print("{}  {}  objectives: LIGGGHTS against {} {:.3g}; whole runs: largest difference {:.3g}: {}; run twice "
               "as long on LIGGGHTS, the objectives change by {:.3g}: {}\n",
               c.digest.substr(0, 12), c.case_dir, c.law.empty() ? "in situ" : "refsim under " + c.law,
               c.objective_difference, c.largest_difference, c.verdict, longer,
               longer <= design::kFinalTolerance ? "final" : "NOT FINAL");
    if (!c.law.empty()) {
      fmt::print("{}  {} against the search's {} (model form, not a disagreement): {}\n", c.digest.substr(0, 12), c.law,
                 model::to_string(space.fixed.normal_model), design::spread_text(c));
    }
    disagreements += c.verdict != "agree";
    if (!c.variant.empty()) {
      std::string measures;
      for (const auto& [name, value] : c.variant_measures) measures += fmt::format(" {} {:.4g}", name, value);
      fmt::print("{}  {}:{}{}\n", c.digest.substr(0, 12), c.variant, measures,
                 c.variant_not_final.empty() ? "" : "; " + c.variant_not_final);
    }
  }
  std::uintmax_t bytes = 0;  // what confirm's cases hold on disk now
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir / "confirm", ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_regular_file(ec)) bytes += it->file_size(ec);
  }
  fmt::print("confirm: its cases take {:.3g} MB in {}\n", static_cast<double>(bytes) / 1e6, (dir / "confirm").string());
  if (!print_report(space, store, dir, f.jobs)) return kCaseFailed;
  if (not_run == static_cast<int>(results.size())) {
    fmt::print(stderr, "error: none of the front's {} design{} could run on LIGGGHTS (above: why): nothing was confirmed\n",
               results.size(), results.size() == 1 ? "" : "s");
    return kCaseFailed;
  }
  return disagreements > 0 ? kDisagree : kOk;
}

// The objective table (design/objectives.hpp) as docs/how-to/design.md shows it.
int print_objectives() {
  fmt::print("| name | unit | what | needs | scenarios |\n|---|---|---|---|---|\n");
  for (const auto& o : design::objective_table()) {
    fmt::print("| `{}` | {} | {} | {} | {} |\n", o.name, o.unit, o.formula, o.needs == design::Needs::any ? "" : design::to_string(o.needs),
               o.from_run != nullptr ? "worst or mean of its runs" : "the design's own");
  }
  return 0;
}

}  // namespace

Command add_design(CLI::App& app) {
  auto f = std::make_shared<DesignFlags>();
  auto* cmd = app.add_subcommand("design", "Search a space of nested stacks for the least transmitted impact (NSGA-II on refsim, asynchronous or generational)");
  cmd->require_subcommand(1);
  auto* run = cmd->add_subcommand("run", "Run (or resume) the search of a design space; writes the store and the report");
  run->add_option("space", f->space_file, "Design space file (TOML: [fixed], [vary], [constraints], objectives, [search])")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("-o,--output", f->dir, "Design directory: its store (design.sqlite), space and report")
      ->check(output_directory())->required();
  run->add_option("-j,--jobs", f->jobs, "Designs run at once (refsim, one thread each)")->check(CLI::Range(1, 1024));
  run->add_option("--generations", f->generations, "Generations to reach (overrides [search] generations; more resumes further)")
      ->check(whole_range(0, design::kMaxGenerations));
  run->add_option("--max-designs", f->max_designs, "End once the search has run this many distinct designs (overrides [search] max_designs)")
      ->check(whole_range(design::kLeastMaxDesigns, 100'000'000L, design::kLeastMaxDesignsWhy));
  run->add_option("--time-limit", f->time_limit, "Start no design after this many seconds, abandoning those running (run again to go on)")
      ->check(finite_range(1.0, 1e9));
  run->add_flag("--no-report", f->no_report, "Do not write the report");
  run->add_flag("--slurm", f->slurm,
                "Run the designs as SLURM job arrays (granstack submit's): asynchronous, -j designs in flight, each "
                "an array of its scenarios; generational, each generation's designs, waited for");
  auto& b = f->batch;
  run->add_option("--partition", b.submit.partition, "--slurm: the partition [the site's default]");
  run->add_option("--account", b.submit.account, "--slurm: the account [the site's default]");
  run->add_option("--time", b.submit.time, "--slurm: wall time per task, HH:MM:SS [estimated]");
  run->add_option("--cases-per-task", b.submit.cases_per_task, "--slurm: designs each task runs")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  run->add_option("--max-parallel", b.submit.max_parallel, "--slurm: tasks at once [no limit]")->check(CLI::Range(1, 1000000));
  run->add_option("--poll", b.poll_seconds, "--slurm: seconds between looks at the queue [5]")->check(finite_range(0.05, 3600.0));
  run->add_option("--attempts", b.attempts, "--slurm: submissions of a design before the search stops [3]")->check(CLI::Range(1, 100));
  auto* status = cmd->add_subcommand("status", "What a design store holds: generations, hypervolume, the front");
  status->add_option("dir", f->dir, "Design directory")->required()->check(CLI::ExistingDirectory);
  auto* rep = cmd->add_subcommand("report", "Write the report (md, html, json, the front's spec files) again");
  rep->add_option("dir", f->dir, "Design directory")->required()->check(CLI::ExistingDirectory);
  rep->add_option("-j,--jobs", f->jobs, "The front's designs run again at once for the figures (refsim, one thread each)")
      ->check(CLI::Range(1, 1024));
  auto* conf = cmd->add_subcommand("confirm", "Run the front's best designs on LIGGGHTS and refsim and compare (validate)");
  conf->add_option("dir", f->dir, "Design directory")->required()->check(CLI::ExistingDirectory);
  conf->add_option("--top", f->top, "How many of the front's designs, best first objective first")->check(CLI::Range(1, 100));
  conf->add_option("-j,--jobs", f->jobs,
                   "Runs at once (each LIGGGHTS on one rank, each refsim on one thread), and the report's designs after")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  add_program_option(conf, runner::Engine::liggghts, f->liggghts);
  conf->add_option("--geometry", f->geometry, "Also run each design as this body on LIGGGHTS: nested3d (the strip's blocks as a 3D nest) [the space's [confirm]]")
      ->check(CLI::IsMember({"nested3d"}));
  conf->add_option("--sides", f->sides, "... and with these sides: wall | free [the space's [confirm]]")->check(CLI::IsMember({"wall", "free"}));
  auto* objectives = cmd->add_subcommand("objectives", "The measures a design space may minimise or bound, as a markdown table");
  return {cmd, [f, run, status, rep, conf, objectives] {
            if (objectives->parsed()) return print_objectives();
            if (run->parsed()) return run_design(*f);
            if (status->parsed()) return print_status(f->dir);
            if (rep->parsed()) return report(*f);
            if (conf->parsed()) return confirm(*f);
            return kBadInput;
          }};
}

}  // namespace granstack::app
