#pragma once
// A reproduction set beside another engine's (reproduce --against DIR): each claim's value on
// both, how far apart, whether its verdict changed, and why the engines differ on it.
#include <granstack/study/reproduce.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace granstack::study {

// The other reproduction's report.json, read before any case runs: throws ReproduceError where it
// is missing, unreadable, or of the same engine.
nlohmann::json read_other_report(const std::string& dir, const std::string& engine_here);

// This study's claims beside the other report's, the causes named from the experiments' specs and
// the two engines' contact rules (model/lammps.hpp).
EngineComparison compare_engines(const StudyResult& r, const nlohmann::json& other, const std::string& dir);

// Why the engines `a` and `b` (liggghts, refsim, lammps) differ on experiment e's cases.
std::string difference_cause(const Experiment& e, const std::string& a, const std::string& b);

}  // namespace granstack::study
