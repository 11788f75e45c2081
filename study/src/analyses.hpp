#pragma once
// The named analyses the catalogue's experiments refer to: each measures its experiment's
// quantities from the reduced cases, and adds the tables and figures of the report.
#include <granstack/study/reproduce.hpp>

#include <map>
#include <string>
#include <vector>

namespace granstack::study {

struct AnalysisInput {
  const Experiment& experiment;
  const std::map<std::string, const CaseRecord*>& cases;  // every case of the run, by "<experiment>/<case>"
  std::string figures_dir;                                 // DIR/figures
  std::string gnuplot;
  const std::vector<ExperimentResult>& results;            // every experiment of the run, in the catalogue's
                                                           // order: those before this one are analysed
  // The case's reduction, or nullptr when it did not run or could not be reduced.
  const postproc::CaseReduction* reduction(const std::string& experiment, const std::string& case_name) const;
  const postproc::CaseReduction* own(const std::string& case_name) const { return reduction(experiment.name, case_name); }
  // An experiment of the run by name (analysed when it comes before this one), or nullptr.
  const ExperimentResult* result(const std::string& experiment) const;
  // A value of an experiment analysed before this one (one it `needs` comes first in the
  // catalogue); none when that experiment or value is missing.
  std::optional<double> earlier(const std::string& experiment, const std::string& value) const;
  // The paper's value of this experiment's claim on `quantity` (its primary reading); NaN when
  // no claim states one.
  double paper(const std::string& quantity) const;
  // The claim of an experiment of the run whose primary reading is `quantity`, or nullptr.
  const Claim* claim_on(const std::string& experiment, const std::string& quantity) const;
};

using Analysis = void (*)(const AnalysisInput&, ExperimentResult&);

// nullptr when the catalogue names an analysis granstack does not have.
Analysis find_analysis(const std::string& name);

namespace analyses {

void fig2(const AnalysisInput& in, ExperimentResult& out);
void fig3(const AnalysisInput& in, ExperimentResult& out);
void scale(const AnalysisInput& in, ExperimentResult& out);
void friction(const AnalysisInput& in, ExperimentResult& out);
void fig4(const AnalysisInput& in, ExperimentResult& out);
void sandwich(const AnalysisInput& in, ExperimentResult& out);
void container(const AnalysisInput& in, ExperimentResult& out);
void eq3(const AnalysisInput& in, ExperimentResult& out);
void eq45(const AnalysisInput& in, ExperimentResult& out);
void rows(const AnalysisInput& in, ExperimentResult& out);
void mechanisms(const AnalysisInput& in, ExperimentResult& out);
// Beyond the paper: Fig. 3's decay when the contacts yield (analyses_plasticity.cpp).
void plasticity(const AnalysisInput& in, ExperimentResult& out);

// The output of the main case of a Teflon experiment (fig4, sandwich) read every way, the
// restitution scan of its Teflon contacts and the material sensitivity runs.
void teflon_outputs(const AnalysisInput& in, ExperimentResult& out, const std::string& main_name);

// A sphere resting on two smaller ones touching both (model::seat_height): the angle of the
// contact normals from the vertical and the mass ratio kappa = m_small / m_large of Eq. (3).
struct Seat {
  double cos_theta = 0.0, kappa = 0.0;
  double eq3() const;  // v_f / v_i of the large sphere
  double eq5() const;  // transmitted amplitude per branch
  double eq4() const;  // the symmetric Y-branch of granular chains at the same angle
};
Seat seat(double upper_radius, double upper_mass, double lower_radius, double lower_mass);

}  // namespace analyses

}  // namespace granstack::study
