#pragma once
// Figures through gnuplot (Debian gnuplot-nox): each writes its data (.dat) and a readable
// gnuplot script (.gp) beside the image, so a user can restyle it and run gnuplot again.
#include <granstack/postproc/table.hpp>

#include <string>
#include <vector>

namespace granstack::postproc {

struct PlotOptions {
  std::string format = "png";  // png | svg
  std::string gnuplot = "gnuplot";
};

// gnuplot's `set terminal` line for the options' format (png or svg), in the project's style.
std::string gnuplot_terminal(const PlotOptions& options);
// Writes NAME.dat and NAME.gp into `dir` and runs gnuplot there, from an argument vector (no
// shell sees any path); the script must write NAME.<format>. Returns the image path; throws
// std::runtime_error with gnuplot's own words when it fails.
std::string render_gnuplot(const std::string& dir, const std::string& name, const std::string& data,
                           const std::string& script, const PlotOptions& options);

// The name (without extension) of the energy figure of the case labelled `label`, and the files
// a figure called `name` writes (data, script, image).
std::string energy_plot_name(const std::string& label);
std::vector<std::string> plot_files(const std::string& name, const PlotOptions& options);

// Each block's kinetic energy over time, normalised by the top block's peak (the study's
// energy figures), from the case's in-situ series. `label` names the case in the figure and its
// file name (unique among the cases plotted together). gnuplot starts from an argument vector.
// Returns the image path.
std::string plot_block_energy(const std::string& case_dir, const std::string& label, const std::string& out_dir,
                              const PlotOptions& options);

// A container's panels: each panel's kinetic energy and the matrix's over time, / E_in, on a log
// axis (the leak into the neighbours is orders below the impacted panel), from the reduction's
// panel_frames. Named panels_LABEL. Returns the image path.
std::string panel_plot_name(const std::string& label);
std::string plot_panel_energy(const CaseReduction& reduction, const std::string& label, const std::string& out_dir,
                              const PlotOptions& options);

// Output fraction against N_B on a log axis, one series per group with its fitted line.
std::string plot_decay(const OutputTable& table, const std::string& out_dir, const PlotOptions& options);

}  // namespace granstack::postproc
