#pragma once
// The named analyses the catalogue's experiments refer to: each measures its experiment's
// quantities from the reduced cases, and adds the tables and figures of the report.
#include <granstack/study/reproduce.hpp>

#include <map>
#include <string>

namespace granstack::study {

struct AnalysisInput {
  const Experiment& experiment;
  const std::map<std::string, const CaseRecord*>& cases;  // every case of the run, by "<experiment>/<case>"
  std::string figures_dir;                                 // DIR/figures
  std::string gnuplot;
  // The case's reduction, or nullptr when it did not run or could not be reduced.
  const postproc::CaseReduction* reduction(const std::string& experiment, const std::string& case_name) const;
  const postproc::CaseReduction* own(const std::string& case_name) const { return reduction(experiment.name, case_name); }
};

using Analysis = void (*)(const AnalysisInput&, ExperimentResult&);

// nullptr when the catalogue names an analysis granstack does not have.
Analysis find_analysis(const std::string& name);

}  // namespace granstack::study
