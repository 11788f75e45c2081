#pragma once
// A reproduction set beside another engine's (reproduce --against DIR): each claim's value on
// both, how far apart, whether its verdict changed, and why the engines differ on it.
#include <granstack/formats/json_box.hpp>
#include <granstack/study/reproduce.hpp>

#include <string>

namespace granstack::study {

// Another reproduction, vouched for by its cases.
struct OtherReproduction {
  std::string dir;
  formats::JsonBox report;  // its report.json
  std::string engine;     // the engine its cases ran on, by their run.json
};

// The other reproduction's report.json, read before any case runs, and the cases it was made from:
// each case it counts as done must still be as the report found it (its run.json the one the
// report recorded, its files those its run wrote, as `status` checks them) and all of one engine,
// the report's. Throws ReproduceError naming what is wrong and how to bring it up to date.
OtherReproduction read_other_report(const std::string& dir);

// This study's claims beside the other report's, the causes named from the experiments' specs and
// the two engines' contact rules (model/lammps.hpp).
EngineComparison compare_engines(const StudyResult& r, const OtherReproduction& other);

// Why the engines `a` and `b` (liggghts, refsim, lammps) differ on experiment e's cases.
std::string difference_cause(const Experiment& e, const std::string& a, const std::string& b);

}  // namespace granstack::study
