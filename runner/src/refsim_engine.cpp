// refsim behind the engine interface: granstack's reference integrator, in this process.
#include "engine.hpp"

#include <granstack/runner/engine_options.hpp>
#include <granstack/runner/engines.hpp>

#include <granstack/generator/case_writer.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/version.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/process.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/refsim/system.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace granstack::runner {

namespace fs = std::filesystem;

namespace {

// Thrown from refsim's progress callback to end its loop when granstack is asked to stop.
struct Interrupted {};

// refsim takes its physics from the manifest, LIGGGHTS from the deck: they must say the same.
std::string refsim_unavailable(const fs::path& dir, const formats::Manifest& manifest) {
  if (generator::has_default_deck(dir.string(), manifest)) return "";
  const bool other_build = manifest.git_commit != granstack::git_commit();
  return fmt::format("refsim: {} is not the deck this granstack's template gives for this case ({}), so refsim cannot "
                     "be sure to run the same physics; run it with LIGGGHTS, or generate the case again{}",
                     (dir / manifest.files.deck).string(),
                     other_build ? fmt::format("the case was written by granstack commit {}, this is {}; or it was "
                                               "rendered from a --template of yours",
                                               manifest.git_commit, granstack::git_commit())
                                 : "it was rendered from a --template of yours",
                     other_build ? "" : " without --template");
}

EngineResult run_refsim(const fs::path& dir, const RunOptions& o,
                        const std::function<void(long)>& on_step, const std::function<void()>& on_started) {
  EngineResult result;
  const auto& own = o.own<RefsimOptions>();
  try {
    refsim::RunOptions ro;
    ro.threads = own.threads;
    ro.kernel = own.kernel;
    ro.lammps_rules = own.lammps_rules;
    // The outputs on a thread of their own where a CPU is left over by every case's threads.
    ro.write_behind = os::usable_cpus() >= (own.threads + 1) * std::max(1, o.jobs);
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
    result.record["threads"] = own.threads;
    result.record["kernel"] = stats.kernel;
    result.record["contact_rules"] = own.lammps_rules ? "lammps" : "liggghts";
    result.record["write_behind"] = stats.write_behind;
    result.record["neighbor_builds"] = stats.neighbor_builds;
    result.record["outside_loop_seconds"] = {{"read", stats.read_seconds},
                                             {"build", stats.build_seconds},
                                             {"first_output", stats.first_output_seconds},
                                             {"close", stats.close_seconds}};
  } catch (const Interrupted&) {
    result.interrupted = true;
  } catch (const std::exception& e) {
    const std::string why = e.what();  // System's own messages may name refsim already
    result.error = why.starts_with("refsim: ") ? why : "refsim: " + why;
  }
  return result;
}

class Refsim final : public CaseEngine {
 public:
  std::string lock_holder() const override { return "granstack run --engine refsim"; }
  std::string unavailable(const formats::Case& c, const RunOptions& o) const override {
    if (o.own<RefsimOptions>().lammps_rules) {
      // refsim's LAMMPS rules are those of the LAMMPS this machine has (contact_models/choice.hpp).
      if (const auto why = model::lammps_contact_unmappable(c.spec(), model::lammps_rules_run_here()); !why.empty()) {
        return "refsim --contact-rules lammps: " + why;
      }
    } else if (const auto why = model_refusal(Engine::refsim, c.spec().contact_model()); !why.empty()) {
      return "refsim by LIGGGHTS's contact rules (the default): " + std::string(why);
    }
    return refsim_unavailable(c.dir(), c.manifest());
  }
  EngineResult run(const formats::Case& c, const RunOptions& o, const std::function<void(long)>& on_step,
                   const std::function<void()>& on_started) const override {
    return run_refsim(c.dir(), o, on_step, on_started);
  }
};

// --kernel's values: auto, reference and the vector instruction sets this CPU runs.
std::vector<std::string> kernel_choices() {
  std::vector<std::string> choices{"auto", "reference"};
  for (const auto& k : refsim::vector_kernels()) choices.push_back(k);
  return choices;
}

void add_refsim_options(CLI::App& group, RunOptions& o) {
  auto& own = o.own<RefsimOptions>();
  group.add_option("--threads", own.threads,
                   "Threads per case (results do not depend on it; where a CPU is left over, refsim writes its outputs "
                   "on one more)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  group.add_option("--kernel", own.kernel,
                   fmt::format("refsim's kernels: auto (the best vector instruction set this CPU runs), reference "
                               "(scalar) or one of this CPU's: {}; all give the same bits",
                               fmt::join(refsim::vector_kernels(), ", ")))
      ->check(CLI::IsMember(kernel_choices()))
      ->capture_default_str();
  group.add_option_function<std::string>(
           "--contact-rules", [&own](const std::string& rules) { own.lammps_rules = rules == "lammps"; },
           "liggghts (the case's deck, LIGGGHTS's contact law to the bit) or lammps (the same spec as LAMMPS runs it: "
           "docs/explanation/lammps.md)")
      ->check(CLI::IsMember({"liggghts", "lammps"}))
      ->default_str("liggghts");
}

// refsim's contact rules are LIGGGHTS's, whose frame also runs refsim's own Thornton, or LAMMPS's.
std::string_view refsim_refuses(const model::ContactModel& m, bool lammps_rules) {
  return lammps_rules ? model::lammps_refusal(m) : model::refsim_liggghts_refusal(m);
}

EngineRow::Cpus refsim_cpus(const RunOptions& o) { return {o.own<RefsimOptions>().threads, "threads", "--threads"}; }

}  // namespace

EngineRow refsim_row() {
  return {Engine::refsim,
          "refsim",
          "the in-house reference integrator",
          {"--threads", "--kernel", "--contact-rules"},
          {},
          [] { return std::unique_ptr<CaseEngine>(std::make_unique<Refsim>()); },
          refsim_refuses,
          add_refsim_options,
          nullptr,
          refsim_cpus,
          true};
}

}  // namespace granstack::runner
