#pragma once
// The study's experiments as data (study/data/catalogue.toml, embedded at build time): each
// experiment's cases, the paper's statements with their acceptance bands, and the analysis that
// measures them.
#include <granstack/model/spec.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::study {

// One entry of the catalogue's record: a change to a claim's "statement", reading ("quantity"),
// "band", "paper" value, "scope" or, for a wave speed, the rule that times the wave ("timing",
// postproc::leading_pulse_rule), or to an experiment's "geometry" or "physics" (its main case's,
// geometry_text and physics_text), with the values before and after (as recorded_fields and
// geometry_text write them) and why.
struct Change {
  std::string date, commit, field, before, after, why;
  bool results_known = false;  // made when the run's values for the old reading were known
};

// The values a claim or an experiment was first fixed with, and its changes since, oldest first.
struct Record {
  std::string date, commit;
  std::map<std::string, std::string> fixed;  // field -> value as text
  // The first values were fixed in the commit that first reported their results (fixed's
  // results_known = true): not a prediction made before the run either.
  bool fixed_with_results = false;
  std::vector<Change> changes;
};

// One statement of the paper and how it is judged.
struct Claim {
  std::string id;                      // "<experiment>.<n>", n from 1 in the catalogue's order
  std::string statement;
  std::string quantity;                 // the primary reading, by the analysis's name: fixed before
                                       // the run, the one the verdict is about
  std::vector<std::string> sensitivity; // other readings of the same quantity, shown beside it, never a pass
  std::vector<std::string> context;     // readings of other quantities shown beside it, never judged against its band
  std::optional<double> paper;         // the value the paper states, if any
  double low = 0.0, high = 0.0;        // the acceptance band
  std::string band_reason;
  std::string expect;                  // "within" or "outside": what the elastic model gives
  // Whose statement it is: "paper" (the paper's claim), "granstack" (granstack's extension or
  // model of it, not the paper's words), "model check" (a property of the model the claim rests
  // on) or "arithmetic" (the paper's calculation, checked); scope_reason says why, where not "paper".
  std::string scope = "paper";
  std::string scope_reason;
  Record record;
};

// Whether a claim's quantity is a wave speed read by postproc's timing rule (speed.*,
// speed_ratio.*, speed_over_nesterenko.*).
bool reads_wave_timing(std::string_view quantity);

// The claim's recorded fields as the record writes them: statement, quantity, band "[low, high]",
// paper ("none" when it states none), scope, and for a wave speed the timing rule.
std::map<std::string, std::string> recorded_fields(const Claim& c);

struct CaseEntry {
  std::string name;      // the case's directory under DIR/<experiment>/
  model::StackSpec spec;
  bool quick = true;     // part of --quick when its experiment is
  bool full = false;     // run only with --full (the longer convergence and sensitivity runs)
  // "refsim": the case runs on refsim whatever the reproduction's engine (a contact law only
  // refsim has: Thornton's, which LIGGGHTS 3.8 and LAMMPS lack); "": on the reproduction's.
  std::string engine;
};

struct Experiment {
  std::string name, title, source, analysis, explanation;
  std::string main;                // the case the report's parameter table shows
  std::vector<std::string> needs;  // experiments whose cases this one's analysis reads
  bool quick = false;
  bool full = false;               // run only with --full, or when named
  // Beyond the paper: no claim of the paper's; measured and reported in a section of its own,
  // apart from the paper's claims and their verdicts.
  bool beyond = false;
  std::vector<CaseEntry> cases;
  std::vector<Claim> claims;
  Record record;  // of "geometry", the main case's geometry_text
};

// What a claim's verdict rests on in a case: its blocks, rows, top columns, radius ratio,
// materials, boundaries and when the run stops, e.g. "3 blocks of 24 rows, 2 top columns, ratio 2,
// steel/teflon/steel, bottom free, sides free, stop blow_end".
std::string geometry_text(const model::StackSpec& s);
// An experiment's main case's physics as its record writes it: the restitution and friction (and
// their pairs), the striker, the bottom radius, the contact model, and what else a spec may set
// (an offset, gravity, walls' material, custom materials, a fixed dt or duration).
std::string physics_text(const model::StackSpec& s);

// Each recorded field whose value is not what its record gives (the first fixed value, then each
// change's after in turn, each change's before being the value it replaced), and each record that
// is malformed: one line per problem, naming the claim or experiment and the fix. Empty when every
// change is recorded.
std::vector<std::string> unrecorded_changes(const Experiment& e);

// A statement of the paper granstack does not test, and why.
struct OutOfScope {
  std::string statement, why;
};

struct Catalogue {
  std::vector<Experiment> experiments;
  std::vector<OutOfScope> out_of_scope;
  const Experiment* find(std::string_view name) const;  // nullptr when unknown
  std::vector<std::string> names() const;
};

// Thrown for a catalogue that does not parse or names an invalid spec, naming the entry.
class CatalogueError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An experiment name the catalogue does not know (the message lists the known ones).
class UnknownExperiment : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Catalogue parse_catalogue(std::string_view toml_text, const std::string& source);
// The catalogue built into granstack.
const Catalogue& builtin_catalogue();

// The experiments to run, in the catalogue's order: those named (all when `names` is empty; with
// `quick`, those marked quick; without `full`, not those marked full), and the experiments they
// need. Throws UnknownExperiment.
std::vector<const Experiment*> select(const Catalogue& c, const std::vector<std::string>& names, bool quick, bool full = false);

}  // namespace granstack::study
