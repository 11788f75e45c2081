#pragma once
// The report's figures, re-made in the paper's style, as SVG through gnuplot (postproc's
// render_gnuplot: data and a readable script beside each image).
#include "curves.hpp"

#include <granstack/study/reproduce.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace granstack::study {

// Each block's kinetic energy over the top block's peak against time, with an inset magnifying
// the lower blocks (Fig. 2 and 4); with `impact_column`, the energy of each block's impact
// column instead (over its peak in block 1).
Figure energy_figure(const postproc::CaseReduction& r, const std::string& dir, const std::string& name,
                     const std::string& gnuplot, const std::string& caption, bool impact_column = false);

// Output against N_B on a log axis per e (points), with exp(-(alpha/e) N_B) for one alpha (Fig. 3).
Figure decay_figure(const std::map<double, std::vector<std::pair<int, double>>, std::greater<>>& by_e, double alpha,
                    const std::string& dir, const std::string& gnuplot);

struct BarGroup {
  std::string label;
  std::vector<double> values;  // one per series
};
struct BarStyle {
  std::string name, title, ylabel, caption;
  std::vector<std::pair<std::string, double>> references;  // dashed horizontal lines (the paper's values)
};
// Clustered bars of fractions, in %: a cluster per group, a bar per series.
Figure bar_figure(const std::vector<BarGroup>& groups, const std::vector<std::string>& series, const BarStyle& style,
                  const std::string& dir, const std::string& gnuplot);

// The output sphere's energy over E_in against time, its kicks marked.
Figure output_figure(const postproc::CaseReduction& r, const Curve& output, const std::vector<Kick>& kicks,
                     const std::string& dir, const std::string& name, const std::string& gnuplot, const std::string& caption);

}  // namespace granstack::study
