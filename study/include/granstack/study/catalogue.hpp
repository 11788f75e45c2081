#pragma once
// The study's experiments as data (study/data/catalogue.toml, embedded at build time): each
// experiment's cases, the paper's statements with their acceptance bands, and the analysis that
// measures them.
#include <granstack/model/spec.hpp>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::study {

// One statement of the paper and how it is judged.
struct Claim {
  std::string id;                      // "<experiment>.<n>", n from 1 in the catalogue's order
  std::string statement;
  std::string quantity;                 // the primary reading, by the analysis's name: fixed before
                                       // the run, the one the verdict is about
  std::vector<std::string> sensitivity; // other readings, shown beside it, never a pass
  std::optional<double> paper;         // the value the paper states, if any
  double low = 0.0, high = 0.0;        // the acceptance band
  std::string band_reason;
  std::string expect;                  // "within" or "outside": what the elastic model gives
};

struct CaseEntry {
  std::string name;      // the case's directory under DIR/<experiment>/
  model::StackSpec spec;
  bool quick = true;     // part of --quick when its experiment is
  bool full = false;     // run only with --full (the longer convergence and sensitivity runs)
};

struct Experiment {
  std::string name, title, source, analysis, explanation;
  std::string main;                // the case the report's parameter table shows
  std::vector<std::string> needs;  // experiments whose cases this one's analysis reads
  bool quick = false;
  bool full = false;               // run only with --full, or when named
  std::vector<CaseEntry> cases;
  std::vector<Claim> claims;
};

struct Catalogue {
  std::vector<Experiment> experiments;
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
