// A fourth engine, standing in for one a contributor adds: refsim's integrator under another name,
// with an option of its own (--standin-threads). It is this file and its row, added to the table
// by runner::add_engine as the program starts; nothing else in granstack names it. It is built
// into a second program with the same commands (granstack_standin), which
// tests/cli/test_standin.cpp runs through run, its help, validate and reduce.
#include "engine.hpp"  // runner/src: CaseEngine, the seam every engine implements

#include <granstack/generator/decks.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/runner/engines.hpp>

#include <CLI/CLI.hpp>

namespace granstack::runner {
namespace {

// Its own options.
struct StandinOptions {
  int threads = 1;
};

struct Stopped {};  // thrown from the progress callback when granstack is asked to stop

class Standin final : public CaseEngine {
 public:
  std::string lock_holder() const override { return "granstack run --engine standin"; }
  // As refsim: LIGGGHTS's contact rules, and the manifest's physics only where the deck is granstack's own.
  std::string unavailable(const formats::Case& c, const RunOptions&) const override {
    if (const auto why = model::refsim_liggghts_refusal(c.spec().contact_model()); !why.empty()) {
      return "standin: " + std::string(why);
    }
    return generator::has_default_deck(c.dir(), c.manifest()) ? "" : "standin: the case's deck is not granstack's own";
  }
  EngineResult run(const formats::Case& c, const RunOptions& o, const std::function<void(long)>& on_step,
                   const std::function<void()>& on_started) const override {
    EngineResult result;
    refsim::RunOptions ro;
    ro.threads = o.own<StandinOptions>().threads;
    ro.on_progress = [&](long step, long) {
      if (!result.started) on_started();
      result.started = true;
      on_step(step);
      if (os::interrupt_signal() != 0) throw Stopped();
    };
    try {
      const auto stats = refsim::run_case(c.dir(), ro);
      result.started = true;
      result.loop_seconds = stats.loop_seconds;
      result.particle_steps_per_second = stats.particle_steps_per_second;
      result.record["steps"] = stats.steps;
      result.record["threads"] = ro.threads;
    } catch (const Stopped&) {
      result.interrupted = true;
    } catch (const std::exception& e) {
      result.error = std::string("standin: ") + e.what();
    }
    return result;
  }
};

void add_standin_options(CLI::App& group, RunOptions& o) {
  group.add_option("--standin-threads", o.own<StandinOptions>().threads, "Threads per case")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
}

[[maybe_unused]] const Engine kStandin = add_engine({Engine{},
                                    "standin",
                                    "refsim under another name, a test's stand-in engine",
                                    {"--standin-threads"},
                                    {},
                                    [] { return std::unique_ptr<CaseEngine>(std::make_unique<Standin>()); },
                                    [](const model::ContactModel& m, bool) { return model::refsim_liggghts_refusal(m); },
                                    add_standin_options,
                                    nullptr,
                                    [](const RunOptions& o) {
                                      return EngineRow::Cpus{o.own<StandinOptions>().threads, "threads",
                                                             "--standin-threads"};
                                    }});

}  // namespace
}  // namespace granstack::runner
