#pragma once
// Figures through gnuplot (Debian gnuplot-nox): each writes its data (.dat) and a readable
// gnuplot script (.gp) beside the image, so a user can restyle it and run gnuplot again.
#include <granstack/postproc/table.hpp>

#include <string>

namespace granstack::postproc {

struct PlotOptions {
  std::string format = "png";  // png | svg
  std::string gnuplot = "gnuplot";
};

// Each block's kinetic energy over time, normalised by the top block's peak (the study's
// energy figures), from the case's in-situ series. Returns the image path.
std::string plot_block_energy(const std::string& case_dir, const std::string& out_dir, const PlotOptions& options);

// Output fraction against N_B on a log axis, one series per group with its fitted line.
std::string plot_decay(const OutputTable& table, const std::string& out_dir, const PlotOptions& options);

}  // namespace granstack::postproc
