#pragma once
// The report's figures, re-made in the paper's style, as SVG through gnuplot (postproc's
// render_gnuplot: data and a readable script beside each image).
#include "curves.hpp"

#include <granstack/model/stack.hpp>
#include <granstack/study/reproduce.hpp>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace granstack::study {

// Energy curves of each block (top block first) over a common scale against time, in the
// paper's style: every block in the main panel, and an inset magnifying blocks inset_from..N on
// their own scale with the paper's values dashed across it.
struct EnergyPlot {
  std::string name, title, ylabel, caption;
  std::vector<Curve> curves;  // top block first; each with its own times
  double scale = 1.0;         // the curves are plotted divided by it
  int inset_from = 2;         // block number; no inset where those blocks reach 0.3 of the scale
                              // or more (it would magnify nothing)
  std::vector<std::pair<std::string, double>> references;  // (label, value over scale), dashed in the inset
  // The time axis, s (the main panel's; the inset's starts where the lower blocks move): by
  // default action_window of the curves.
  std::optional<std::pair<double, double>> window;
  // Another run's curves to compare with (title, curve), dashed grey in both panels, divided by
  // `scale` as the blocks' are (the caller scales them to their own run's reference first).
  std::vector<std::pair<std::string, Curve>> compare;
};
Figure energy_plot(const EnergyPlot& p, const std::string& dir, const std::string& gnuplot);

// Where a figure's time axis shows the action: from the first time any curve exceeds
// `start_level` of its own largest value to the last time any exceeds `end_level` of it (a
// plateau of departing spheres is no action), with a margin of 8 % of that stretch either side.
std::pair<double, double> action_window(const std::vector<Curve>& curves, double start_level, double end_level);

// The same for curves that settle at a plateau (a block's energy after the pulse has left): to
// the last time any curve lies further than `tolerance` of its largest value from its final one.
std::pair<double, double> settle_window(const std::vector<Curve>& curves, double start_level, double tolerance);

// A string as gnuplot reads it, in single quotes (a quote inside doubled).
std::string gp_quote(const std::string& text);

// The paper's outputs (N_B, fraction) are drawn as open squares with its exp(-alpha_paper N_B).
Figure decay_figure(const std::map<double, std::vector<std::pair<int, double>>, std::greater<>>& by_e, double alpha,
                    const std::vector<std::pair<int, double>>& paper, double alpha_paper, const std::string& dir,
                    const std::string& gnuplot);

// Output against depth for named series (beyond the paper: elastic and yielding stacks), each with
// its fit A exp(-alpha N_B) (free prefactor) dashed in its colour, on a log axis.
struct DecaySeries {
  std::string title;
  std::vector<std::pair<int, double>> points;  // N_B, E_out / E_in
  double alpha = 0.0, prefactor = 1.0;
};
Figure decay_series_figure(const std::vector<DecaySeries>& series, const std::string& name, const std::string& caption,
                           const std::string& dir, const std::string& gnuplot);

struct BarGroup {
  std::string label;
  std::vector<double> values;  // one per series
};
struct BarStyle {
  std::string name, title, ylabel, caption;
  std::vector<std::pair<std::string, double>> references;  // dashed horizontal lines (the paper's values)
  // Shaded horizontal bands (a claim's acceptance band), each in its reference's colour: [low, high].
  std::vector<std::pair<double, double>> bands;
};
// Clustered bars of fractions, in %: a cluster per group, a bar per series.
Figure bar_figure(const std::vector<BarGroup>& groups, const std::vector<std::string>& series, const BarStyle& style,
                  const std::string& dir, const std::string& gnuplot);

// The output sphere's energy over E_in against time, with the same stack's damped runs beside it
// (their curves over the same E_in), the read-out times marked (the blow's end and the fixed
// time) and the paper's value dashed.
struct OutputFigure {
  double restitution = 1.0;  // the main curve's
  double readout_time = 0.0;  // s
  double paper = 0.0;
  std::vector<std::pair<std::string, Curve>> damped;  // title, curve
};
Figure output_figure(const postproc::CaseReduction& r, const Curve& output, const OutputFigure& f, const std::string& dir,
                     const std::string& name, const std::string& gnuplot, const std::string& caption);

// Outputs against the restitution of the Teflon contacts, one line per series (a figure and a
// read-out), on a log axis, with each figure's acceptance band shaded and the paper's value dashed.
struct ScanSeries {
  std::string title;
  std::map<double, double> by_e;  // e -> E_out / E_in
  int band = 0;                   // index into the bands
};
struct ScanBand {
  std::string label;
  double low = 0.0, high = 0.0, paper = 0.0;
};
Figure scan_figure(const std::vector<ScanSeries>& series, const std::vector<ScanBand>& bands, const std::string& dir,
                   const std::string& gnuplot, const std::string& caption);

// A sphere drawn in a colour of its own: 5 blue, 6 green (the caption says what each marks).
struct DrawingMark {
  int id = 0;
  int colour = 5;
};

// A drawing of the simulated stack (Fig. 1a: the x-z plane) or container (Fig. 1b: every sphere
// projected on the y-z plane), to scale: spheres by material, the striker red, the marked ones in
// their colours.
Figure stack_drawing(const model::Stack& stack, const std::string& dir, const std::string& name, const std::string& gnuplot,
                     const std::string& caption, const std::vector<DrawingMark>& marks = {});

// Stacks side by side (the x-z plane, one panel each, on one scale): each panel the spheres whose
// centres lie in its z window (m; all without one).
struct DrawingPanel {
  std::string title;
  model::Stack stack;
  std::vector<DrawingMark> marks;
  std::optional<std::pair<double, double>> z_window;
};
Figure panels_drawing(const std::vector<DrawingPanel>& panels, const std::string& dir, const std::string& name,
                      const std::string& gnuplot, const std::string& caption);

}  // namespace granstack::study
