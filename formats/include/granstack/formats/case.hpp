#pragma once
// One case directory, opened once: its manifest (verified), the stack its spec builds, the
// values generate derived for it (typed, from the manifest: the deck's own dt and step count),
// its files, its run record (run.json: the one reader and writer) and its lock. Every command
// that works on a case opens it through here.
#include <granstack/formats/json_box.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/os/case_lock.hpp>

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace granstack::formats {

// What generate derived and wrote to the manifest (derived), as the deck runs it.
struct Derived {
  double dt = 0.0;        // s
  double duration = 0.0;  // s, steps * dt
  long steps = 0;
  long dump_every = 0;
  long series_every = 0;
  // The dump frames a whole run writes: step 0 and every dump_every-th step.
  long frames() const { return steps / dump_every + 1; }
};

// A run's record, run.json: "running" while a run goes on, then "done", "failed" or
// "interrupted" with what the run measured. One rule for a damaged record everywhere: it is
// `damaged`, with the reason in `error`, never taken for a finished run.
struct RunRecord {
  std::string status;         // "" when there is none, "damaged" when it cannot be read
  std::string error;          // a failed run's message (its first line in `error_line()`), or why it is damaged
  JsonBox record;             // the whole record (an empty object when none or damaged)
  bool exists() const { return !status.empty(); }
  bool done() const { return status == "done"; }
  std::string error_line() const { return error.substr(0, error.find('\n')); }
};

// The engine a run's record names, with refsim's contact rules where they are LAMMPS's: "liggghts",
// "lammps", "refsim" or "refsim (LAMMPS's rules)", and "liggghts (run by hand)" for a run
// `granstack adopt` took; "" when the record names none.
std::string run_engine(const RunRecord& record);

// The commands beyond granstack's deck that a run executed, as its spec's deck_additions let them
// ("TEXT (FILE:LINE)", formats/deck_rules.hpp), from its record; empty when none.
std::vector<std::string> deck_additions_ran(const RunRecord& record);

// Reads DIR/run.json (files.run_record).
RunRecord read_run_record(const std::filesystem::path& case_dir, const CaseFiles& files);
// Writes it atomically (a temporary file renamed into place).
void write_run_record(const std::filesystem::path& case_dir, const CaseFiles& files, const nlohmann::json& record);

class Case;
// The dump frames a case's run wrote: step 0 and every dump_every-th step to the end of the run
// (Derived::frames()); for a case that stops at the blow's end (StopRule::blow_end), to the step
// where its run stopped, which its run record holds (a FormatError when it holds none).
long frames_written(const Case& c);

class Case {
 public:
  // Opens DIR: reads and verifies its manifest (FormatError naming what is wrong) and reads the
  // derived values. The stack is built when first asked for (a million spheres take seconds, which
  // a LIGGGHTS run or a frame count does not need), once, from any thread.
  static Case open(const std::string& dir);

  const std::string& dir() const { return dir_; }
  std::filesystem::path path(const std::string& file) const { return std::filesystem::path(dir_) / file; }
  const Manifest& manifest() const { return manifest_; }
  const std::string& name() const { return manifest_.case_name; }
  const model::StackSpec& spec() const { return manifest_.spec; }
  const CaseFiles& files() const { return manifest_.files; }
  const model::Stack& stack() const;
  const Derived& derived() const { return derived_; }
  // What the spec gives today: the same as derived() unless the rules changed since generate
  // (or the manifest was edited), which check_derived() refuses.
  model::Resolution resolution() const { return model::resolve(stack()); }
  // What the case costs (model::estimate_cost), from the manifest's counts: no stack is built.
  model::Cost cost() const;
  // Throws FormatError when the derived values are not what the spec gives.
  void check_derived() const;

  // Takes the case's lock for `what` ("granstack run"), or throws os::LockedError naming its holder.
  os::CaseLock lock(const std::string& what) const { return os::CaseLock(dir_, what); }

  RunRecord run_record() const { return read_run_record(dir_, files()); }
  void write_run_record(const nlohmann::json& record) const { formats::write_run_record(dir_, files(), record); }

 private:
  std::string dir_;
  Manifest manifest_;
  struct LazyStack {
    std::once_flag built;
    std::optional<model::Stack> stack;
  };
  std::shared_ptr<LazyStack> stack_ = std::make_shared<LazyStack>();
  Derived derived_;
};

}  // namespace granstack::formats
