// granstack design confirm: the front's best run again on LIGGGHTS and refsim (validate's
// comparison), on LIGGGHTS twice as long, and as the physical variant the space asks for.
#include "report_parts.hpp"

#include <granstack/design/convergence.hpp>
#include <granstack/formats/case.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/yield.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/postproc/reduce.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/runner/runner.hpp>

#include <granstack/os/interrupt.hpp>
#include <granstack/refsim/in_situ.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace granstack::design {

namespace fs = std::filesystem;
using report_parts::worst_run;

namespace {

// A case confirm writes: its dumps binary (the same doubles as text, reduce and validate give the
// same numbers, about a third of the bytes and LIGGGHTS's time writing them).
model::StackSpec binary_dumps(model::StackSpec spec) {
  spec.dump_format = model::DumpFormat::binary;
  return spec;
}

// The run of the physical variant of a design's run `ran`: the variant's own, to its own blow's end
// (a store written before runs stopped there holds the strip's length and cadences: not the nest's).
model::StackSpec variant_run(const Space& space, const model::StackSpec& ran) {
  auto v = space.confirm_variant.applied_to(ran);
  if (!stops_at_blow_end(v)) return v;
  v.duration.reset();
  v.dump_every.reset();
  v.series_every.reset();
  return stopping_at_blow_end(v, space.cap_durations);
}

// The largest relative difference between the design's objectives from LIGGGHTS (reduce of
// its run) and the store's in-situ values.
double objective_difference(const Space& space, const model::StackSpec& ran, const std::map<std::string, double>& stored,
                            const postproc::CaseReduction& r) {
  const auto outcome = outcome_of(r, ran);
  double worst = 0.0;
  for (const auto o : space.objectives) {
    if (o->from_run == nullptr) continue;  // the geometric ones: the same stack
    const auto liggghts = o->from_run(outcome, space);
    const auto mine = stored.find(std::string(o->name));
    if (!liggghts || mine == stored.end()) continue;
    worst = std::max(worst, std::fabs(*liggghts - mine->second) / std::max(std::fabs(*liggghts), std::fabs(mine->second)));
  }
  return worst;
}

// A run of the design `ran` ran for `steps` steps, twice as long, with the same dt and output cadences.
model::StackSpec twice_as_long(const model::StackSpec& ran, long steps) { return running_for(ran, 2 * steps); }

// The steps the run of a case took: its run record's (a case that stops at its blow's end), or its spec's.
long steps_run(const std::string& case_dir) {
  const auto c = formats::Case::open(case_dir);
  return (formats::frames_written(c) - 1) * c.derived().dump_every;
}

// What confirm runs of a design: its run spec and stored measures, one per scenario.
std::vector<std::pair<model::StackSpec, std::map<std::string, double>>> confirm_runs(const Evaluation& e) {
  if (e.scenarios.empty()) return {{e.spec, e.measures}};
  std::vector<std::pair<model::StackSpec, std::map<std::string, double>>> out;
  for (const auto& r : e.scenarios) out.emplace_back(r.spec, r.measures);
  return out;
}

// What confirm will run and the most it can write (each run to its cap, binary dumps): LIGGGHTS
// and refsim of every scenario's case, LIGGGHTS again at up to twice that length, and the variant.
// What confirm will run for the front's designs that LIGGGHTS can take (`not_run[i]` empty) and
// the most it can write.
std::string confirm_plan(const Space& space, const std::vector<Evaluation>& front, const std::vector<std::string>& not_run,
                         std::size_t cases) {
  double bytes = 0.0;
  long runs = 0;
  const auto add = [&](const model::StackSpec& spec, double times) {
    const auto stack = model::Stack::build(binary_dumps(spec));
    const auto cost = model::estimate_cost(stack, model::resolve(stack));
    bytes += times * (cost.dump_bytes + cost.series_bytes);
  };
  std::size_t refused = 0;
  for (std::size_t i = 0; i < front.size(); ++i) {
    if (!not_run[i].empty()) {
      ++refused;
      continue;
    }
    for (const auto& [spec, measures] : confirm_runs(front[i])) {
      add(model::liggghts_counterpart(spec), 4.0);  // two engines, and LIGGGHTS twice as long
      runs += 3;
    }
    if (!space.confirm_variant.empty()) {
      add(variant_run(space, worst_run(front[i])), 1.0);
      ++runs;
    }
  }
  return fmt::format("confirm: {} front design{}{}, {} case{}, {} runs; at most {:.0f} MB of dumps and series (binary, "
                     "each run to its cap at most)",
                     front.size(), front.size() == 1 ? "" : "s",
                     refused > 0 ? fmt::format(" ({} not run on LIGGGHTS: below, why)", refused) : "", cases,
                     cases == 1 ? "" : "s", runs, bytes / 1e6);
}

// A case of one of a design's runs, as confirm runs it on LIGGGHTS: its spec (the search's, or the
// same stack under LIGGGHTS's nearest law, model::liggghts_counterpart) and the store's measures.
struct Entry {
  std::size_t design;
  std::map<std::string, double> measures;
  model::StackSpec spec;
  std::string dir;
  bool counterpart;  // LIGGGHTS runs another law than the search's
};

// Writes design `i`'s cases (DIGEST12, or DIGEST12_sK per scenario) into `dir` as LIGGGHTS runs them
// and adds them to `entries`: "", or why generate refused them for LIGGGHTS (nothing of them kept).
std::string write_cases(const Evaluation& e, std::size_t i, const fs::path& dir, std::vector<Entry>& entries) {
  const auto runs = confirm_runs(e);
  std::vector<Entry> mine;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto name = e.digest.substr(0, 12) + (runs.size() > 1 ? fmt::format("_s{}", k + 1) : "");
    generator::GenerateOptions o;
    o.output = dir / name;
    o.force = true;  // replaces only a case granstack made
    const auto spec = model::liggghts_counterpart(runs[k].first);
    if (auto why = runner::case_refusal(runner::Engine::liggghts, spec); !why.empty()) {  // a case LIGGGHTS refuses
      for (const auto& m : mine) fs::remove_all(m.dir);
      return why;
    }
    try {
      generator::generate({{name, binary_dumps(spec)}}, o);
    } catch (const std::invalid_argument& refused) {  // the deck's: LIGGGHTS cannot take this stack under its law
      for (const auto& m : mine) fs::remove_all(m.dir);
      return refused.what();
    }
    mine.push_back({i, runs[k].second, spec, o.output.string(), spec.normal_model != runs[k].first.normal_model});
  }
  entries.insert(entries.end(), mine.begin(), mine.end());
  return "";
}

// Each objective's spread between LIGGGHTS's law and the search's: LIGGGHTS's measures of the
// design's runs (`liggghts`, one per scenario) aggregated as the space aggregates them, over the
// store's, less 1.
std::map<std::string, double> law_spread(const Space& space, const Evaluation& e,
                                         const std::vector<std::map<std::string, double>>& liggghts) {
  std::map<std::string, double> out;
  const auto theirs = aggregated(space, liggghts);
  for (const auto o : space.objectives) {
    const auto it = theirs.find(std::string(o->name));
    const auto mine = objective_value(e, o);
    if (o->from_run != nullptr && it != theirs.end() && mine && *mine != 0.0) out[it->first] = it->second / *mine - 1.0;
  }
  return out;
}

}  // namespace

std::vector<Confirmation> confirm_front(const Space& space, Store& store, const fs::path& dir, int top,
                                        const std::function<void(const std::string&)>& on_progress,
                                        const std::string& liggghts_exe,
                                        const std::function<void(const std::string&)>& on_plan, int jobs) {
  auto front = pareto_front(space, store.evaluations());
  if (front.size() > static_cast<std::size_t>(top)) front.resize(static_cast<std::size_t>(top));
  std::vector<Entry> entries;
  std::vector<std::string> not_run(front.size());
  for (std::size_t i = 0; i < front.size(); ++i) not_run[i] = write_cases(front[i], i, dir, entries);
  std::vector<std::string> dirs;
  for (const auto& en : entries) dirs.push_back(en.dir);
  if (on_plan) on_plan(confirm_plan(space, front, not_run, entries.size()));
  runner::RunOptions ro;
  ro.jobs = jobs;
  if (!liggghts_exe.empty()) ro.programs[runner::Engine::liggghts] = liggghts_exe;
  const auto check = [](const std::vector<runner::RunOutcome>& outcomes) {
    for (const auto& r : outcomes) {
      if (r.status == runner::RunStatus::failed) throw ConfirmRunFailed(fmt::format("{}: {}", r.case_dir, r.message));
    }
    // A stop signal: the runs went no further, and nothing of them is read.
    if (const int signal = os::interrupt_signal(); signal != 0) {
      throw refsim::InSituStopped(fmt::format("confirm stopped by signal {}: the front's runs went no further (its cases, "
                                              "in confirm/, are kept); 'granstack design confirm' runs them again",
                                              signal));
    }
  };
  for (const auto engine : {runner::Engine::liggghts, runner::Engine::refsim}) {
    ro.on_progress = [&](const runner::ProgressSnapshot& s) {
      if (on_progress) on_progress(fmt::format("confirm: {} runs {} of {}", runner::to_string(engine), s.finished, s.total));
    };
    check(runner::run_copies(dirs, engine, ro));
  }
  // The physical confirmation: each run again on LIGGGHTS, twice as long as LIGGGHTS ran it
  // (to the frame where it judged the blow ended), with the same cadences.
  std::vector<std::string> longer_dirs;
  std::vector<model::StackSpec> longer_specs;
  for (const auto& en : entries) {
    generator::GenerateOptions o;
    o.output = en.dir + "_x2";
    o.force = true;
    longer_specs.push_back(twice_as_long(en.spec, steps_run(runner::copy_dir(en.dir, runner::Engine::liggghts))));
    generator::generate({{o.output.filename().string(), binary_dumps(longer_specs.back())}}, o);
    longer_dirs.push_back(o.output.string());
  }
  ro.engine = runner::Engine::liggghts;
  ro.force = true;
  ro.on_progress = [&](const runner::ProgressSnapshot& s) {
    if (on_progress) on_progress(fmt::format("confirm: LIGGGHTS twice as long, {} of {}", s.finished, s.total));
  };
  check(runner::run_cases(longer_dirs, ro));
  // The physical variant the space asks for, of each design's worst scenario, on LIGGGHTS.
  const auto& variant = space.confirm_variant;
  std::vector<std::pair<std::string, model::StackSpec>> variant_runs(front.size());
  if (!variant.empty()) {
    std::vector<std::string> variant_dirs;
    for (std::size_t i = 0; i < front.size(); ++i) {
      if (!not_run[i].empty()) continue;
      generator::GenerateOptions o;
      o.output = dir / (front[i].digest.substr(0, 12) + variant.suffix());
      o.force = true;
      variant_runs[i] = {o.output.string(), variant_run(space, model::liggghts_counterpart(worst_run(front[i])))};
      generator::generate({{o.output.filename().string(), binary_dumps(variant_runs[i].second)}}, o);
      variant_dirs.push_back(o.output.string());
    }
    ro.on_progress = [&](const runner::ProgressSnapshot& s) {
      if (on_progress) on_progress(fmt::format("confirm: LIGGGHTS, {}, {} of {}", variant.label(), s.finished, s.total));
    };
    check(runner::run_cases(variant_dirs, ro));
  }
  // Per design: the worst of its scenarios' comparisons, and the largest LIGGGHTS values.
  std::vector<Confirmation> out;
  postproc::ReduceOptions quiet;
  quiet.write_files = false;
  for (std::size_t i = 0; i < front.size(); ++i) {
    Confirmation c{front[i].digest, "", 0.0, std::nullopt, 0.0, 0.0, "", std::nullopt, "", {}, "", "", {}, std::nullopt,
                   not_run[i]};
    if (!not_run[i].empty()) {
      c.verdict = "not run on LIGGGHTS: " + not_run[i];
      out.push_back(c);
      store.put_confirmation(c);
      continue;
    }
    std::vector<std::string> disagreements;
    std::vector<std::map<std::string, double>> liggghts_measures;
    for (std::size_t n = 0; n < entries.size(); ++n) {
      const auto& en = entries[n];
      if (en.design != i) continue;
      const auto liggghts = runner::copy_dir(en.dir, runner::Engine::liggghts), refsim = runner::copy_dir(en.dir, runner::Engine::refsim);
      const auto compared = postproc::compare_runs(liggghts, refsim);
      if (const auto why = compared.disagreement(postproc::kDefaultTolerance); !why.empty()) {
        disagreements.push_back(fs::path(en.dir).filename().string() + ": " + why);
      }
      const auto r = postproc::reduce_case(liggghts, quiet);
      liggghts_measures.push_back(run_measures(space, outcome_of(r, en.spec)));
      // What LIGGGHTS is held to: the store's objectives, or, under another law than the
      // search's, refsim's run of the same case.
      const auto reference = en.counterpart ? run_measures(space, outcome_of(postproc::reduce_case(refsim, quiet), en.spec))
                                            : en.measures;
      if (en.counterpart) {
        c.law = model::to_string(en.spec.normal_model);
        if (const auto y = model::yield_pressure_departure(model::Stack::build(en.spec))) {
          c.law_yield = c.law_yield ? std::pair{std::min(c.law_yield->first, y->first), std::max(c.law_yield->second, y->second)} : *y;
        }
      }
      if (c.case_dir.empty()) c.case_dir = en.dir;
      c.liggghts_output_fraction = std::max(c.liggghts_output_fraction, r.output_fraction);
      if (r.peak_wall_force) c.liggghts_peak_wall_force = std::max(c.liggghts_peak_wall_force.value_or(0.0), *r.peak_wall_force);
      c.largest_difference = std::max(c.largest_difference, compared.worst());
      c.objective_difference = std::max(c.objective_difference, objective_difference(space, en.spec, reference, r));
      const auto longer = postproc::reduce_case(en.dir + "_x2", quiet);
      c.longer_difference = std::max(c.longer_difference.value_or(0.0),
                                     objective_difference(space, longer_specs[n], reference, longer));
    }
    if (!c.law.empty()) c.law_spread = law_spread(space, front[i], liggghts_measures);
    // One tolerance, one verdict: the objectives and the whole runs, frame by frame, to the same
    // stopping frame (validate's), whatever the objectives say.
    if (c.objective_difference > postproc::kDefaultTolerance) {
      disagreements.push_back(fmt::format("objectives differ by {:.3g} (tolerance {:g})", c.objective_difference,
                                          postproc::kDefaultTolerance));
    }
    c.verdict = disagreements.empty() ? "agree" : fmt::format("DISAGREE: {}", fmt::join(disagreements, "; "));
    if (!variant.empty()) {
      const auto& [vdir, vspec] = variant_runs[i];
      const auto outcome = outcome_of(postproc::reduce_case(vdir, quiet), vspec);
      c.variant = variant.label();
      c.variant_measures = run_measures(space, outcome);
      c.variant_not_final = not_final(space, vspec, outcome);
    }
    out.push_back(c);
    store.put_confirmation(c);
  }
  return out;
}

}  // namespace granstack::design
