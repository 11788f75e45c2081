#pragma once
// The engines granstack runs a case on, behind one interface: run_one (runner.cpp) does the
// rest (the lock, the earlier outputs, run.json) the same for all. LIGGGHTS's is
// liggghts_engine.cpp, refsim's refsim_engine.cpp, LAMMPS's lammps_engine.cpp, each with its row
// (engines.hpp: its factory, its options' group, its refusals); another engine is one more such
// file, its row listed in engines.cpp (with an enumerator in Engine, runner.hpp) or added by
// add_engine() from the file itself.
#include <granstack/formats/case.hpp>
#include <granstack/runner/engines.hpp>
#include <granstack/runner/runner.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace granstack::runner {

// What one engine run produced: an error message (empty on success) and the figures for run.json.
struct EngineResult {
  std::string error;
  nlohmann::json record = nlohmann::json::object();
  bool interrupted = false;  // stopped by a signal to granstack
  bool started = false;      // the engine began the run (LIGGGHTS printed its banner; refsim stepped)
  double loop_seconds = 0.0;
  double particle_steps_per_second = 0.0;
};

class CaseEngine {
 public:
  virtual ~CaseEngine() = default;
  // What the case's lock says holds it ("granstack run").
  virtual std::string lock_holder() const = 0;
  // Why it cannot start on this case (a missing program, a deck it cannot run), or "": asked
  // before anything of an earlier run is touched.
  virtual std::string unavailable(const formats::Case& c, const RunOptions& o) const = 0;
  // Runs the case; on_step with each step it reaches, on_started once when it has begun.
  virtual EngineResult run(const formats::Case& c, const RunOptions& o, const std::function<void(long)>& on_step,
                           const std::function<void()>& on_started) const = 0;
  // The files a run reads and writes: the case's, but for the deck, log and screen output of an
  // engine that is not the one the case's deck is for.
  virtual formats::CaseFiles files(const formats::Case& c) const { return c.files(); }
  // Removes what a stopped run leaves that is no result (made since `since`).
  virtual void tidy(const std::filesystem::path& dir, std::filesystem::file_time_type since) const {
    (void)dir;
    (void)since;
  }
};

// The built-in engines' rows, each defined in its engine's file.
EngineRow liggghts_row();
EngineRow refsim_row();
EngineRow lammps_row();
inline std::unique_ptr<CaseEngine> make_engine(Engine e) { return engine_row(e).make(); }

}  // namespace granstack::runner
